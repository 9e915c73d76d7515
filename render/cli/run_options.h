// Options shared by `simulate` and `render` that change how a scene is run rather than what it
// holds: --max-steps and --max-speed (the runaway limits of sim/run_guard.h, overriding the
// scene's [simulation] max_steps and max_speed) and --repair (repair = true on every shape,
// sim/geometry/mesh_repair.h).
#pragma once

#include <cstdint>
#include <optional>

#include "sim/scene/scene.h"

namespace CLI {
class App;
}

namespace vf::cli {

struct RunOptions {
  std::optional<std::uint64_t> maxSteps;  // steps a run may need
  std::optional<double> maxSpeed;         // m/s
  bool repair = false;
};

// Registers the options on a subcommand; `o` must outlive the parse.
void addRunOptions(CLI::App& sub, RunOptions& o);
// Copies the given options into the scene.
void applyRunOptions(SceneSpec& spec, const RunOptions& o);

}  // namespace vf::cli
