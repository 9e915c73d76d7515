// Rock sizes of an ensemble: a rock volume drawn per realisation from a log-normal or a
// power-law distribution, bounded, and the drawn shape scaled to it with a drawn density.
#pragma once

#include <memory>

#include "sim/scene/scene.h"

namespace vf {

struct Shape;

// The volume (m^3) at probability u in [0, 1) of `v`, by the inverse of its cumulative
// distribution restricted to [min, max], so that u uniform gives volumes distributed as `v`:
// - log-normal: ln V normal with mean ln(median) and standard deviation sigma;
// - power: the count of rocks larger than V proportional to V^-b (b = exponent), the
//   frequency-volume law of rock-fall inventories (Dussauge-Peisser et al. 2002).
double volumeAt(const VolumeSpec& v, double u);

// `base` scaled uniformly about its centre of mass to volume `volume` (m^3), with density
// `density` (kg/m^3): mass, volume, inertia, diameter, mesh and sphere tree follow; the tree's
// levels keep their count (the paper's voxel size is relative to the body's size, so scaling
// the tree equals voxelising the scaled mesh). The polygon collider's polyhedron is not kept.
std::shared_ptr<const Shape> resizedShape(const Shape& base, double volume, double density);

}  // namespace vf
