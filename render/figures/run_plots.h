// Plots of a user's own run (`voxfall simulate --csv RUN.csv`): kinetic and potential energy
// against time, the speed of each body against time, and the trajectories in plan (x-y) and
// side (x-z) view, each as PNG + SVG, with the derived numbers as CSV beside them.
#pragma once

#include <string>
#include <vector>

#include "sim/core/math.h"

namespace vf::fig {

// What the energies need to know of each body id; without a scene every body counts as 1 kg
// with no rotational inertia (energies per kg, translation only).
struct BodyMass {
  double mass = 1;                  // kg; 0 for static bodies (no energy)
  Mat3 inertiaBody = Mat3::Zero();  // kg m^2 about the centre of mass, body frame
};
struct RunPlotOptions {
  std::string outDir;                // folder for the files
  std::vector<BodyMass> bodies;      // by body id; empty: 1 kg each, no rotation
  Vec3 gravity = Vec3(0, 0, -9.81);  // m/s^2
  std::string title;                 // e.g. the scene name
  std::vector<std::string> inputs;   // files read besides RUN.csv (scene, meshes): never written
};

// Reads RUN.csv (frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz; InputError with file:line
// for anything else) and writes OUT/energy.{png,svg,csv}, OUT/speed.{png,svg},
// OUT/trajectories.{png,svg} and OUT/bodies.csv (body, time, speed, x, y, z: what the speed and
// trajectory plots draw, grouped by body). Energies per frame: kinetic sum of m v^2 / 2 + w.I(t)w /
// 2, potential -m g.x (relative to the origin, as `simulate`'s summary), over non-static bodies.
// Earlier files of these names are replaced, but RUN.csv and `inputs` never are: an output that
// is one of them is refused (InputError) before anything is written.
void plotRun(const std::string& runCsv, const RunPlotOptions& options);

}  // namespace vf::fig
