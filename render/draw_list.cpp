#include "render/draw_list.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace vf {
namespace {

constexpr double kDegrees = std::numbers::pi / 180.0;

// The automatic camera looks down 13 degrees from the azimuth of the default CameraSpec
// position (4, -6, 3): floor, shadows and three sides of a box are visible, and the horizon
// with its sky gradient sits in the top fifth of the picture (tan 13 / tan 20 of the
// half-height above the middle for the default 40 degree field of view).
constexpr double kAutoPitch = 13 * kDegrees;

// The sun stands 50 degrees high, 55 degrees counter-clockwise of the camera's azimuth:
// shadows fall sideways and away from the viewer, where they show the bodies' contact with
// the floor, and the faces towards the camera are lit unevenly, which shows facets.
Vec3 sunFromCamera(const Vec3& cameraOffset) {
  const double azimuth = std::atan2(cameraOffset.y(), cameraOffset.x()) + 55 * kDegrees;
  const double elevation = 50 * kDegrees;
  return Vec3(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
              std::sin(elevation));
}

// Bounding sphere of a mesh's vertices (box centre; good enough for framing and shadows).
Sphere meshSphere(const TriMesh& mesh) {
  if (mesh.vertices.empty()) return Sphere{};
  Eigen::AlignedBox3d box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  Sphere s{box.center(), 0};
  for (const Vec3& v : mesh.vertices) s.radius = std::max(s.radius, (v - s.centre).norm());
  return s;
}

}  // namespace

std::vector<Vec3> smoothVertexNormals(const TriMesh& mesh) {
  // Each face normal weighted by the face's angle at the vertex: unlike area weights, the
  // result does not depend on how a surface happens to be cut into triangles (a grid cell's
  // diagonal would otherwise tilt the normals towards its side).
  std::vector<Vec3> normals(mesh.vertices.size(), Vec3::Zero());
  for (const auto& t : mesh.triangles) {
    const Vec3 n = (mesh.vertices[t[1]] - mesh.vertices[t[0]])
                       .cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    if (!(n.norm() > 0)) continue;
    for (int corner = 0; corner < 3; ++corner) {
      const Vec3& p = mesh.vertices[t[corner]];
      const Vec3 a = mesh.vertices[t[(corner + 1) % 3]] - p;
      const Vec3 b = mesh.vertices[t[(corner + 2) % 3]] - p;
      const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
      normals[t[corner]] += n.normalized() * angle;
    }
  }
  for (Vec3& n : normals) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ());
  return normals;
}

Mat4 bodyModelMatrix(const Vec3& x, const Quat& q) {
  Mat4 m = Mat4::Identity();
  m.block<3, 3>(0, 0) = q.normalized().toRotationMatrix();
  m.block<3, 1>(0, 3) = x;
  return m;
}

std::vector<BodyView> bodyViews(const World& world, const std::vector<Color>& colors) {
  std::vector<BodyView> views(static_cast<std::size_t>(world.bodyCount()));
  for (int id = 0; id < world.bodyCount(); ++id) {
    BodyView& v = views[static_cast<std::size_t>(id)];
    v.shape = world.shapePtr(id);
    v.x = world.state(id).x;
    v.q = world.state(id).q;
    v.active = world.isActive(id);
    v.color = static_cast<std::size_t>(id) < colors.size() ? colors[static_cast<std::size_t>(id)]
                                                           : defaultBodyColor(id);
  }
  return views;
}

Sphere enclose(const Sphere& a, const Sphere& b) {
  const Vec3 d = b.centre - a.centre;
  const double dist = d.norm();
  if (dist + b.radius <= a.radius) return a;
  if (dist + a.radius <= b.radius) return b;
  const double radius = (dist + a.radius + b.radius) / 2;
  // dist > 0 here: equal centres are caught by one of the containment tests above.
  return Sphere{a.centre + d * ((radius - a.radius) / dist), radius};
}

Sphere encloseAll(std::span<const Sphere> spheres) {
  if (spheres.empty()) return Sphere{Vec3::Zero(), 1};
  Eigen::AlignedBox3d box;
  for (const Sphere& s : spheres) {
    box.extend(s.centre - Vec3::Constant(s.radius));
    box.extend(s.centre + Vec3::Constant(s.radius));
  }
  Sphere out{box.center(), 0};
  for (const Sphere& s : spheres) {
    out.radius = std::max(out.radius, (s.centre - out.centre).norm() + s.radius);
  }
  return out;
}

