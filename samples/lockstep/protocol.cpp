// samples/lockstep/protocol.cpp — message encoding and decoding (see protocol.h).
#include "protocol.h"

#include "state_io.h"

namespace unison::lockstep {
namespace {

ByteWriter begin(MessageType type) {
    ByteWriter w;
    w.u8(std::uint8_t(type));
    return w;
}

void writeRun(ByteWriter& w, const InputRun& run) {
    w.u32(std::uint32_t(run.player));
    w.u32(std::uint32_t(run.first));
    w.u32(std::uint32_t(run.inputs.size()));
    for (const PlayerInput& in : run.inputs) {
        w.u8(std::uint8_t(in.dx));
        w.u8(std::uint8_t(in.dy));
    }
}

InputRun readRun(ByteReader& r) {
    InputRun run;
    run.player = int(r.u32());
    run.first = int(r.u32());
    const std::uint32_t n = r.u32();
    if (n > r.remaining() / 2) {
        r.fail("input run longer than the message");
        return run;
    }
    run.inputs.resize(n);
    for (PlayerInput& in : run.inputs) {
        in.dx = std::int8_t(r.u8());
        in.dy = std::int8_t(r.u8());
    }
    return run;
}

void writeStats(ByteWriter& w, const SessionStats& s) {
    for (int v : {s.rollbacks, s.resimulatedTicks, s.maxRollback, s.predictedTicks, s.mispredictions, s.steps, s.saves,
                  s.restores})
        w.i32(v);
    for (double v : {s.stepUs, s.saveUs, s.restoreUs}) w.f64(v);
    w.u64(s.maxStateBytes);
}

SessionStats readStats(ByteReader& r) {
    SessionStats s;
    for (int* v : {&s.rollbacks, &s.resimulatedTicks, &s.maxRollback, &s.predictedTicks, &s.mispredictions, &s.steps,
                   &s.saves, &s.restores})
        *v = r.i32();
    for (double* v : {&s.stepUs, &s.saveUs, &s.restoreUs}) *v = r.f64();
    s.maxStateBytes = std::size_t(r.u64());
    return s;
}

}  // namespace

std::vector<std::uint8_t> encodeHello(int wantedPlayer) {
    ByteWriter w = begin(MessageType::hello);
    w.u32(kProtocolVersion);
    w.i32(wantedPlayer);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeWelcome(const Welcome& m) {
    ByteWriter w = begin(MessageType::welcome);
    w.i32(m.match.players);
    w.i32(m.match.rows);
    w.u64(m.match.seed);
    w.u8(m.match.sleep ? 1 : 0);
    const SessionConfig& s = m.session;
    for (int v : {s.localPlayer, s.ticks, s.inputDelay, s.maxPrediction, s.checkEvery, s.desyncAt}) w.i32(v);
    w.f64(m.net.latencyMs);
    w.f64(m.net.jitterMs);
    w.f64(m.net.loss);
    w.u64(m.net.seed);
    w.u8(m.realtime ? 1 : 0);
    w.f64(m.hz);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeSimple(MessageType type) { return std::move(begin(type).data()); }

std::vector<std::uint8_t> encodeInputs(const std::vector<int>& acks, const InputRun& run) {
    ByteWriter w = begin(MessageType::inputs);
    w.u32(std::uint32_t(acks.size()));
    for (int a : acks) w.i32(a);
    writeRun(w, run);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeRelay(int ack, const std::vector<InputRun>& runs) {
    ByteWriter w = begin(MessageType::relay);
    w.i32(ack);
    w.u32(std::uint32_t(runs.size()));
    for (const InputRun& run : runs) writeRun(w, run);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeTick(MessageType type, int tick) {
    ByteWriter w = begin(type);
    w.i32(tick);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeHash(int tick, std::uint64_t hash, std::uint64_t window) {
    ByteWriter w = begin(MessageType::hash);
    w.i32(tick);
    w.u64(hash);
    w.u64(window);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeQueryHashes(int from, int to) {
    ByteWriter w = begin(MessageType::queryHashes);
    w.i32(from);
    w.i32(to);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeHashes(int from, const std::vector<std::uint64_t>& hashes) {
    ByteWriter w = begin(MessageType::hashes);
    w.i32(from);
    w.u32(std::uint32_t(hashes.size()));
    for (std::uint64_t h : hashes) w.u64(h);
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeSnapshot(int tick, const std::vector<std::uint8_t>& bytes) {
    ByteWriter w = begin(MessageType::snapshot);
    w.i32(tick);
    w.u64(bytes.size());
    w.bytes(bytes.data(), bytes.size());
    return std::move(w.data());
}

std::vector<std::uint8_t> encodeDone(const PeerDone& d) {
    ByteWriter w = begin(MessageType::done);
    w.i32(d.tick);
    w.u64(d.finalHash);
    writeStats(w, d.stats);
    w.i32(d.dropped);
    w.f64(d.stalledMs);
    return std::move(w.data());
}

bool decodeMessage(const std::vector<std::uint8_t>& bytes, Message* out, std::string* error) {
    ByteReader r(bytes.data(), bytes.size());
    Message m;
    const std::uint8_t type = r.u8();
    if (type < std::uint8_t(MessageType::hello) || type > std::uint8_t(MessageType::stop)) {
        if (error) *error = "unknown message type " + std::to_string(type);
        return false;
    }
    m.type = MessageType(type);
    switch (m.type) {
        case MessageType::hello:
            m.version = r.u32();
            m.wantedPlayer = r.i32();
            break;
        case MessageType::welcome: {
            Welcome& w = m.welcome;
            w.match.players = r.i32();
            w.match.rows = r.i32();
            w.match.seed = r.u64();
            w.match.sleep = r.u8() != 0;
            SessionConfig& s = w.session;
            for (int* v : {&s.localPlayer, &s.ticks, &s.inputDelay, &s.maxPrediction, &s.checkEvery, &s.desyncAt})
                *v = r.i32();
            w.net.latencyMs = r.f64();
            w.net.jitterMs = r.f64();
            w.net.loss = r.f64();
            w.net.seed = r.u64();
            w.realtime = r.u8() != 0;
            w.hz = r.f64();
            break;
        }
        case MessageType::start:
        case MessageType::stop: break;
        case MessageType::inputs: {
            const std::uint32_t n = r.u32();
            if (n > r.remaining() / 4) r.fail("acknowledgement count larger than the message");
            for (std::uint32_t i = 0; i < n && r.ok(); ++i) m.acks.push_back(r.i32());
            m.runs.push_back(readRun(r));
            break;
        }
        case MessageType::relay: {
            m.ack = r.i32();
            const std::uint32_t n = r.u32();
            if (n > r.remaining() / 12) r.fail("run count larger than the message");
            for (std::uint32_t i = 0; i < n && r.ok(); ++i) m.runs.push_back(readRun(r));
            break;
        }
        case MessageType::hash:
            m.tick = r.i32();
            m.hash = r.u64();
            m.window = r.u64();
            break;
        case MessageType::checkOk:
        case MessageType::querySnapshot: m.tick = r.i32(); break;
        case MessageType::queryHashes:
            m.from = r.i32();
            m.to = r.i32();
            break;
        case MessageType::hashes: {
            m.from = r.i32();
            const std::uint32_t n = r.u32();
            if (n > r.remaining() / 8) r.fail("hash count larger than the message");
            for (std::uint32_t i = 0; i < n && r.ok(); ++i) m.hashList.push_back(r.u64());
            break;
        }
        case MessageType::snapshot: {
            m.tick = r.i32();
            const std::size_t n = r.count(1, "snapshot byte");
            m.bytes.resize(n);
            for (std::size_t i = 0; i < n && r.ok(); ++i) m.bytes[i] = r.u8();
            break;
        }
        case MessageType::done:
            m.done.tick = r.i32();
            m.done.finalHash = r.u64();
            m.done.stats = readStats(r);
            m.done.dropped = r.i32();
            m.done.stalledMs = r.f64();
            break;
    }
    if (r.ok() && !r.atEnd()) r.fail("unexpected bytes at the end");
    if (!r.ok()) {
        if (error) *error = "malformed message: " + r.error();
        return false;
    }
    *out = std::move(m);
    return true;
}

}  // namespace unison::lockstep
