// samples/view_page.cpp — packs a capture into the viewer page (see view_page.h).
#include "view_page.h"

#include <zlib.h>

#include <cstring>
#include <stdexcept>

namespace unison::view {
namespace {

using nlohmann::json;

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* const kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(bytes[i]) << 16 | unsigned(bytes[i + 1]) << 8 | bytes[i + 2];
        for (int k = 3; k >= 0; --k) out.push_back(kDigits[(v >> (6 * k)) & 63u]);
    }
    if (i < bytes.size()) {
        const bool two = i + 1 < bytes.size();
        const unsigned v = unsigned(bytes[i]) << 16 | (two ? unsigned(bytes[i + 1]) << 8 : 0u);
        out.push_back(kDigits[(v >> 18) & 63u]);
        out.push_back(kDigits[(v >> 12) & 63u]);
        out.push_back(two ? kDigits[(v >> 6) & 63u] : '=');
        out.push_back('=');
    }
    return out;
}

/// Groups the bytes of `count` elements of `size` bytes by significance, then deflates (zlib format).
std::vector<unsigned char> pack(const void* data, std::size_t count, std::size_t size) {
    const auto* in = static_cast<const unsigned char*>(data);
    std::vector<unsigned char> grouped(count * size);
    for (std::size_t b = 0; b < size; ++b)
        for (std::size_t i = 0; i < count; ++i) grouped[b * count + i] = in[i * size + b];
    uLongf length = compressBound(uLong(grouped.size()));
    std::vector<unsigned char> out(length);
    if (compress2(out.data(), &length, grouped.data(), uLong(grouped.size()), 6) != Z_OK)
        throw std::runtime_error("view: compression failed");
    out.resize(length);
    return out;
}

/// JSON for a <script> element: "</" cannot appear inside it ("<\/" is the same JSON string).
std::string scriptSafe(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        out.push_back(text[i]);
        if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out.push_back('\\');
    }
    return out;
}

template <class T>
void addBlob(json& specs, std::string& html, const char* name, const char* type, const std::vector<T>& values) {
    const std::vector<unsigned char> packed = pack(values.data(), values.size(), sizeof(T));
    specs[name] = {{"type", type}, {"count", values.size()}, {"element", sizeof(T)}, {"packed_bytes", packed.size()}};
    html += "<script type=\"application/octet-stream\" id=\"b-";
    html += name;
    html += "\">";
    html += base64(packed);
    html += "</script>\n";
}

}  // namespace

std::string renderPage(const Capture& cap, const json& report, const std::string& title) {
    std::string blobs;
    json specs = json::object();
    addBlob(specs, blobs, "poses", "f32", cap.poses);
    addBlob(specs, blobs, "islands", "u16", cap.islands);
    addBlob(specs, blobs, "contact_start", "u32", cap.contactStart);
    addBlob(specs, blobs, "contacts", "f32", cap.contacts);
    addBlob(specs, blobs, "contact_bodies", "u16", cap.contactBodies);
    const json meta = {{"title", title},
                       {"dimension", cap.dimension},
                       {"ticks", cap.ticks},
                       {"hz", cap.hz},
                       {"body_count", cap.bodyCount},
                       {"pose_stride", cap.poseStride},
                       {"contact_stride", cap.contactStride},
                       {"bodies", cap.bodies},
                       {"geometry", cap.geometry},
                       {"hashes", cap.hashes},
                       {"recorded_hashes", cap.recordedHashes},
                       {"stats", cap.stats},
                       {"bounds", std::vector<double>(cap.bounds, cap.bounds + 6)},
                       {"report", report},
                       {"blobs", specs}};
    const std::string data = "<script type=\"application/json\" id=\"meta\">" + scriptSafe(meta.dump()) + "</script>\n" + blobs;
    std::string page = viewerTemplate();
    const std::string marker = "<!--UNISON-DATA-->";
    const std::size_t at = page.find(marker);
    if (at == std::string::npos) throw std::runtime_error("view: the page template has no data marker");
    page.replace(at, marker.size(), data);
    return page;
}

}  // namespace unison::view
