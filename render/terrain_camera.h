// Where the automatic and chase cameras stand on a terrain. Looking straight onto a slope shows
// ground and nothing else (no horizon, no sense of the fall); looking across it, along the
// contour lines, shows the slope in profile, the rocks crossing the picture and the sky above
// the far ground. So on a terrain those cameras look across the slope under the rocks' release,
// downhill to the right, and keep above the ground.
#pragma once

#include <optional>
#include <span>

#include "render/camera.h"
#include "sim/shape/heightfield.h"

namespace vf {

// The horizontal unit vector down the plane fitted (least squares) to the terrain's samples in
// the box around `points` (x, y) grown by `margin` m; none when there are fewer than three
// samples with data there or the plane is level (a fall of under 1 in 1000).
std::optional<Vec3> downhillNear(const Heightfield& h, std::span<const Vec3> points, double margin);

// The horizontal viewing direction across a slope falling along `downhill`, with downhill on
// the right of the picture (the reading direction): up x downhill, turned `upDegrees` towards
// uphill, so that the camera stands that much down the slope from what it looks at and sees the
// slope's face rather than grazing along it.
Vec3 acrossSlope(const Vec3& downhill, double upDegrees = 0);

// Lifts the camera, keeping what it looks at, so that its eye is at least `clearance` m above
// the terrain under it (where the terrain has data there), and so that the ground between the
// eye and `target` does not hide the target: the sight line keeps above the terrain by
// `clearance` shrinking linearly to nothing at the target, sampled every half cell (up to 256
// samples) short of its last 5 % (where the target's own ground is).
void keepAboveTerrain(const Heightfield& h, CameraView& camera, const Vec3& target,
                      double clearance);

}  // namespace vf
