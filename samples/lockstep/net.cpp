// samples/lockstep/net.cpp — ENet endpoints with simulated delay and loss (see net.h).
#include "net.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <functional>

namespace unison::lockstep {
namespace {

bool initialiseEnet(std::string* error) {
    static const bool ok = [] {
        if (enet_initialize() != 0) return false;
        std::atexit(enet_deinitialize);
        return true;
    }();
    if (!ok && error) *error = "ENet could not be initialised";
    return ok;
}

std::uint64_t splitmix(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

constexpr enet_uint8 kUnreliableChannel = 0, kReliableChannel = 1;

/// Heap order of queued messages: the earliest due first, ties in queueing order.
template <class P>
bool later(const P& a, const P& b) {
    return a.due != b.due ? a.due > b.due : a.order > b.order;
}

}  // namespace

std::unique_ptr<Endpoint> Endpoint::listen(int port, int maxConnections, std::string* error) {
    if (!initialiseEnet(error)) return nullptr;
    ENetAddress address;
    enet_address_set_host_ip(&address, "127.0.0.1");
    address.port = enet_uint16(port);
    std::unique_ptr<Endpoint> e(new Endpoint);
    e->mHost = enet_host_create(&address, std::size_t(maxConnections), 2, 0, 0);
    if (!e->mHost) {
        if (error) *error = "cannot listen on 127.0.0.1:" + std::to_string(port);
        return nullptr;
    }
    e->mStartMs = e->nowMs();
    return e;
}

std::unique_ptr<Endpoint> Endpoint::connect(const std::string& host, int port, int timeoutMs, std::string* error) {
    if (!initialiseEnet(error)) return nullptr;
    std::unique_ptr<Endpoint> e(new Endpoint);
    e->mHost = enet_host_create(nullptr, 1, 2, 0, 0);
    ENetAddress address;
    if (!e->mHost || enet_address_set_host_ip(&address, host.c_str()) != 0) {
        if (error) *error = "cannot create a client for " + host;
        return nullptr;
    }
    address.port = enet_uint16(port);
    ENetPeer* peer = enet_host_connect(e->mHost, &address, 2, 0);
    ENetEvent event;
    if (!peer || enet_host_service(e->mHost, &event, enet_uint32(timeoutMs)) <= 0 || event.type != ENET_EVENT_TYPE_CONNECT) {
        if (error) *error = "no answer from " + host + ":" + std::to_string(port);
        return nullptr;
    }
    peer->data = reinterpret_cast<void*>(std::intptr_t(0));
    e->mLinks.push_back(Link{peer, {}, 0, 0.0, {}});
    e->mStartMs = e->nowMs();
    return e;
}

Endpoint::~Endpoint() {
    if (mHost) enet_host_destroy(mHost);
}

int Endpoint::port() const { return mHost ? int(mHost->address.port) : 0; }

double Endpoint::nowMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count() -
           mStartMs;
}

void Endpoint::setConditions(int connection, const NetConditions& conditions) {
    Link& link = mLinks.at(std::size_t(connection));
    link.conditions = conditions;
    link.rng = conditions.seed;
}

double Endpoint::uniform(Link& link) { return double(splitmix(link.rng) >> 11) * (1.0 / 9007199254740992.0); }

void Endpoint::send(int connection, const std::vector<std::uint8_t>& bytes, bool reliable) {
    if (connection < 0 || std::size_t(connection) >= mLinks.size()) return;
    Link& link = mLinks[std::size_t(connection)];
    if (!link.peer) return;
    const NetConditions& c = link.conditions;
    if (!reliable && c.loss > 0.0 && uniform(link) < c.loss) {
        ++mDropped;
        return;
    }
    double delay = c.latencyMs + (c.jitterMs > 0.0 ? c.jitterMs * (2.0 * uniform(link) - 1.0) : 0.0);
    delay = std::max(0.0, delay);
    double due = nowMs() + delay;
    if (reliable) {
        due = std::max(due, link.lastReliableDue);  // reliable messages keep their order
        link.lastReliableDue = due;
    }
    link.queue.push_back(Pending{due, mOrder++, reliable, bytes});
    std::push_heap(link.queue.begin(), link.queue.end(), [](const Pending& a, const Pending& b) { return later(a, b); });
    sendDue(nowMs(), false);
}

void Endpoint::sendDue(double now, bool all) {
    bool sent = false;
    for (Link& link : mLinks) {
        while (!link.queue.empty() && (all || link.queue.front().due <= now)) {
            std::pop_heap(link.queue.begin(), link.queue.end(),
                          [](const Pending& a, const Pending& b) { return later(a, b); });
            Pending p = std::move(link.queue.back());
            link.queue.pop_back();
            if (!link.peer) continue;
            ENetPacket* packet = enet_packet_create(p.bytes.data(), p.bytes.size(),
                                                    p.reliable ? ENET_PACKET_FLAG_RELIABLE : ENET_PACKET_FLAG_UNSEQUENCED);
            if (enet_peer_send(link.peer, p.reliable ? kReliableChannel : kUnreliableChannel, packet) != 0)
                enet_packet_destroy(packet);
            sent = true;
        }
    }
    if (sent) enet_host_flush(mHost);
}

int Endpoint::linkOf(ENetPeer* peer) const {
    for (std::size_t i = 0; i < mLinks.size(); ++i)
        if (mLinks[i].peer == peer) return int(i);
    return -1;
}

void Endpoint::poll(int timeoutMs, std::vector<NetEvent>& out) {
    double now = nowMs();
    sendDue(now, false);
    // Wake up in time for the next due message.
    double wait = timeoutMs;
    for (const Link& link : mLinks)
        if (!link.queue.empty()) wait = std::min(wait, std::max(0.0, link.queue.front().due - now));
    ENetEvent event;
    int got = enet_host_service(mHost, &event, enet_uint32(wait));
    while (got > 0) {
        switch (event.type) {
            case ENET_EVENT_TYPE_CONNECT: {
                int index = linkOf(event.peer);
                if (index < 0) {
                    index = int(mLinks.size());
                    mLinks.push_back(Link{event.peer, {}, 0, 0.0, {}});
                }
                out.push_back({NetEvent::Type::connected, index, {}});
                break;
            }
            case ENET_EVENT_TYPE_RECEIVE: {
                NetEvent e{NetEvent::Type::received, linkOf(event.peer), {}};
                e.bytes.assign(event.packet->data, event.packet->data + event.packet->dataLength);
                enet_packet_destroy(event.packet);
                out.push_back(std::move(e));
                break;
            }
            case ENET_EVENT_TYPE_DISCONNECT: {
                const int index = linkOf(event.peer);
                if (index >= 0) mLinks[std::size_t(index)].peer = nullptr;
                out.push_back({NetEvent::Type::disconnected, index, {}});
                break;
            }
            case ENET_EVENT_TYPE_NONE: break;
        }
        got = enet_host_check_events(mHost, &event);
    }
    sendDue(nowMs(), false);
}

void Endpoint::flushAll() { sendDue(nowMs(), true); }

void Endpoint::disconnectAll(int timeoutMs) {
    flushAll();
    int live = 0;
    for (Link& link : mLinks) {
        if (link.peer) {
            enet_peer_disconnect_later(link.peer, 0);
            ++live;
        }
    }
    const double end = nowMs() + timeoutMs;
    ENetEvent event;
    while (live > 0 && nowMs() < end) {
        if (enet_host_service(mHost, &event, 10) <= 0) continue;
        if (event.type == ENET_EVENT_TYPE_RECEIVE) enet_packet_destroy(event.packet);
        if (event.type == ENET_EVENT_TYPE_DISCONNECT) {
            const int index = linkOf(event.peer);
            if (index >= 0) mLinks[std::size_t(index)].peer = nullptr;
            --live;
        }
    }
    for (Link& link : mLinks) {
        if (link.peer) enet_peer_reset(link.peer);
        link.peer = nullptr;
    }
}

}  // namespace unison::lockstep
