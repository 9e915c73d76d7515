// The paper's figures as a library call: what `voxfall figures [NAME...] [-o DIR] [--quick]`
// does. The paper's comparison figures (fig10, fig13, fig14, fig16) as PNG + SVG + CSV and
// DIR/README.md (render/figures/paper_figures.h). It does not poll for a stop: a signal removes
// the files being written and ends the process (render/run/stop_policy.h); figures already
// finished stay.
#pragma once

#include <string>
#include <vector>

#include "render/run/stop_policy.h"

namespace vf {

struct FiguresRequest {
  std::vector<std::string> names;      // fig10 fig13 fig14 fig16; empty: all
  std::string outDir = "out/figures";  // output folder
  std::string scenes;                  // the paper's scenes; "": ./scenes, else the source tree's
  bool quick = false;                  // reduced configurations that run in seconds
  bool quiet = false;                  // no progress lines
};

// Runs the figures' simulations and draws them. Bad input throws InputError.
RunStatus runFigures(const FiguresRequest& request);

}  // namespace vf
