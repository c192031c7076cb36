// samples/lockstep/net.h — ENet on the loopback address, with simulated network conditions.
//
// Owns: an Endpoint (one ENet host: a listening server with numbered connections, or a client with connection 0
// to its server) and, per connection, the simulated link of its outgoing messages: a one-way delay of
// latency ± jitter (uniform) and, for unreliable messages only, a loss probability. Every draw comes from a
// per-connection generator seeded by NetConditions::seed, so the sequence of delays and drops is the same in
// every run (which packet gets which draw still depends on wall-clock timing).
// Reliable messages go on ENet channel 1 (ordered, resent by ENet, never dropped here; their delays never let
// one overtake another); unreliable ones on channel 0 (unsequenced: jitter may reorder them).
#pragma once

#include <enet/enet.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace unison::lockstep {

/// Simulated conditions of one direction of a link.
struct NetConditions {
    double latencyMs = 0.0;  ///< mean one-way delay (ms)
    double jitterMs = 0.0;   ///< delay varies uniformly in [latency - jitter, latency + jitter], never below 0
    double loss = 0.0;       ///< probability that an unreliable message is dropped, in [0, 1)
    std::uint64_t seed = 1;  ///< seeds the delays and drops
};

/// Something that happened on an endpoint.
struct NetEvent {
    enum class Type { connected, received, disconnected };
    Type type = Type::received;
    int connection = -1;              ///< server: connection index in connect order; client: 0
    std::vector<std::uint8_t> bytes;  ///< received: the message
};

class Endpoint {
public:
    /// A server on 127.0.0.1:port (0: a free port) for up to maxConnections clients; null with *error on failure.
    static std::unique_ptr<Endpoint> listen(int port, int maxConnections, std::string* error);
    /// A client connected to host:port, waiting up to timeoutMs; null with *error on failure.
    static std::unique_ptr<Endpoint> connect(const std::string& host, int port, int timeoutMs, std::string* error);
    ~Endpoint();
    Endpoint(const Endpoint&) = delete;
    Endpoint& operator=(const Endpoint&) = delete;

    /// The local port.
    int port() const;
    /// Conditions of the messages this endpoint sends on `connection`.
    void setConditions(int connection, const NetConditions& conditions);
    /// Queues a message on a connection (see the top of this file for reliable and unreliable).
    void send(int connection, const std::vector<std::uint8_t>& bytes, bool reliable);
    /// Hands due messages to ENet, waits up to timeoutMs for traffic and appends what happened to `out`.
    void poll(int timeoutMs, std::vector<NetEvent>& out);
    /// Sends every queued message now (ignoring the remaining delays) and flushes ENet.
    void flushAll();
    /// Unreliable messages dropped by the simulated loss so far.
    int dropped() const { return mDropped; }
    /// Disconnects every connection gracefully (waits up to timeoutMs for the acknowledgements).
    void disconnectAll(int timeoutMs);

private:
    struct Pending {
        double due;               // ms on the endpoint's clock
        std::uint64_t order;      // ties keep queueing order
        bool reliable;
        std::vector<std::uint8_t> bytes;
    };
    struct Link {
        ENetPeer* peer = nullptr;
        NetConditions conditions;
        std::uint64_t rng = 0;
        double lastReliableDue = 0.0;
        std::vector<Pending> queue;  // min-heap by (due, order)
    };
    Endpoint() = default;
    double nowMs() const;
    void sendDue(double now, bool all);
    int linkOf(ENetPeer* peer) const;
    double uniform(Link& link);  // [0, 1)

    ENetHost* mHost = nullptr;
    std::vector<Link> mLinks;
    std::uint64_t mOrder = 0;
    int mDropped = 0;
    double mStartMs = 0.0;
};

}  // namespace unison::lockstep
