// Framing geometry for the cameras that place themselves: bounding spheres, the automatic
// camera's fit of a fixed orientation around every sphere of a clip, and the part of a view
// the shadow map covers at terrain scale. Plain Eigen, no GL.
#pragma once

#include <array>
#include <cmath>
#include <span>

#include "render/camera.h"
#include "sim/core/math.h"

namespace vf {

// A bounding sphere.
struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
};
// Smallest sphere around both (exact for two spheres).
Sphere enclose(const Sphere& a, const Sphere& b);
// A sphere around all of them (the centre of their bounding box; not minimal, but simple and
// order-independent). An empty list gives a unit sphere at the origin.
Sphere encloseAll(std::span<const Sphere> spheres);

// The automatic camera's horizontal viewing direction without a terrain: from the azimuth of
// the default CameraSpec position (4, -6) towards the origin.
Vec3 defaultAutoView();

// The automatic camera: a fixed orientation (looking `pitchDegrees` down along the horizontal
// direction `view`; 13 by default, so that floor, shadows and three sides of a box show, and
// the horizon with its sky gradient sits in the top fifth of the picture: tan 13 / tan 20 of
// the half-height above the middle for the default 40 degree field of view) and the position
// closest to the scene from which every sphere added so far projects inside a view of the given
// vertical field of view and aspect ratio, with a little air around. Exact per sphere, not via one
// enclosing sphere, so a scene spread flat on the floor fills the picture.
class AutoFraming {
 public:
  AutoFraming(double fovYDegrees, double aspect, const Vec3& view = defaultAutoView(),
              double pitchDegrees = 13);
  // Includes a sphere (the framing only ever grows).
  void add(const Sphere& s);
  bool empty() const { return empty_; }
  // A sphere around everything added (for depth range and fade distances).
  const Sphere& region() const { return region_; }
  // The camera; with nothing added, one that frames a unit sphere at the origin. With its eye
  // at least at height `lowestEye` (m): raised along the picture's up and moved back until
  // everything is in view again, the orientation unchanged.
  CameraView camera(double lowestEye = -INFINITY) const;

 private:
  static constexpr double kMargin = 1.05;  // radii grow 5%: rounding never clips a body
  double fovYDegrees_, halfX_ = 0, halfY_ = 0;
  Vec3 forward_, right_, up_;
  std::array<Vec3, 4> normals_;     // inward side-plane normals: right, left, top, bottom
  std::array<double, 4> limits_{};  // n_j . P <= limits_[j] keeps every sphere in view
  Sphere region_;
  bool empty_ = true;
};

// The part of a camera's view from the eye out to `depth` (m) along its axis, as a sphere.
Sphere viewSlice(const CameraView& camera, double aspect, double depth);

}  // namespace vf
