// replay/snapshot_file.cpp — atomic snapshot files and snapshot diffs (see snapshot_file.h).
#include "snapshot_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <fcntl.h>
#include <unistd.h>

namespace unison::replay {

void writeFileAtomic(const std::string& path, const std::vector<std::uint8_t>& bytes) {
    const std::string tmp = path + ".tmp." + std::to_string(::getpid());
    auto fail = [&](const char* what) {
        const std::string why = std::strerror(errno);
        std::remove(tmp.c_str());
        throw ReplayError(path + ": cannot write (" + what + ": " + why + ")");
    };
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) fail("open");
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0) {
            if (errno == EINTR) continue;
            ::close(fd);
            fail("write");
        }
        done += std::size_t(n);
    }
    if (::fsync(fd) != 0) {
        ::close(fd);
        fail("fsync");
    }
    if (::close(fd) != 0) fail("close");
    if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename");
}

std::vector<std::uint8_t> readBinaryFile(const std::string& path) {
    const std::string text = jsonio::readFile(path, policy::kMaxBinaryBytes);  // bounded, like every input
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

namespace {

template <class World>
void restoreInto(World& world, const std::vector<std::uint8_t>& bytes, const std::string& what) {
    std::string error;
    if (!world.restore(bytes.data(), bytes.size(), &error)) throw ReplayError(what + ": " + error);
}

template <class World>
std::vector<FieldDifference> diffAs(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                    const std::string& whatA, const std::string& whatB) {
    World wa, wb;
    restoreInto(wa, a, whatA);
    restoreInto(wb, b, whatB);
    return diffFields(wa.stateFields(), wb.stateFields());
}

/// The container's world kind (bytes [12, 16)); 0 when too short (restore then says why).
std::uint32_t kindOf(const std::vector<std::uint8_t>& bytes) {
    if (bytes.size() < 16) return 0;
    ByteReader r(bytes.data() + 12, 4);
    return r.u32();
}

}  // namespace

void restoreOrThrow(World2& world, const std::vector<std::uint8_t>& bytes, const std::string& what) {
    restoreInto(world, bytes, what);
}

void restoreOrThrow(World3& world, const std::vector<std::uint8_t>& bytes, const std::string& what) {
    restoreInto(world, bytes, what);
}

std::vector<FieldDifference> diffSnapshots(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                                           const std::string& whatA, const std::string& whatB) {
    if (kindOf(a) == std::uint32_t(SnapshotKind::world3)) return diffAs<World3>(a, b, whatA, whatB);
    return diffAs<World2>(a, b, whatA, whatB);
}

nlohmann::json differencesToJson(const std::vector<FieldDifference>& diffs, const char* nameA, const char* nameB,
                                 std::size_t limit) {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t i = 0; i < diffs.size() && i < limit; ++i) {
        const FieldDifference& d = diffs[i];
        out.push_back({{"body", describeBody(d.body)}, {"field", d.path}, {nameA, d.a}, {nameB, d.b}});
    }
    return out;
}

}  // namespace unison::replay
