// A simulation run as a library call: what `voxfall simulate` does, for the command and for any
// program or test that wants it without argv. The scene is stepped through its output frames
// without drawing; the outputs asked for are written (each through render/output/output_file.h)
// and the run summary and checksum printed to stdout.
//
// Order matters for the user: cheap checks first (scene file, then output paths), the expensive
// shape building and stepping last, so a typo never costs a long run. A run stops as
// render/run/stop_policy.h says: stopped after whole frames, the CSV, bake and other outputs
// hold those frames and the summary says it was interrupted.
#pragma once

#include <string>

#include "render/run/stop_policy.h"
#include "sim/scene/scene.h"

namespace vf {

struct SimulateRequest {
  std::string scene;            // the scene file (TOML)
  std::string csv;              // "": no per-frame CSV
  std::string summary;          // "": no summary JSON
  std::string bake;             // "": no bake
  std::string outcomes;         // "": no per-rock outcomes (CSV, or GeoJSON by its extension)
  std::string lines;            // "": no evaluation-line files (a folder)
  std::string barriers;         // "": no per-barrier CSV
  SceneOverrides overrides;     // level, step, collider, run limits, repair, threads
  bool quiet = false;           // no progress line
  bool overwrite = false;       // -y
  bool neverOverwrite = false;  // -n
};

// Runs the scene and writes the outputs. Bad input (scene, paths, an output the scene cannot
// have) and a run stopped by the run guard throw InputError, after the guard's whole frames are
// kept in the CSV and bake.
RunStatus runSimulation(const SimulateRequest& request);

}  // namespace vf
