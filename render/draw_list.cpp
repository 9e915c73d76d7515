#include "render/draw_list.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "render/terrain_camera.h"
#include "render/terrain_solid.h"
#include "sim/core/error.h"
#include "sim/geometry/cell_grid.h"
#include "sim/scene/scene.h"
#include "sim/shape/drape_import.h"
#include "sim/world.h"

namespace vf {
namespace {

constexpr double kDegrees = std::numbers::pi / 180.0;

// The shadow map is fitted to the view instead of the casters when the view's slice is under
// a quarter of the casters' sphere: only at terrain scale, so scenes whose casters all lie in
// view keep the fit they had (and their pixels).
constexpr double kShadowFitRatio = 0.25;

// Trails are drawn this many pixels wide at every distance.
constexpr double kTrailPixels = 2;

// The sides and base of a terrain's solid: a dry, dark earth, so a cut through the ground reads
// as ground and not as the sky or the floor behind it.
constexpr Color kTerrainSideColor{0.15f, 0.12f, 0.09f};

// On a terrain, a chase camera without a given view frames its bodies with this many body
// radii of context (three elsewhere): enough of the slope to read where the rock goes, with the
// rock still a few percent of the picture's height (at 1280x720, twenty-odd pixels for the
// Tyrol scene's 1 m rocks).
constexpr double kTerrainChaseContext = 10;
constexpr double kChaseContext = 3;

// The ground under the first frame's bodies that sets the automatic view on a terrain: their
// box grown by this many cells, so the fit sees the slope and not one bump.
constexpr double kSlopeFitCells = 20;
// A terrain chase looks across the slope under its target, fitted this many cells around it,
// and turns towards a new slope direction with this time constant (s): the slope under a
// rolling rock changes from cell to cell, and a camera swinging with every bump is unwatchable.
constexpr double kChaseSlopeCells = 8;
constexpr double kChaseTurnSeconds = 2;
// ...from 30 degrees down the slope from the across-slope view, and looking 25 degrees down
// (the automatic camera's 13 on a floor): along the contour and nearly level, a chase camera
// grazes the ground between it and the rock, which fills the picture as a dark smear, wherever
// the slope turns.
constexpr double kChaseUpSlopeDegrees = 30;
constexpr double kTerrainChasePitch = 25;
// The automatic camera on a terrain keeps about this many body positions of the clip in sight,
// checked again after each of at most this many moves.
constexpr std::size_t kSightLines = 2000;
constexpr int kSightRounds = 4;
// ...rising by at most this share of its distance from what it looks at.
constexpr double kMostLift = 0.25;

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

void DrawListBuilder::addTrails(DrawList& list, std::span<const BodyView> bodies, int frame) {
  const CameraView& cam = list.camera;
  const Vec3 forward = (cam.lookAt - cam.position).normalized();
  const double pixel = 2 * std::tan(cam.fovYDegrees * kDegrees / 2) / height_;  // m per m depth
  const int first = std::max(0, frame - static_cast<int>(std::ceil(spec_.trailSeconds * fps_)));
  for (std::size_t id = 0; id < bodies.size(); ++id) {
    if (!bodies[id].shape) continue;
    auto mesh = std::make_shared<TriMesh>();
    for (int f = first; f < frame; ++f) {
      const FrameRecord& a = history_[static_cast<std::size_t>(f)];
      const FrameRecord& b = history_[static_cast<std::size_t>(f + 1)];
      if (id >= a.centres.size() || id >= b.centres.size() || !a.active[id] || !b.active[id]) {
        continue;
      }
      const Vec3 p0 = a.centres[id], p1 = b.centres[id];
      const Vec3 mid = (p0 + p1) / 2;
      const double depth = forward.dot(mid - cam.position);
      Vec3 side = (p1 - p0).cross(mid - cam.position);
      if (!(depth > cam.nearPlane) || !(side.norm() > 0)) continue;
      side *= 0.5 * kTrailPixels * pixel * depth / side.norm();
      const auto base = static_cast<std::uint32_t>(mesh->vertices.size());
      mesh->vertices.insert(mesh->vertices.end(), {p0 - side, p0 + side, p1 - side, p1 + side});
      mesh->triangles.push_back({base, base + 1, base + 3});
      mesh->triangles.push_back({base, base + 3, base + 2});
    }
    if (mesh->triangles.empty()) continue;
    DrawMesh drawn;
    drawn.mesh = mesh;
    drawn.transient = true;
    list.meshes.push_back(drawn);
    DrawInstance inst;
    inst.mesh = static_cast<int>(list.meshes.size()) - 1;
    inst.color = bodies[id].color;
    inst.surface = Surface::unlit;
    inst.castsShadow = false;
    list.instances.push_back(inst);
  }
}

DrawListBuilder::DrawListBuilder(const CameraSpec& camera, std::optional<double> groundHeight,
                                 int width, int height, double fps)
    : spec_(camera),
      ground_(groundHeight),
      aspect_(static_cast<double>(width) / height),
      height_(height),
      fps_(fps),
      framing_(camera.fovDegrees, aspect_),
      light_(sceneLight(LightSpec{}, nullptr)),
      autoView_(defaultAutoView()) {}

DrawListBuilder::DrawListBuilder(const CameraSpec& camera, std::optional<double> groundHeight,
                                 double aspect)
    : DrawListBuilder(camera, groundHeight, static_cast<int>(std::lround(720 * aspect)), 720, 30) {
  aspect_ = aspect;
}

void DrawListBuilder::setTerrain(std::shared_ptr<const Heightfield> field,
                                 std::shared_ptr<const DrapeImage> drape) {
  field_ = std::move(field);
  drape_ = std::move(drape);
  if (!field_) {
    setTerrain(std::shared_ptr<const TriMesh>());
    setTerrainSides(nullptr);
    return;
  }
  // A heightfield is a sampled smooth surface: drawn with smooth normals, and slope-coloured.
  auto surface = std::make_shared<const TriMesh>(field_->toMesh());
  setTerrain(surface, std::make_shared<const std::vector<Vec3>>(smoothVertexNormals(*surface)));
  const double base = terrainBase(*field_, ground_);
  const bool onFloor = ground_ && *ground_ == base;
  setTerrainSides(std::make_shared<const TriMesh>(terrainSides(*field_, base, !onFloor)));
}

void DrawListBuilder::setTerrainSides(std::shared_ptr<const TriMesh> sides) {
  terrainSides_ = std::move(sides);
  sidesSphere_ = terrainSides_ ? meshSphere(*terrainSides_) : Sphere{};
}

void DrawListBuilder::setLight(const SceneLight& light) { light_ = light; }

void DrawListBuilder::setTerrain(std::shared_ptr<const TriMesh> mesh,
                                 std::shared_ptr<const std::vector<Vec3>> normals, Color color) {
  terrain_ = std::move(mesh);
  terrainNormals_ = std::move(normals);
  terrainColor_ = color;
  terrainSphere_ = terrain_ ? meshSphere(*terrain_) : Sphere{};
  terrainBox_.setEmpty();
  terrainTiles_.clear();
  if (!terrain_) return;
  for (const Vec3& v : terrain_->vertices) terrainBox_.extend(v);
  const std::size_t count = terrain_->triangles.size();
  if (count <= 2 * kTerrainTileTriangles) {
    terrainTiles_.push_back({terrain_, terrainNormals_});
    return;
  }
  // Why tiles: the renderer redraws only what can change between frames (redraw_region.h),
  // culling instances by their boxes, but a terrain of one mesh is one instance that every
  // redrawn part has to draw whole. On the Tyrol DEM (400,000 triangles) as one mesh, llvmpipe
  // spends over half of a frame in Mesa's draw module walking all of its vertices for each part.
  // Triangles go to the square of a grid over the terrain's box that holds their centroid (the
  // side chosen for about kTerrainTileTriangles a square where they are spread evenly), in
  // their own order; a tile copies the vertices (and normals) its triangles use, so every
  // triangle reaches the GPU with exactly the values it had in the whole mesh.
  const Eigen::Vector2d lo = terrainBox_.min().head<2>();
  const Eigen::Vector2d size = terrainBox_.sizes().head<2>().cwiseMax(1e-9);
  const double side =
      std::sqrt(size.x() * size.y() * static_cast<double>(kTerrainTileTriangles) / count);
  const int nx = std::max(1, static_cast<int>(std::ceil(size.x() / side)));
  const int ny = std::max(1, static_cast<int>(std::ceil(size.y() / side)));
  std::vector<std::vector<std::uint32_t>> squares(static_cast<std::size_t>(nx) * ny);
  const std::vector<Vec3>& v = terrain_->vertices;
  for (std::size_t k = 0; k < count; ++k) {
    const auto& t = terrain_->triangles[k];
    const Eigen::Vector2d c = ((v[t[0]] + v[t[1]] + v[t[2]]) / 3).head<2>();
    const int i = cellIndex((c.x() - lo.x()) / side, nx - 1);
    const int j = cellIndex((c.y() - lo.y()) / side, ny - 1);
    squares[static_cast<std::size_t>(j) * nx + i].push_back(static_cast<std::uint32_t>(k));
  }
  std::vector<std::uint32_t> local(v.size(), UINT32_MAX);  // whole-mesh vertex -> tile vertex
  for (const std::vector<std::uint32_t>& square : squares) {
    if (square.empty()) continue;
    auto tile = std::make_shared<TriMesh>();
    auto tileNormals = terrainNormals_ ? std::make_shared<std::vector<Vec3>>() : nullptr;
    std::vector<std::uint32_t> used;
    for (const std::uint32_t k : square) {
      std::array<std::uint32_t, 3> t = terrain_->triangles[k];
      for (std::uint32_t& index : t) {
        if (local[index] == UINT32_MAX) {
          local[index] = static_cast<std::uint32_t>(tile->vertices.size());
          tile->vertices.push_back(v[index]);
          if (tileNormals) tileNormals->push_back((*terrainNormals_)[index]);
          used.push_back(index);
        }
        index = local[index];
      }
      tile->triangles.push_back(t);
    }
    for (const std::uint32_t index : used) local[index] = UINT32_MAX;
    terrainTiles_.push_back({std::move(tile), std::move(tileNormals)});
  }
}

double DrawListBuilder::shapeRadius(const std::shared_ptr<const Shape>& shape) {
  auto it = radii_.find(shape.get());
  if (it != radii_.end()) return it->second.second;
  double r = 0;
  for (const Vec3& v : shape->mesh.vertices) r = std::max(r, v.norm());
  radii_.emplace(shape.get(), std::make_pair(shape, r));
  return r;
}

bool DrawListBuilder::onStage(const BodyView& b) {
  if (!b.shape) return false;
  const double r = shapeRadius(b.shape);
  if (terrain_ && !terrainBox_.isEmpty()) {
    const Vec3& lo = terrainBox_.min();
    const Vec3& hi = terrainBox_.max();
    const bool over = b.x.x() >= lo.x() - r && b.x.x() <= hi.x() + r && b.x.y() >= lo.y() - r &&
                      b.x.y() <= hi.y() + r;
    if (!over) return false;
    if (b.x.z() + r < std::min(lo.z(), ground_.value_or(lo.z()))) return false;
    return true;
  }
  if (ground_ && b.x.z() + r < *ground_) return false;  // fell through the floor
  return true;
}

std::vector<Sphere> DrawListBuilder::bodySpheres(std::span<const BodyView> bodies,
                                                 bool withGround) {
  std::vector<Sphere> spheres;
  for (const BodyView& b : bodies) {
    if (!b.active || !b.shape || !onStage(b)) continue;
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

std::optional<Vec3> DrawListBuilder::chaseTarget(std::span<const BodyView> bodies) const {
  std::vector<int> ids = spec_.followGroup;
  if (spec_.followBody) ids.push_back(*spec_.followBody);
  Vec3 sum = Vec3::Zero();
  int count = 0;
  for (const int id : ids) {
    if (id < 0 || static_cast<std::size_t>(id) >= bodies.size()) continue;
    const BodyView& b = bodies[static_cast<std::size_t>(id)];
    if (!b.active || !b.shape) continue;
    sum += b.x;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return Vec3(sum / count);
}

void DrawListBuilder::chooseAutoView(std::span<const BodyView> bodies) {
  if (!field_) return;
  // Every body placed, released or not: an emitter's bodies wait where they will be released.
  std::vector<Vec3> placed;
  for (const BodyView& b : bodies)
    if (b.shape) placed.push_back(b.x);
  if (const auto down = downhillNear(*field_, placed, kSlopeFitCells * field_->cell)) {
    autoView_ = acrossSlope(*down);
    framing_ = AutoFraming(spec_.fovDegrees, aspect_, autoView_);
  }
}

DrawMesh DrawListBuilder::bodyMesh(const BodyView& b) {
  // A shape's mesh is closed and wound outward (validateClosedMesh), and so is its creased
  // copy: DrawMesh::closed.
  if (!b.smoothDegrees) {
    return DrawMesh{
        b.shape.get(), std::shared_ptr<const TriMesh>(b.shape, &b.shape->mesh), {}, false, true};
  }
  auto& creased = creased_[{b.shape.get(), *b.smoothDegrees}];
  if (!creased)
    creased = std::make_shared<const CreasedMesh>(creasedNormals(b.shape->mesh, *b.smoothDegrees));
  return DrawMesh{creased.get(), std::shared_ptr<const TriMesh>(creased, &creased->mesh),
                  std::shared_ptr<const std::vector<Vec3>>(creased, &creased->normals), false,
                  true};
}

void DrawListBuilder::include(std::span<const BodyView> bodies) {
  if (included_++ == 0) chooseAutoView(bodies);
  // The terrain is left out: a large one would shrink the bodies to specks; the bodies (and the
  // floor under them) are where the action is.
  for (const Sphere& s : bodySpheres(bodies, true)) framing_.add(s);
  for (const Sphere& s : bodySpheres(bodies, false)) {
    casterBox_.extend(s.centre - Vec3::Constant(s.radius));
    casterBox_.extend(s.centre + Vec3::Constant(s.radius));
  }
}

void DrawListBuilder::addDrawnFrame(std::span<const BodyView> bodies) {
  FrameRecord record;
  record.centres.reserve(bodies.size());
  for (const BodyView& b : bodies) {
    record.centres.push_back(b.x);
    record.active.push_back(b.active && b.shape);
  }
  // The chase target lags the followed bodies (chaseStep); before they appear it waits.
  const std::optional<Vec3> target = chaseTarget(bodies);
  const std::optional<Vec3> previous = history_.empty() ? std::nullopt : history_.back().chase;
  if (target && previous) {
    record.chase = chaseStep(*previous, *target, 1 / fps_, spec_.smoothing);
  } else {
    record.chase = target ? target : previous;
  }
  record.chaseView = history_.empty() ? autoView_ : history_.back().chaseView;
  if (terrainChase() && record.chase) {
    const Vec3 at[] = {*record.chase};
    if (const auto down = downhillNear(*field_, at, kChaseSlopeCells * field_->cell)) {
      const bool first = history_.empty() || !history_.back().chase;  // the chase starts
      const Vec3 turned = chaseStep(record.chaseView, acrossSlope(*down, kChaseUpSlopeDegrees),
                                    1 / fps_, first ? 0.0 : kChaseTurnSeconds);
      if (turned.head<2>().norm() > 1e-6)
        record.chaseView = Vec3(turned.x(), turned.y(), 0).normalized();
    }
  }
  history_.push_back(std::move(record));
}

DrawList DrawListBuilder::build(std::span<const BodyView> bodies) {
  observe(bodies);
  return build(bodies, observedFrames() - 1);
}

bool DrawListBuilder::terrainChase() const {
  const bool follows = spec_.followBody || !spec_.followGroup.empty();
  return follows && field_ && !spec_.offsetGiven;
}

CameraView DrawListBuilder::chooseCamera(std::span<const BodyView> bodies, int frame) {
  const std::optional<Vec3>& chase = history_[static_cast<std::size_t>(frame)].chase;
  if (!spec_.path.empty()) return interpolateCameraPath(spec_.path, frame / fps_, spec_.up);
  // A chase on a terrain without a given offset is framed across the slope (below), and
  // before its bodies are released the view is the automatic one.
  if (spec_.given && !terrainChase()) {
    CameraView cam;
    cam.position = spec_.position;
    cam.lookAt = spec_.lookAt;
    cam.up = spec_.up;
    cam.fovYDegrees = spec_.fovDegrees;
    if (chase) {
      // Keep the scene's camera offset and move it with the (smoothed) target.
      cam.position = *chase + (spec_.position - spec_.lookAt);
      cam.lookAt = *chase;
    }
    return cam;
  }
  if (chase) {
    // The followed bodies with three body sizes of context (more on a terrain), and the floor
    // under them.
    double r = 0;
    std::vector<int> ids = spec_.followGroup;
    if (spec_.followBody) ids.push_back(*spec_.followBody);
    for (const int id : ids) {
      if (id < 0 || static_cast<std::size_t>(id) >= bodies.size()) continue;
      const BodyView& b = bodies[static_cast<std::size_t>(id)];
      if (!b.active || !b.shape) continue;
      const double context = field_ ? kTerrainChaseContext : kChaseContext;
      r = std::max(r, (b.x - *chase).norm() + context * shapeRadius(b.shape));
    }
    auto framed = [&](const Vec3& view) {
      AutoFraming own(spec_.fovDegrees, aspect_, view, field_ ? kTerrainChasePitch : 13);
      own.add(Sphere{*chase, r});
      if (ground_) own.add(Sphere{Vec3(chase->x(), chase->y(), *ground_), 0.25 * r});
      CameraView cam = own.camera();
      if (field_) keepAboveTerrain(*field_, cam, *chase, 0.1 * r);
      return cam;
    };
    const Vec3 view = field_ ? history_[static_cast<std::size_t>(frame)].chaseView : autoView_;
    CameraView cam = framed(view);
    // Off the terrain's data the camera would look at the solid's wall: from the other side
    // of the slope instead, where that side has ground.
    const auto offTerrain = [&](const CameraView& c) {
      return std::isnan(field_->heightAt(c.position.x(), c.position.y()));
    };
    if (field_ && offTerrain(cam)) {
      const CameraView other = framed(-view);
      if (!offTerrain(other)) cam = other;
    }
    return cam;
  }
  return automaticCamera();
}

CameraView DrawListBuilder::automaticCamera() {
  const std::pair<int, int> seen{included_, observedFrames()};
  if (autoCamera_ && autoCamera_->first == seen) return autoCamera_->second;
  CameraView cam = framing_.camera();
  if (field_ && !framing_.empty()) {
    // In sight of the bodies over the clip: the eye as high as the ground between it and them
    // asks (checked for up to about kSightLines body positions spread evenly over the frames),
    // reached by rising and stepping back with the same pitch. Stepping back can bring other
    // ground into the way, so a few rounds.
    std::size_t positions = 0;
    for (const FrameRecord& f : history_) positions += f.centres.size();
    const std::size_t stride = std::max<std::size_t>(1, positions / kSightLines);  // frames
    // Not above this, however much ground is in the way: a view from far above shows a map.
    const double highest = cam.position.z() + kMostLift * (cam.lookAt - cam.position).norm() / 1.1;
    for (int round = 0; round < kSightRounds; ++round) {
      CameraView lifted = cam;
      const double clearance = 0.05 * (cam.lookAt - cam.position).norm();
      keepAboveTerrain(*field_, lifted, framing_.region().centre, clearance);
      for (std::size_t k = 0; k < history_.size(); k += stride) {
        const FrameRecord& f = history_[k];
        for (std::size_t id = 0; id < f.centres.size(); ++id)
          if (f.active[id]) keepAboveTerrain(*field_, lifted, f.centres[id], clearance);
      }
      if (lifted.position.z() <= cam.position.z()) break;
      cam = framing_.camera(std::min(lifted.position.z(), highest));
      if (lifted.position.z() >= highest) break;
    }
  }
  autoCamera_ = std::make_pair(seen, cam);
  return cam;
}

void DrawListBuilder::addBodies(DrawList& list, std::span<const BodyView> bodies) {
  // Meshes in order of first use, so the list is the same for the same bodies. A body smaller
  // on screen than min_pixels is drawn as a flat marker of that size: its own shape, scaled
  // up about its centre, unlit in its colour, casting no shadow.
  std::map<const void*, int> meshIndex;
  for (std::size_t id = 0; id < bodies.size(); ++id) {
    const BodyView& b = bodies[id];
    if (!b.active || !b.shape) continue;
    DrawMesh drawn = bodyMesh(b);
    auto [it, added] = meshIndex.emplace(drawn.key, static_cast<int>(list.meshes.size()));
    if (added) list.meshes.push_back(std::move(drawn));
    DrawInstance inst;
    inst.mesh = it->second;
    inst.model = bodyModelMatrix(b.x, b.q);
    inst.color = b.color;
    inst.id = static_cast<int>(id);
    if (spec_.minPixels > 0) {
      const double pixels = projectedDiameter(list.camera, b.x, shapeRadius(b.shape), height_);
      if (pixels < spec_.minPixels) {
        const double scale = spec_.minPixels / std::max(pixels, 1e-9);
        inst.model.block<3, 3>(0, 0) *= scale;
        inst.surface = Surface::unlit;
        inst.castsShadow = false;
      }
    }
    list.instances.push_back(inst);
  }
}

void DrawListBuilder::addTerrain(DrawList& list) const {
  for (const TerrainTile& tile : terrainTiles_) {
    list.meshes.push_back(DrawMesh{tile.mesh.get(), tile.mesh, tile.normals});
    DrawInstance inst;
    inst.mesh = static_cast<int>(list.meshes.size()) - 1;
    inst.color = terrainColor_;
    inst.surface = Surface::terrain;
    list.instances.push_back(inst);
  }
  if (terrainSides_ && !terrainSides_->triangles.empty()) {
    // Walls and base face outward, and their insides lie under the surface: seen from outside
    // the solid (or from above its surface) every back face is hidden, so they are culled.
    list.meshes.push_back(DrawMesh{terrainSides_.get(), terrainSides_, nullptr, false, true});
    DrawInstance inst;
    inst.mesh = static_cast<int>(list.meshes.size()) - 1;
    inst.color = kTerrainSideColor;
    inst.surface = Surface::body;
    list.instances.push_back(inst);
  }
}

Sphere DrawListBuilder::casterSphere() const {
  // Every body on the stage in every observed frame (one map for the whole clip, so frames
  // differ only where bodies moved: the renderer redraws just that part) and the terrain.
  std::vector<Sphere> casters;
  if (!casterBox_.isEmpty()) {
    casters.push_back(Sphere{casterBox_.center(), 0.5 * casterBox_.diagonal().norm()});
  }
  if (terrain_) casters.push_back(terrainSphere_);
  if (terrainSides_ && !terrainSides_->vertices.empty()) casters.push_back(sidesSphere_);
  return encloseAll(casters);
}

void DrawListBuilder::setDepthRange(DrawList& list, const Sphere& region, double distance,
                                    double extent) const {
  // Near as far out as the framed region allows (depth precision where bodies touch the
  // floor), far past the fade.
  CameraView& cam = list.camera;
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
}

DrawList DrawListBuilder::build(std::span<const BodyView> bodies, int frame) {
  VF_ASSERT(frame >= 0 && frame < observedFrames());
  DrawList list;
  list.groundHeight = ground_;

  // Camera.
  const Sphere region = framing_.empty() ? Sphere{Vec3::Zero(), 1} : framing_.region();
  CameraView& cam = list.camera;
  cam = chooseCamera(bodies, frame);

  addBodies(list, bodies);
  addTerrain(list);
  list.drape = drape_;

  // Shadow casters.
  Sphere casters = casterSphere();

  // Depth range and floor fade from the distances involved.
  const double distance = std::max((cam.lookAt - cam.position).norm(), 1e-3);
  const double extent = std::max(region.radius, 0.05);
  setDepthRange(list, region, distance, extent);
  if (spec_.trailSeconds > 0) addTrails(list, bodies, frame);

  // Kilometre scale: one 2048-texel map over a whole 2 km terrain has metre-wide texels, and a
  // metre-sized rock casts no visible shadow. When the part of the view around what the camera
  // looks at (out to the framed bodies' far side) is much smaller than the casters, the map
  // covers that part only; casters further towards the sun still fall inside its depth range.
  const Sphere viewed = viewSlice(cam, aspect_, distance + 2 * extent);
  if (viewed.radius < kShadowFitRatio * casters.radius) casters = viewed;
  list.casterCentre = casters.centre;
  list.casterRadius = casters.radius;

  // Fixed in the world: the scene's sun, or the default for the automatic view (which the
  // first observed frame fixed), whatever camera draws this frame.
  list.sunDirection = light_.sunDirection.value_or(defaultSunDirection(autoView_));
  list.light = light_.colors;
  return list;
}

}  // namespace vf
