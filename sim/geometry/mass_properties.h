// Mass, centre of mass and inertia tensor of a closed triangle mesh of uniform density,
// from exact volume integrals over its triangles (divergence theorem).
#pragma once

#include "sim/core/math.h"
#include "sim/geometry/tri_mesh.h"

namespace vf {

struct MassProperties {
  double volume = 0;  // m^3
  double mass = 0;    // kg
  Vec3 centerOfMass;  // m, in mesh coordinates
  Mat3 inertia;       // kg m^2, about the centre of mass, mesh axes
};

// Exact for any closed, outward-oriented mesh (validateClosedMesh first). density in kg/m^3.
MassProperties computeMassProperties(const TriMesh& mesh, double density);

}  // namespace vf
