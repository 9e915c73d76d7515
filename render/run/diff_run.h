// A comparison of images as a library call: what `voxfall diff EXPECTED ACTUAL` does. Two PNGs,
// or two folders of PNG frames matched by file name, compared under a tolerance (image_diff.h),
// for users' own visual regression tests: a script renders frames with
// `voxfall render -o new/frame_####.png` and runs `voxfall diff golden/ new/`; the status says
// whether anything changed beyond rounding.
//
// One line per frame on stdout (verdict and metrics), a closing count; done when every frame is
// within tolerance, failed when one is not (or is missing, or cannot be read). Names only in
// ACTUAL are listed but do not fail: rendering more frames than the goldens hold is not a
// regression. It does not poll for a stop: a signal removes the diff image being written and
// ends the process (render/run/stop_policy.h).
#pragma once

#include <string>

#include "render/output/image_diff.h"
#include "render/run/stop_policy.h"

namespace vf {

struct DiffRequest {
  std::string expected;     // the reference PNG or folder
  std::string actual;       // the PNG or folder to check
  DiffTolerance tolerance;  // per-channel threshold, share of differing pixels, SSIM
  std::string out;          // a file (two PNGs) or a folder (two folders); "": no diff images
};

// Compares and prints the verdicts. Bad input throws InputError.
RunStatus runDiff(const DiffRequest& request);

}  // namespace vf
