// samples/view_page.h — the replay viewer's page: one self-contained HTML file (inline script, style and data; no
// network access, nothing fetched) that plays a captured recording (samples/view_capture.h).
//
// Data layout in the page: <script type="application/json" id="meta"> holds the settings, body shapes, hashes,
// per-tick statistics and the desync report; each large array is a <script type="application/octet-stream"
// id="b-NAME"> holding base64 of the zlib-deflated array whose bytes were grouped by significance first (all
// first bytes of the elements, then all second bytes, ...: float data then deflates about twice as well). The page
// undoes it with the browser's own DecompressionStream. The viewer itself is samples/viewer/viewer.html.
#pragma once

#include "view_capture.h"

#include <nlohmann/json.hpp>

#include <string>

namespace unison::view {

/// The viewer page for a capture; `report` is a desync report (`unison verify --report`, `lockstep --report`) or
/// null; `title` names the recording.
std::string renderPage(const Capture& capture, const nlohmann::json& report, const std::string& title);

/// The viewer's HTML template (generated from samples/viewer/viewer.html at build time).
const char* viewerTemplate();

}  // namespace unison::view
