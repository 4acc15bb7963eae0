#pragma once
// The scene that runs when none is given: scenes/default.toml, built into the program so it
// needs nothing outside the repository.
#include "scene/scene.h"

namespace pbdsplat::scene {

const char* default_scene_text();
Scene default_scene();

} // namespace pbdsplat::scene