AutoFraming::AutoFraming(double fovYDegrees, double aspect) : fovYDegrees_(fovYDegrees) {
  const Vec3 horizontal = Vec3(-4, 6, 0).normalized();  // looking from (4, -6) towards the origin
  forward_ = horizontal * std::cos(kAutoPitch) - Vec3::UnitZ() * std::sin(kAutoPitch);
  right_ = forward_.cross(Vec3::UnitZ()).normalized();
  up_ = right_.cross(forward_);
  halfY_ = fovYDegrees * kDegrees / 2;
  halfX_ = std::atan(std::tan(halfY_) * aspect);
  // Inward normals of the four side planes of a frustum with this orientation (any position).
  const double ca = std::cos(halfX_), sa = std::sin(halfX_);
  const double cb = std::cos(halfY_), sb = std::sin(halfY_);
  normals_ = {-ca * right_ + sa * forward_, ca * right_ + sa * forward_, -cb * up_ + sb * forward_,
              cb * up_ + sb * forward_};
}

void AutoFraming::add(const Sphere& s) {
  // A sphere is inside side plane j of a camera at P when n_j . (s - P) >= r, i.e.
  // n_j . P <= n_j . s - r: keep the tightest right-hand side per plane.
  for (std::size_t j = 0; j < 4; ++j) {
    const double h = normals_[j].dot(s.centre) - s.radius * kMargin;
    limits_[j] = empty_ ? h : std::min(limits_[j], h);
  }
  const Sphere grown{s.centre, s.radius};
  region_ = empty_ ? grown : enclose(region_, grown);
  empty_ = false;
}

CameraView AutoFraming::camera() const {
  const Sphere region = empty_ ? Sphere{Vec3::Zero(), 1} : region_;
  std::array<double, 4> h = limits_;
  if (empty_) {
    for (std::size_t j = 0; j < 4; ++j) h[j] = normals_[j].dot(region.centre) - region.radius;
  }
  // Position P = x right + y up + z forward, as far forward as the four constraints
  // n_j . P <= h_j allow. The right/left pair bounds z by (hR + hL) / (2 sin a) and fixes x
  // midway, the top/bottom pair likewise; the tighter pair decides, the other is centred.
  const double x = (h[1] - h[0]) / (2 * std::cos(halfX_));
  const double y = (h[3] - h[2]) / (2 * std::cos(halfY_));
  const double z =
      std::min((h[0] + h[1]) / (2 * std::sin(halfX_)), (h[2] + h[3]) / (2 * std::sin(halfY_)));
  Vec3 position = x * right_ + y * up_ + z * forward_;
  // A little air around the outermost bodies: step back by a tenth of the distance.
  const double distance = std::max(forward_.dot(region.centre - position), 1e-3);
  position -= forward_ * (0.1 * distance);
  CameraView c;
  c.position = position;
  c.lookAt = position + forward_ * (1.1 * distance);
  c.up = Vec3::UnitZ();
  c.fovYDegrees = fovYDegrees_;
  return c;
}

DrawListBuilder::DrawListBuilder(const CameraSpec& camera, std::optional<double> groundHeight,
                                 double aspect)
    : spec_(camera), ground_(groundHeight), aspect_(aspect), framing_(camera.fovDegrees, aspect) {}

void DrawListBuilder::setTerrain(std::shared_ptr<const TriMesh> mesh,
                                 std::shared_ptr<const std::vector<Vec3>> normals, Color color) {
  terrain_ = std::move(mesh);
  terrainNormals_ = std::move(normals);
  terrainColor_ = color;
  terrainSphere_ = terrain_ ? meshSphere(*terrain_) : Sphere{};
}

double DrawListBuilder::shapeRadius(const std::shared_ptr<const Shape>& shape) {
  auto it = radii_.find(shape.get());
  if (it != radii_.end()) return it->second.second;
  double r = 0;
  for (const Vec3& v : shape->mesh.vertices) r = std::max(r, v.norm());
  radii_.emplace(shape.get(), std::make_pair(shape, r));
  return r;
}

std::vector<Sphere> DrawListBuilder::bodySpheres(std::span<const BodyView> bodies,
                                                 bool withGround) {
  std::vector<Sphere> spheres;
  for (const BodyView& b : bodies) {
    if (!b.active || !b.shape) continue;
    const double r = shapeRadius(b.shape);
    spheres.push_back(Sphere{b.x, r});
    // The floor under a body belongs in the picture: that is where it lands and its shadow
    // is. A small sphere: a full-size one would be half under the floor, and framing that
    // invisible half would push the bodies up the picture.
    if (withGround && ground_) {
      spheres.push_back(Sphere{Vec3(b.x.x(), b.x.y(), *ground_), 0.25 * r});
    }
  }
  return spheres;
}

