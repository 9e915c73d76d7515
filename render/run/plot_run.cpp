#include "render/run/plot_run.h"

#include <cstdio>
#include <filesystem>
#include <string>

#include "render/figures/run_plots.h"
#include "render/run/run_input.h"
#include "sim/scene/scene.h"

namespace vf {

RunStatus runPlot(const PlotRequest& o) {
  fig::RunPlotOptions p;
  const std::string stem = std::filesystem::path(o.run).stem().string();
  p.outDir = o.outDir.empty() ? "out/plots/" + stem : o.outDir;
  p.title = stem;
  if (!o.scene.empty()) {
    SceneSpec spec = loadScene(o.scene);
    applyLevelOverride(spec, 1);  // mass properties do not depend on the level: build cheaply
    const BuiltScene built = buildScene(spec);
    for (int id = 0; id < built.world->bodyCount(); ++id) {
      const Shape& s = built.world->shape(id);
      const bool still = built.world->isStatic(id);
      p.bodies.push_back({still ? 0.0 : s.mass, still ? Mat3(Mat3::Zero()) : s.inertiaBody});
    }
    p.gravity = spec.gravity;
    p.title = spec.name;
    p.inputs = runOutputRules(spec, o.scene, false, false).inputs;  // scene, meshes: never written
  }
  fig::plotRun(o.run, p);
  std::printf("plots written to %s (energy, speed, trajectories: PNG, SVG; CSV data)\n",
              p.outDir.c_str());
  return RunStatus::done();
}

}  // namespace vf
