#include "render/cli/run_options.h"

#include <CLI/CLI.hpp>

namespace vf::cli {

void addRunOptions(CLI::App& sub, RunOptions& o) {
  sub.add_option("--max-steps", o.maxSteps,
                 "refuse runs needing more steps than this (default 10000000)")
      ->type_name("N")
      ->check(CLI::PositiveNumber);
  sub.add_option("--max-speed", o.maxSpeed,
                 "stop the run when a body moves faster than this, m/s (default 1000)")
      ->type_name("V")
      ->check(CLI::PositiveNumber);
  sub.add_flag("--repair", o.repair,
               "repair every shape's mesh: fill small holes, remove duplicate and degenerate "
               "triangles, fix the winding");
}

void applyRunOptions(SceneSpec& spec, const RunOptions& o) {
  if (o.maxSteps) spec.limits.maxSteps = *o.maxSteps;
  if (o.maxSpeed) spec.limits.maxSpeed = *o.maxSpeed;
  if (o.repair)
    for (ShapeSpec& s : spec.shapes) s.repair = true;
}

}  // namespace vf::cli
