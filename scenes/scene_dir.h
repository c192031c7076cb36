// scenes/scene_dir.h — where the shared example scenes (scenes/*.json) are: the source tree the tests, benchmarks
// and samples were built from. Part of the fixtures library, not of the installed one.
#pragma once

#include <string>

namespace unison::scenes {

/// Folder of the shared example scenes (scenes/*.json in the source tree).
std::string sceneDir();

}  // namespace unison::scenes