void DrawListBuilder::observe(std::span<const BodyView> bodies) {
  // The terrain is left out: a large one would shrink the bodies to specks; the bodies (and the
  // floor under them) are where the action is.
  for (const Sphere& s : bodySpheres(bodies, true)) framing_.add(s);
}

DrawList DrawListBuilder::build(std::span<const BodyView> bodies) {
  observe(bodies);
  DrawList list;
  list.groundHeight = ground_;

  // Meshes in order of first use, so the list is the same for the same bodies.
  std::map<const void*, int> meshIndex;
  for (const BodyView& b : bodies) {
    if (!b.active || !b.shape) continue;
    auto [it, added] = meshIndex.emplace(b.shape.get(), static_cast<int>(list.meshes.size()));
    if (added) {
      list.meshes.push_back(
          DrawMesh{b.shape.get(), std::shared_ptr<const TriMesh>(b.shape, &b.shape->mesh), {}});
    }
    DrawInstance inst;
    inst.mesh = it->second;
    inst.model = bodyModelMatrix(b.x, b.q);
    inst.color = b.color;
    list.instances.push_back(inst);
  }
  if (terrain_) {
    list.meshes.push_back(DrawMesh{terrain_.get(), terrain_, terrainNormals_});
    DrawInstance inst;
    inst.mesh = static_cast<int>(list.meshes.size()) - 1;
    inst.color = terrainColor_;
    inst.surface = Surface::terrain;
    list.instances.push_back(inst);
  }

  // Shadow casters: this frame's bodies (tight, for shadow-map resolution) and the terrain.
  std::vector<Sphere> casters = bodySpheres(bodies, false);
  if (terrain_) casters.push_back(terrainSphere_);
  const Sphere casterSphere = encloseAll(casters);
  list.casterCentre = casterSphere.centre;
  list.casterRadius = casterSphere.radius;

  // Camera.
  const Sphere region = framing_.empty() ? Sphere{Vec3::Zero(), 1} : framing_.region();
  const BodyView* followed = nullptr;
  if (spec_.followBody && *spec_.followBody >= 0 &&
      static_cast<std::size_t>(*spec_.followBody) < bodies.size() &&
      bodies[static_cast<std::size_t>(*spec_.followBody)].shape) {
    followed = &bodies[static_cast<std::size_t>(*spec_.followBody)];
  }
  CameraView& cam = list.camera;
  if (spec_.given) {
    cam.position = spec_.position;
    cam.lookAt = spec_.lookAt;
    cam.up = spec_.up;
    cam.fovYDegrees = spec_.fovDegrees;
    if (followed) {
      // Keep the scene's camera offset and move it with the body.
      cam.position = followed->x + (spec_.position - spec_.lookAt);
      cam.lookAt = followed->x;
    }
  } else if (followed) {
    const double r = shapeRadius(followed->shape);
    // The body with three body sizes of context, and the floor under it.
    AutoFraming own(spec_.fovDegrees, aspect_);
    own.add(Sphere{followed->x, 3 * r});
    if (ground_) own.add(Sphere{Vec3(followed->x.x(), followed->x.y(), *ground_), 0.75 * r});
    cam = own.camera();
  } else {
    cam = framing_.camera();
  }

  // Depth range and floor fade from the distances involved: near as far out as the framed
  // region allows (depth precision where bodies touch the floor), far past the fade.
  const double distance = std::max((cam.lookAt - cam.position).norm(), 1e-3);
  const double extent = std::max(region.radius, 0.05);
  list.groundFadeStart = distance + 2.5 * extent;
  if (terrain_) {
    // The terrain is the set: it stays clear out to its far edge.
    list.groundFadeStart =
        std::max(list.groundFadeStart,
                 (cam.position - terrainSphere_.centre).norm() + terrainSphere_.radius);
  }
  list.groundFadeEnd = list.groundFadeStart + 6 * extent + 0.5 * distance;
  const double nearestBody = (cam.position - region.centre).norm() - region.radius;
  cam.nearPlane = std::clamp(0.5 * nearestBody, 0.002 * distance, 0.25 * distance);
  // Terrain may come much closer to the camera than any body.
  if (terrain_) cam.nearPlane = std::min(cam.nearPlane, 0.02 * distance);
  cam.farPlane = list.groundFadeEnd * 1.05 + 2 * extent;

  list.sunDirection = sunFromCamera(cam.position - cam.lookAt);
  return list;
}

}  // namespace vf
