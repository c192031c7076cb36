// samples/view_capture.h — what the replay viewer (`unison view`) shows, captured by re-simulating a recording.
//
// A recording holds the scene, the inputs and one hash per tick; the viewer also needs what the recording does not
// store: each body's placement, the contact points with their impulses, the islands and the solver's work of every
// tick. captureRecording() replays the recording through replay::Session2/Session3 (exactly as `unison verify`
// does) and keeps all of that, as flat arrays ready to be packed into the page (samples/view_page.h).
// Bodies are named by their body numbers (replay/inputs.h): the scene's bodies 0..n-1, then one per create_body.
// Arrays store float32: the viewer draws, it does not simulate.
#pragma once

#include "recording.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace unison::view {

/// Per-tick data of a replayed recording. "frames" = ticks + 1 (frame 0 is the loaded scene).
struct Capture {
    int dimension = 2;
    int ticks = 0;
    double hz = 60.0;
    int bodyCount = 0;                 ///< body numbers 0..bodyCount-1 ever seen
    int poseStride = 3;                ///< floats per pose: 2D x, y, angle; 3D x, y, z, qw, qx, qy, qz
    int contactStride = 6;             ///< floats per contact: 2D point, normal, jn, jt; 3D point, normal, jn, jt (3)
    nlohmann::json bodies;             ///< (bodyCount) {"type", "shapes"} in the body frame (see view_capture.cpp)
    nlohmann::json geometry;           ///< 3D: shared polyhedra and meshes the shapes refer to
    std::vector<float> poses;          ///< (frames x bodyCount x poseStride), NaN where a body does not exist
    std::vector<std::uint16_t> islands;  ///< (frames x bodyCount): smallest body number of its island | 0x8000 when
                                         ///< asleep; 0xFFFF for bodies in no island (static, kinematic, absent)
    std::vector<std::uint32_t> contactStart;     ///< (frames + 1) offsets into the contact arrays
    std::vector<float> contacts;                 ///< (contacts x contactStride)
    std::vector<std::uint16_t> contactBodies;    ///< (contacts x 2) body numbers of a and b (normal points to a)
    std::vector<std::string> hashes;             ///< (frames) state hash after each tick, replayed
    std::vector<std::string> recordedHashes;     ///< (frames) as recorded
    nlohmann::json stats;  ///< per tick arrays: pivots, work, contacts, islands, awake_islands, max_penetration
    double bounds[6] = {0, 0, 0, 0, 0, 0};  ///< min x, y, z, max x, y, z of the moving bodies' origins over the match
};

/// Replays a recording tick by tick and captures what the viewer draws. Throws replay::ReplayError on a bad
/// recording scene or input.
Capture captureRecording(const replay::Recording& rec);

}  // namespace unison::view
