// The keys each table of a scene file may hold. The loader refuses every other key, and the
// scene reference (docs/scene-format.md) documents exactly these: a test compares the two, so a
// key cannot be added to one without the other.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace vf {

// One table of a scene file, by its dotted path: "" is the top level, "simulation.rest" the
// inline table `rest` of [simulation], "shapes.NAME" every [shapes.X], "camera.path" a key of a
// camera's `path` array, "bodies" every [[bodies]] entry.
struct SceneTableKeys {
  std::string path;
  std::vector<std::string> keys;
};

// Every table of the format, in the order the reference presents them.
const std::vector<SceneTableKeys>& sceneTableKeys();

// The keys of the table at `path`; a path that is not in sceneTableKeys() is a programming
// error (std::logic_error).
const std::vector<std::string>& sceneKeysOf(std::string_view path);

}  // namespace vf
