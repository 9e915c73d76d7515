#include "sim/scene/scene_keys.h"

#include <stdexcept>

namespace vf {

const std::vector<SceneTableKeys>& sceneTableKeys() {
  static const std::vector<SceneTableKeys> tables = {
      {"",
       {"simulation", "contact", "ground", "shapes", "bodies", "emitters", "camera", "cameras",
        "light", "output", "ensemble", "evaluation_lines", "barriers", "forest"}},
      {"simulation",
       {"duration", "level", "step", "gravity", "fps", "collider", "method", "contact_reduction",
        "sleep", "stop", "rest", "rotation", "max_steps", "max_speed"}},
      {"simulation.rest", {"speed", "time"}},
      {"contact", {"restitution", "friction"}},
      {"contact.restitution", {"body_body", "body_ground"}},
      {"contact.friction", {"body_body", "body_ground"}},
      {"ground",
       {"plane", "heightfield", "offset", "crs", "texture", "material", "materials", "classes",
        "class_materials", "edge", "variability", "variability_seed"}},
      {"forest",
       {"density", "dbh", "trees", "trees_dbh_field", "species", "species_factors", "stem_height",
        "seed"}},
      {"ground.materials.NAME",
       {"law", "restitution", "friction", "rolling_resistance", "tangential_restitution", "mu_min",
        "mu_max", "kappa", "beta", "scar"}},
      {"ground.materials.NAME.scar", {"density", "fluid_drag", "compaction_drag", "modulus"}},
      {"shapes.NAME",
       {"mesh", "rock", "scale", "density", "mass", "up", "level", "color", "repair", "smooth"}},
      {"shapes.NAME.rock", {"class", "seed", "seeds", "size", "volume"}},
      {"bodies",
       {"shape", "position", "orientation", "velocity", "angular_velocity", "static", "drop_height",
        "color"}},
      {"emitters",
       {"shape", "count", "start", "interval", "position", "positions", "velocity",
        "angular_velocity", "orientation", "color", "jitter", "drop_height", "clear_release"}},
      {"emitters.jitter", {"position", "direction", "orientation", "seed"}},
      {"camera",
       {"position", "look_at", "up", "fov", "follow", "smoothing", "path", "min_pixels", "trail"}},
      {"camera.path", {"time", "position", "look_at", "fov"}},
      {"cameras.NAME",
       {"position", "look_at", "up", "fov", "follow", "smoothing", "path", "min_pixels", "trail"}},
      {"cameras.NAME.path", {"time", "position", "look_at", "fov"}},
      {"light", {"azimuth", "elevation", "date", "time", "intensity", "color", "sky", "ambient"}},
      {"output", {"width", "height", "crf", "speed", "alpha", "overlay"}},
      {"ensemble",
       {"seed", "shape", "shapes", "weights", "release", "drop_height", "orientation", "velocity",
        "angular_velocity", "restitution", "friction", "rolling_resistance", "volume", "density",
        "height_classes"}},
      {"ensemble.velocity", {"min", "max"}},
      {"ensemble.angular_velocity", {"min", "max"}},
      {"ensemble.release",
       {"area", "line", "points", "cells", "file", "layer", "weight_field", "weight", "volume"}},
      {"ensemble.volume", {"distribution", "median", "sigma", "exponent", "min", "max"}},
      {"evaluation_lines", {"name", "points", "file", "layer"}},
      {"barriers",
       {"name", "points", "file", "layer", "height", "capacity", "thickness", "height_field",
        "capacity_field"}},
  };
  return tables;
}

const std::vector<std::string>& sceneKeysOf(std::string_view path) {
  for (const SceneTableKeys& t : sceneTableKeys())
    if (t.path == path) return t.keys;
  throw std::logic_error("no scene table '" + std::string(path) + "'");
}

}  // namespace vf
