// Plots of a run as a library call: what `voxfall plot RUN.csv [--scene SCENE] [-o DIR]` does.
// Publication plots of a run written by `voxfall simulate --csv RUN.csv`
// (render/figures/run_plots.h). The CSV holds positions and velocities but not masses: with a
// scene the energies are in joules (masses and inertia from the scene's shapes), without it per
// kg and translational only, and the plots say so.
#pragma once

#include <string>

#include "render/run/stop_policy.h"

namespace vf {

struct PlotRequest {
  std::string run;     // the run's CSV
  std::string scene;   // "": energies per kg
  std::string outDir;  // "": out/plots/<RUN stem>
};

// Writes the plots. Bad input throws InputError.
RunStatus runPlot(const PlotRequest& request);

}  // namespace vf
