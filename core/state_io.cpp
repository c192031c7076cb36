// core/state_io.cpp — checksum, build flags and the snapshot container (see state_io.h).
#include "state_io.h"

#include <xxhash.h>

#include <cfloat>
#include <cmath>
#include <cstdio>
#include <map>
#include <tuple>

namespace unison {

namespace {
constexpr std::uint8_t kMagic[8] = {'U', 'N', 'I', 'S', 'N', 'A', 'P', 0};
}

std::uint64_t hash64(const std::uint8_t* data, std::size_t size) { return XXH3_64bits(data, size); }

std::uint64_t resultAffectingBuildFlags() {
    std::uint64_t flags = 0;
#if defined(__FAST_MATH__)
    flags |= 1u;
#endif
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
    flags |= 2u;
#endif
#if !defined(EIGEN_DONT_VECTORIZE)
    flags |= 4u;
#endif
    return flags;
}

std::vector<std::uint8_t> frameSnapshot(SnapshotKind kind, std::uint64_t bodyCount, const std::vector<std::uint8_t>& payload) {
    ByteWriter w;
    w.bytes(kMagic, sizeof kMagic);
    w.u32(kSnapshotFormatVersion);
    w.u32(std::uint32_t(kind));
    w.u64(resultAffectingBuildFlags());
    w.u64(bodyCount);
    w.u64(payload.size());
    w.bytes(payload.data(), payload.size());
    w.u64(hash64(w.data().data(), w.data().size()));
    return std::move(w.data());
}

bool unframeSnapshot(const std::uint8_t* data, std::size_t size, SnapshotKind kind, SnapshotView* out, std::string* error) {
    auto fail = [&](const std::string& why) {
        if (error) *error = "snapshot rejected: " + why;
        return false;
    };
    if (data == nullptr || size < kSnapshotHeaderSize + 8) return fail("truncated (" + std::to_string(size) + " bytes, shorter than a header)");
    if (std::memcmp(data, kMagic, sizeof kMagic) != 0) return fail("not a Unison snapshot (bad magic)");
    ByteReader r(data + 8, size - 8);
    const std::uint32_t version = r.u32();
    const std::uint32_t k = r.u32();
    const std::uint64_t flags = r.u64();
    const std::uint64_t bodies = r.u64();
    const std::uint64_t payloadSize = r.u64();
    if (version != kSnapshotFormatVersion)
        return fail("format version " + std::to_string(version) + ", this build reads version " + std::to_string(kSnapshotFormatVersion));
    if (k != std::uint32_t(kind))
        return fail("holds a world of kind " + std::to_string(k) + ", expected " + std::to_string(std::uint32_t(kind)));
    if (flags != resultAffectingBuildFlags())
        return fail("written by a build with result-affecting flags " + std::to_string(flags) + ", this build has " +
                    std::to_string(resultAffectingBuildFlags()));
    if (payloadSize != size - kSnapshotHeaderSize - 8)
        return fail("truncated or padded: header announces " + std::to_string(payloadSize) + " payload bytes, file holds " +
                    std::to_string(size - kSnapshotHeaderSize - 8));
    ByteReader tail(data + size - 8, 8);
    if (tail.u64() != hash64(data, size - 8)) return fail("checksum mismatch (corrupt data)");
    out->bodyCount = bodies;
    out->payload = data + kSnapshotHeaderSize;
    out->payloadSize = std::size_t(payloadSize);
    return true;
}

std::string StateField::text() const {
    if (!real) return std::to_string(bits);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string describeBody(BodyId id) {
    if (id.isNull()) return "world";
    return "body " + std::to_string(id.index1) + ":" + std::to_string(id.generation);
}

std::string firstNonFinite(const std::vector<StateField>& fields) {
    for (const StateField& f : fields) {
        if (!f.real) continue;
        double v;
        std::memcpy(&v, &f.bits, sizeof v);
        if (!std::isfinite(v)) return describeBody(f.body) + " " + f.path + " is " + f.text() + " (overflow)";
    }
    return {};
}

std::vector<FieldDifference> diffFields(const std::vector<StateField>& a, const std::vector<StateField>& b) {
    using Key = std::tuple<std::uint32_t, std::uint32_t, std::string>;
    auto key = [](const StateField& f) { return Key{f.body.index1, f.body.generation, f.path}; };
    std::map<Key, const StateField*> inB;
    for (const StateField& f : b) inB.emplace(key(f), &f);
    std::vector<FieldDifference> out;
    for (const StateField& f : a) {
        const auto it = inB.find(key(f));
        if (it == inB.end()) {
            out.push_back({f.body, f.path, f.text(), "absent"});
            continue;
        }
        if (it->second->bits != f.bits || it->second->real != f.real) out.push_back({f.body, f.path, f.text(), it->second->text()});
        inB.erase(it);
    }
    for (const StateField& f : b) {
        if (inB.count(key(f))) out.push_back({f.body, f.path, "absent", f.text()});
    }
    return out;
}

}  // namespace unison
