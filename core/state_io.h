// core/state_io.h — the byte layer of state hashes, snapshots and recordings: explicit little-endian writing and
// bounds-checked reading of fixed-width fields, the 64-bit checksum, and the framed container every snapshot file
// uses (magic, format version, world kind, result-affecting build flags, body count, payload, checksum).
//
// Why by hand: a hash or a file must hold the same bytes on every machine, so each field is written as its own
// little-endian integer (doubles as their IEEE bit pattern). Structs are never copied as bytes (padding, byte order).
// Invariants: ByteReader never reads past its end; after the first failure every read returns 0 and ok() stays false.
#pragma once

#include "body_store.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace unison {

/// Appends fixed-width little-endian fields to a growing byte buffer.
class ByteWriter {
public:
    void u8(std::uint8_t v) { mBytes.push_back(v); }
    void u16(std::uint16_t v) { put(v, 2); }
    void u32(std::uint32_t v) { put(v, 4); }
    void u64(std::uint64_t v) { put(v, 8); }
    void i32(std::int32_t v) { put(std::uint32_t(v), 4); }
    /// A double as its IEEE-754 bit pattern (so -0.0, NaN payloads and every last bit survive).
    void f64(double v) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, sizeof bits);
        put(bits, 8);
    }
    void bytes(const std::uint8_t* data, std::size_t size) { mBytes.insert(mBytes.end(), data, data + size); }
    /// A length-prefixed (u64) byte string.
    void blob(const std::string& s) {
        u64(s.size());
        bytes(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
    }
    std::vector<std::uint8_t>& data() { return mBytes; }
    const std::vector<std::uint8_t>& data() const { return mBytes; }

private:
    void put(std::uint64_t v, int n) {
        for (int i = 0; i < n; ++i) mBytes.push_back(std::uint8_t(v >> (8 * i)));
    }
    std::vector<std::uint8_t> mBytes;
};

/// Reads what ByteWriter wrote, never past the end; the first failure is remembered with its offset.
class ByteReader {
public:
    ByteReader(const std::uint8_t* data, std::size_t size) : mData(data), mSize(size) {}

    std::uint8_t u8() { return std::uint8_t(get(1)); }
    std::uint16_t u16() { return std::uint16_t(get(2)); }
    std::uint32_t u32() { return std::uint32_t(get(4)); }
    std::uint64_t u64() { return get(8); }
    std::int32_t i32() { return std::int32_t(std::uint32_t(get(4))); }
    double f64() {
        const std::uint64_t bits = get(8);
        double v;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    /// A count that must fit in what is left, at `minBytesEach` bytes per element (guards huge allocations).
    std::size_t count(std::size_t minBytesEach, const char* what) {
        const std::uint64_t n = u64();
        if (ok() && minBytesEach > 0 && n > remaining() / minBytesEach)
            fail("truncated data: " + std::string(what) + " count " + std::to_string(n) + " exceeds the bytes left");
        return ok() ? std::size_t(n) : 0;
    }
    /// A length-prefixed byte string (see ByteWriter::blob).
    std::string blob(const char* what) {
        const std::size_t n = count(1, what);
        if (!ok()) return {};
        std::string s(reinterpret_cast<const char*>(mData + mPos), n);
        mPos += n;
        return s;
    }
    /// Marks the data invalid with a reason (kept only for the first failure).
    void fail(const std::string& why) {
        if (mError.empty()) mError = why + " (at byte " + std::to_string(mPos) + ")";
        mPos = mSize;
    }
    bool ok() const { return mError.empty(); }
    const std::string& error() const { return mError; }
    std::size_t position() const { return mPos; }
    std::size_t remaining() const { return mSize - mPos; }
    bool atEnd() const { return mPos == mSize; }

private:
    std::uint64_t get(int n) {
        if (!ok()) return 0;
        if (remaining() < std::size_t(n)) {
            fail("truncated data");
            return 0;
        }
        std::uint64_t v = 0;
        for (int i = 0; i < n; ++i) v |= std::uint64_t(mData[mPos + std::size_t(i)]) << (8 * i);
        mPos += std::size_t(n);
        return v;
    }
    const std::uint8_t* mData;
    std::size_t mSize;
    std::size_t mPos = 0;
    std::string mError;
};

/// 64-bit XXH3 of a byte range (the state hash and every checksum).
std::uint64_t hash64(const std::uint8_t* data, std::size_t size);

/// Result-affecting build flags of this build, a bit set that must be 0 in a deterministic build: bit 0 fast-math,
/// bit 1 FLT_EVAL_METHOD != 0 (excess precision), bit 2 Eigen vectorisation on. Snapshots record it and a snapshot
/// from a build with other flags is rejected (its continuation would not be bit-identical).
std::uint64_t resultAffectingBuildFlags();

/// What kind of object a framed snapshot holds.
enum class SnapshotKind : std::uint32_t { world2 = 2, world3 = 3 };

/// The snapshot container, all little-endian:
///   [0, 8)   magic "UNISNAP\0"
///   [8, 12)  u32 format version (kSnapshotFormatVersion)
///   [12, 16) u32 SnapshotKind
///   [16, 24) u64 build flags (resultAffectingBuildFlags())
///   [24, 32) u64 body count
///   [32, 40) u64 payload size P
///   [40, 40 + P) payload
///   then     u64 XXH3 of every byte before it.
constexpr std::uint32_t kSnapshotFormatVersion = 4;
constexpr std::size_t kSnapshotHeaderSize = 40;

/// Wraps a payload in the container above.
std::vector<std::uint8_t> frameSnapshot(SnapshotKind kind, std::uint64_t bodyCount, const std::vector<std::uint8_t>& payload);

/// Checks a container (size, magic, version, kind, flags, checksum) and returns where its payload lies. On failure
/// returns false with a clear reason in *error.
struct SnapshotView {
    std::uint64_t bodyCount = 0;
    const std::uint8_t* payload = nullptr;
    std::size_t payloadSize = 0;
};
bool unframeSnapshot(const std::uint8_t* data, std::size_t size, SnapshotKind kind, SnapshotView* out, std::string* error);

/// One named field of a canonical state, for snapshot diffs and desync reports (World2/World3::stateFields()).
struct StateField {
    BodyId body;             ///< the body the field belongs to; null for world-level fields
    std::string path;        ///< e.g. "velocity.x" (of `body`), "def.gravity.y", "cache[12].basicMask"
    bool real = false;       ///< true: `bits` are an IEEE double; false: an integer
    std::uint64_t bits = 0;  ///< the value
    /// The value as text: a double with 17 significant digits, or the integer.
    std::string text() const;
};

/// A field whose value differs between two states (or exists in only one of them: its text there is "absent").
struct FieldDifference {
    BodyId body;
    std::string path;
    std::string a, b;  ///< the value in each state
};

/// The fields of a and b that differ, matched by (body, path), in the order of a, then those only in b.
std::vector<FieldDifference> diffFields(const std::vector<StateField>& a, const std::vector<StateField>& b);

/// The first real field that is not finite, as "body 3:1 velocity.x is inf", or empty when there is none.
std::string firstNonFinite(const std::vector<StateField>& fields);

/// "body 3:1" (slot index + 1 and generation) or "world" for the null id.
std::string describeBody(BodyId id);

}  // namespace unison
