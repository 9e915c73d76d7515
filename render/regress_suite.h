// A golden-frame suite: SUITE_DIR/suite.toml lists cases (a scene, the frames to check, a
// size, optionally a tolerance). Read by toml++, the project's TOML library; `voxfall regress`
// and the golden tests read suites through this one reader.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "render/output/image_diff.h"

namespace vf {

struct SuiteCase {
  std::string name;          // folder of its goldens; default: the scene file's stem
  std::string scene;         // resolved against the suite folder
  std::vector<int> frames;   // frame numbers k (t = k / fps), in the order given
  std::optional<int> width;  // default: the scene's [output] size
  std::optional<int> height;
  // An ensemble scene's first `runs` realisations drawn together, as `voxfall ensemble
  // --video-runs K` draws them (ensemble_subset.bake); unset: the scene as `render` draws it.
  std::optional<int> runs;
  DiffTolerance tolerance;
  PixelMask mask;         // rectangles every comparison of this case leaves out
  std::string maskWhere;  // "suite.toml:LINE:COLUMN" of `mask`, for a rectangle off the frame
  std::string where;      // "suite.toml:LINE" of its [[case]] header
};

struct Suite {
  std::string dir;
  std::vector<SuiteCase> cases;
};

// Reads a suite file. Keys: top-level `threshold`, `max_fraction` and `min_ssim` (defaults for
// every case), then [[case]] tables with `scene`, `frames`, and optional `name`, `size`, `runs`,
// `threshold`, `max_fraction`, `min_ssim`, `mask`. Errors: InputError at
// "suite.toml:LINE:COLUMN".
Suite readSuite(const std::string& suiteFile);

}  // namespace vf
