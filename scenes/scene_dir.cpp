// scenes/scene_dir.cpp — see scene_dir.h.
#include "scene_dir.h"

namespace unison::scenes {

std::string sceneDir() { return UNISON_SCENE_DIR; }

}  // namespace unison::scenes
