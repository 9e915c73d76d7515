#include "render/redraw_region.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace vf {
namespace {

// Pixels added around every projected bound: a triangle covers a pixel when one of its sample
// points (inside the pixel) is inside it, and the rounding of the projection differs in the last
// bits between this double-precision bound and the rasteriser's float arithmetic.
constexpr int kMarginPixels = 2;
// Rectangles are aligned to llvmpipe's 4x4 pixel blocks and the 2x2 quads derivatives come
// from (exactness does not depend on it; it keeps every quad whole).
constexpr int kAlignPixels = 8;
// At most this many rectangles are drawn one by one (each is a scene and a present pass).
constexpr std::size_t kMaxPieces = 48;
// A sun lower than this (sine of its elevation) casts shadows too long to bound usefully.
constexpr double kMinSunElevation = 0.02;

bool sameCamera(const CameraView& a, const CameraView& b) {
  return a.position == b.position && a.lookAt == b.lookAt && a.up == b.up &&
         a.fovYDegrees == b.fovYDegrees && a.nearPlane == b.nearPlane && a.farPlane == b.farPlane;
}

// Whether two instances of the same mesh draw the same pixels: what the GPU receives of them
// is equal (their model matrices may still differ in the digits single precision drops).
bool sameInstance(const DrawInstance& a, const GpuTransform& ta, const DrawInstance& b,
                  const GpuTransform& tb) {
  return a.color == b.color && a.surface == b.surface && a.castsShadow == b.castsShadow && ta == tb;
}

// Merges pairs for which merge(a, b) holds into their bounding box until no pair does.
template <class Merge>
std::vector<PixelRect> mergePairs(std::vector<PixelRect> rects, Merge merge) {
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < rects.size() && !merged; ++a) {
      for (std::size_t b = a + 1; b < rects.size(); ++b) {
        if (!merge(rects[a], rects[b])) continue;
        rects[a].unite(rects[b]);
        rects.erase(rects.begin() + static_cast<std::ptrdiff_t>(b));
        merged = true;
        break;
      }
    }
  }
  return rects;
}

int alignDown(int v, int a) { return v >= 0 ? v / a * a : -((-v + a - 1) / a) * a; }
int alignUp(int v, int a) { return -alignDown(-v, a); }

}  // namespace

void PixelRect::unite(const PixelRect& other) {
  if (other.empty()) return;
  if (empty()) {
    *this = other;
    return;
  }
  x0 = std::min(x0, other.x0);
  y0 = std::min(y0, other.y0);
  x1 = std::max(x1, other.x1);
  y1 = std::max(y1, other.y1);
}

bool PixelRect::intersects(const PixelRect& other) const {
  return !empty() && !other.empty() && x0 < other.x1 && other.x0 < x1 && y0 < other.y1 &&
         other.y0 < y1;
}

PixelRect PixelRect::intersection(const PixelRect& other) const {
  return PixelRect{std::max(x0, other.x0), std::max(y0, other.y0), std::min(x1, other.x1),
                   std::min(y1, other.y1)};
}

std::optional<PixelRect> projectPoints(const Mat4& viewProjection, std::span<const Vec3> points,
                                       double grow, int width, int height, int margin, int align) {
  // Each point's cube of half-side `grow` by its corners: the projections' box holds the
  // projection of the points' convex hull widened by `grow`, since a perspective projection
  // maps that hull (in front of the eye) to the convex region spanned by the projected corners.
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const Vec3& point : points) {
    for (int k = 0; k < 8; ++k) {
      const Vec3 p = point + grow * Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
      const Vec4 c = viewProjection * Vec4(p.x(), p.y(), p.z(), 1);
      if (!(c.w() > 1e-9)) return std::nullopt;
      for (int a = 0; a < 2; ++a) {
        const double ndc = c[a] / c.w();
        lo[a] = std::min(lo[a], ndc);
        hi[a] = std::max(hi[a], ndc);
      }
    }
  }
  if (points.empty()) return PixelRect{};
  const double size[2] = {static_cast<double>(width), static_cast<double>(height)};
  int px[2][2];
  for (int a = 0; a < 2; ++a) {
    // Clamp before converting so that far-off bounds do not overflow an int.
    const double from = std::clamp((lo[a] * 0.5 + 0.5) * size[a], -1.0, size[a] + 1);
    const double to = std::clamp((hi[a] * 0.5 + 0.5) * size[a], -1.0, size[a] + 1);
    px[a][0] = alignDown(static_cast<int>(std::floor(from)) - margin, align);
    px[a][1] = alignUp(static_cast<int>(std::ceil(to)) + margin, align);
    px[a][0] = std::clamp(px[a][0], 0, static_cast<int>(size[a]));
    px[a][1] = std::clamp(px[a][1], 0, static_cast<int>(size[a]));
  }
  return PixelRect{px[0][0], px[1][0], px[0][1], px[1][1]};
}

bool floorCovers(const CameraView& camera, int width, int height, double floorHeight,
                 const Eigen::Vector2d& centre, double half, const PixelRect& rect) {
  if (rect.empty() || !(camera.position.z() > floorHeight)) return false;
  const Mat4 viewProjection =
      camera.projectionMatrix(static_cast<double>(width) / height) * camera.viewMatrix();
  const Mat4 inverse = viewProjection.inverse();
  const double inner = half * (1 - 1e-6);  // rounding of the square's corners
  // The window depth (0 at the near plane, 1 at the far one) of the floor under pixel position
  // (x, y); none where that ray misses the square.
  auto floorDepth = [&](double x, double y) -> std::optional<double> {
    const double nx = 2.0 * x / width - 1, ny = 2.0 * y / height - 1;
    const Vec4 a = inverse * Vec4(nx, ny, -1, 1), b = inverse * Vec4(nx, ny, 1, 1);
    const Vec3 from = a.head<3>() / a.w(), to = b.head<3>() / b.w();
    const Vec3 ray = to - from;
    if (!(ray.z() < 0)) return std::nullopt;  // at or above the horizon
    const Vec3 hit = from + ray * ((floorHeight - from.z()) / ray.z());
    if (!(std::abs(hit.x() - centre.x()) < inner && std::abs(hit.y() - centre.y()) < inner)) {
      return std::nullopt;
    }
    const Vec4 c = viewProjection * Vec4(hit.x(), hit.y(), hit.z(), 1);
    return c.z() / c.w() * 0.5 + 0.5;
  };
  for (const int x : {rect.x0 - 1, rect.x1 + 1}) {
    for (const int y : {rect.y0 - 1, rect.y1 + 1}) {
      const std::optional<double> z = floorDepth(x, y), zx = floorDepth(x + 1, y),
                                  zy = floorDepth(x, y + 1);
      if (!z || !zx || !zy) return false;
      // Inside the near and far planes after the floor's polygon offset (the factor times the
      // depth slope, which is affine and so the same over the whole floor, plus the units,
      // each at most 2^-20), with half as much again to spare.
      const double slope = std::max(std::abs(*zx - *z), std::abs(*zy - *z));
      const double offset = kFloorOffsetFactor * slope + kFloorOffsetUnits * std::ldexp(1.0, -20);
      if (!(*z > 0 && *z + 1.5 * offset < 1)) return false;
    }
  }
  return true;
}

Eigen::AlignedBox3d RedrawTracker::meshBox(const DrawMesh& mesh) {
  auto compute = [&mesh] {
    Eigen::AlignedBox3d box;
    for (const Vec3& v : mesh.mesh->vertices) box.extend(v);
    return box;
  };
  if (mesh.transient || !mesh.key) return compute();
  auto it = meshes_.find(mesh.key);
  if (it == meshes_.end()) it = meshes_.emplace(mesh.key, MeshBounds{mesh.mesh, compute()}).first;
  return it->second.box;
}

bool RedrawTracker::reach(const Frame& frame, std::size_t i, double shadowReach,
                          std::vector<PixelRect>& rects) const {
  const std::optional<PixelRect>& body = frame.screen[i];
  if (!body) return false;
  rects.push_back(*body);
  const DrawInstance& inst = frame.instances[i];
  if (!inst.castsShadow || inst.surface == Surface::unlit) return true;
  if (frame.ground &&
      !shadowOn(frame, i, shadowReach, *frame.ground, *frame.ground, std::nullopt, rects)) {
    return false;
  }
  for (std::size_t j = 0; j < frame.boxes.size(); ++j) {
    const Eigen::AlignedBox3d& receiver = frame.boxes[j];
    if (!shadowOn(frame, i, shadowReach, receiver.min().z(), receiver.max().z(), j, rects)) {
      return false;
    }
  }
  return true;
}

bool RedrawTracker::shadowOn(const Frame& frame, std::size_t i, double shadowReach, double z0,
                             double z1, std::optional<std::size_t> receiver,
                             std::vector<PixelRect>& rects) const {
  // The shadow: the box swept away from the sun, widened by shadowReach, where it meets a
  // receiver (the floor, or any instance's box, this one included). Per receiver that is the
  // part of the sweep within the receiver's height range: the hull of the box moved by the
  // first and by the last distance at which it overlaps that range.
  const Vec3 toSun = frame.sun.normalized();
  if (toSun.z() < kMinSunElevation) return false;
  const Eigen::AlignedBox3d& box = frame.boxes[i];
  z0 -= shadowReach;
  z1 += shadowReach;
  const double from = std::max(0.0, (box.min().z() - z1) / toSun.z());
  const double to = (box.max().z() - z0) / toSun.z();
  if (to < from) return true;
  const Vec3 near = toSun * from, far = toSun * to;
  if (receiver) {
    Eigen::AlignedBox3d swept(box.min() - far, box.max() - near);
    swept.extend(Vec3(box.min() - near)).extend(Vec3(box.max() - far));
    const Vec3 grow = Vec3::Constant(shadowReach);
    const Eigen::AlignedBox3d& other = frame.boxes[*receiver];
    const Eigen::AlignedBox3d wide(other.min() - grow, other.max() + grow);
    if (!swept.intersects(wide)) return true;
  }
  const std::array<Vec3, 8>& corners = frame.corners[i];
  std::array<Vec3, 16> part;
  for (std::size_t k = 0; k < 8; ++k) {
    part[k] = corners[k] - near;
    part[k + 8] = corners[k] - far;
  }
  std::optional<PixelRect> r = projectPoints(frame.viewProjection, part, shadowReach, width_,
                                             height_, kMarginPixels, kAlignPixels);
  if (!r) return false;
  // A shadow on an instance shows only where that instance is drawn.
  if (receiver && frame.screen[*receiver]) r = r->intersection(*frame.screen[*receiver]);
  if (!r->empty()) rects.push_back(*r);
  return true;
}

RedrawTracker::Frame RedrawTracker::frameOf(const DrawList& list, const ShadowProjection& shadow) {
  Frame now;
  now.camera = list.camera;
  now.sun = list.sunDirection;
  now.light = list.light;
  now.drape = list.drape.get();
  now.ground = list.groundHeight;
  now.fadeStart = list.groundFadeStart;
  now.fadeEnd = list.groundFadeEnd;
  now.shadow = shadow.viewProjection;
  now.instances = list.instances;
  now.viewProjection = list.camera.projectionMatrix(static_cast<double>(width_) / height_) *
                       list.camera.viewMatrix();
  for (const DrawInstance& inst : list.instances) {
    now.transforms.push_back(gpuTransform(inst.model));
    const DrawMesh& mesh = list.meshes[static_cast<std::size_t>(inst.mesh)];
    const Eigen::AlignedBox3d box = meshBox(mesh);
    std::array<Vec3, 8> corners;
    Eigen::AlignedBox3d world;
    for (int k = 0; k < 8; ++k) {
      const Vec3 c = box.isEmpty()
                         ? Vec3::Zero()
                         : Vec3(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
      corners[static_cast<std::size_t>(k)] = (inst.model * Vec4(c.x(), c.y(), c.z(), 1)).head<3>();
      world.extend(corners[static_cast<std::size_t>(k)]);
    }
    now.corners.push_back(corners);
    now.boxes.push_back(world);
    now.screen.push_back(projectPoints(now.viewProjection, corners, 0, width_, height_,
                                       kMarginPixels, kAlignPixels));
    now.keys.push_back(mesh.transient ? nullptr : mesh.key);
  }
  return now;
}

void RedrawTracker::findFloorShadows(const Frame& now, double shadowReach) {
  floorShadows_.reset();
  if (!now.ground) return;
  std::vector<PixelRect> rects;
  bool bounded = true;
  for (std::size_t i = 0; i < now.instances.size() && bounded; ++i) {
    const DrawInstance& inst = now.instances[i];
    if (!inst.castsShadow || inst.surface == Surface::unlit) continue;
    bounded = shadowOn(now, i, shadowReach, *now.ground, *now.ground, std::nullopt, rects);
  }
  if (bounded) floorShadows_ = coverWithFewPieces(std::move(rects));
}

bool RedrawTracker::sameView(const Frame& a, const Frame& b) {
  return sameCamera(a.camera, b.camera) && a.sun == b.sun && a.light == b.light &&
         a.drape == b.drape && a.ground == b.ground && a.fadeStart == b.fadeStart &&
         a.fadeEnd == b.fadeEnd && a.shadow == b.shadow;
}

std::optional<std::vector<PixelRect>> RedrawTracker::changedRegion(const Frame& before,
                                                                   const Frame& now,
                                                                   double shadowReach) {
  // Instances are matched by id (bodies appear and leave), those without one by order.
  auto keys = [](const Frame& f) {
    std::map<std::pair<int, int>, std::size_t> byKey;
    int unnamed = 0;
    for (std::size_t i = 0; i < f.instances.size(); ++i) {
      const int id = f.instances[i].id;
      byKey.emplace(std::make_pair(id, id < 0 ? unnamed++ : 0), i);
    }
    return byKey;
  };
  const auto was = keys(before), is = keys(now);
  std::vector<PixelRect> rects, casters;
  bool bounded = true;
  for (const auto& [key, i] : is) {
    if (!bounded) break;
    const auto old = was.find(key);
    if (old != was.end()) {
      const std::size_t j = old->second;
      if (now.keys[i] && before.keys[j] == now.keys[i] &&
          sameInstance(before.instances[j], before.transforms[j], now.instances[i],
                       now.transforms[i])) {
        continue;
      }
      // Where it and its shadow were (on that frame's receivers).
      bounded = reach(before, j, shadowReach, rects);
      addCaster(before, j, casters);
    }
    // Where they are (on this frame's).
    bounded = bounded && reach(now, i, shadowReach, rects);
    addCaster(now, i, casters);
  }
  for (const auto& [key, j] : was) {  // gone since
    if (bounded && !is.contains(key)) {
      bounded = reach(before, j, shadowReach, rects);
      addCaster(before, j, casters);
    }
  }
  std::erase_if(rects, [](const PixelRect& r) { return r.empty(); });
  if (!bounded) return std::nullopt;
  shadowRegion_ = coverWithFewPieces(std::move(casters));
  return coverWithFewPieces(std::move(rects));
}

std::optional<std::vector<PixelRect>> RedrawTracker::update(const DrawList& list,
                                                            const ShadowProjection& shadow,
                                                            double shadowReach) {
  shadowRegion_.clear();
  Frame now = frameOf(list, shadow);
  // Where any caster's shadow lookups can reach the floor, this frame.
  findFloorShadows(now, shadowReach);
  std::optional<std::vector<PixelRect>> region;
  if (last_ && sameView(*last_, now)) region = changedRegion(*last_, now, shadowReach);
  last_ = std::move(now);
  return region;
}

std::vector<PixelRect> coverWithFewPieces(std::vector<PixelRect> rects) {
  std::vector<PixelRect> merged = mergeCheap(std::move(rects));
  std::vector<PixelRect> pieces = disjointCover(merged);
  if (pieces.size() <= kMaxPieces) return pieces;
  return mergeOverlapping(std::move(merged));
}

std::vector<PixelRect> mergeOverlapping(std::vector<PixelRect> rects) {
  // Until no two overlap: a pixel is then drawn once, and the rectangles stay few.
  return mergePairs(std::move(rects),
                    [](const PixelRect& a, const PixelRect& b) { return a.intersects(b); });
}

std::vector<PixelRect> mergeCheap(std::vector<PixelRect> rects) {
  // Two rectangles are drawn as their bounding box when that is no larger than the two (they
  // overlap or line up). Merging more loosely (up to 1.25 times their area plus 4,096 pixels)
  // saved passes but drew more: on the whole crosses clip 29 % of the pixels instead of 23 %,
  // and 19 instead of 20.6 frames/s (two interleaved runs each).
  return mergePairs(std::move(rects), [](const PixelRect& a, const PixelRect& b) {
    PixelRect both = a;
    both.unite(b);
    return both.area() <= a.area() + b.area();
  });
}

namespace {

// Appends to `out` rectangles that do not overlap and cover r minus every rectangle of `taken`.
void subtract(const PixelRect& r, std::span<const PixelRect> taken, std::vector<PixelRect>& out) {
  if (r.empty()) return;
  // Each cut leaves at most four bands.
  std::vector<PixelRect> pieces(1, r), rest;
  for (const PixelRect& q : taken) {
    rest.clear();
    for (const PixelRect& p : pieces) {
      if (!p.intersects(q)) {
        rest.push_back(p);
        continue;
      }
      const int y0 = std::max(p.y0, q.y0), y1 = std::min(p.y1, q.y1);
      if (p.y0 < y0) rest.push_back(PixelRect{p.x0, p.y0, p.x1, y0});  // below q
      if (y1 < p.y1) rest.push_back(PixelRect{p.x0, y1, p.x1, p.y1});  // above q
      if (p.x0 < q.x0) rest.push_back(PixelRect{p.x0, y0, q.x0, y1});  // left of q
      if (q.x1 < p.x1) rest.push_back(PixelRect{q.x1, y0, p.x1, y1});  // right of q
    }
    pieces.swap(rest);
    if (pieces.empty()) return;
  }
  out.insert(out.end(), pieces.begin(), pieces.end());
}

}  // namespace

std::vector<PixelRect> disjointCover(std::span<const PixelRect> rects) {
  std::vector<PixelRect> out;
  for (const PixelRect& r : rects) {
    // r minus every rectangle already taken (the loop appends to `out` only after reading it).
    std::vector<PixelRect> pieces;
    subtract(r, out, pieces);
    out.insert(out.end(), pieces.begin(), pieces.end());
  }
  return out;
}

RectSplit splitRect(const PixelRect& r, std::span<const PixelRect> cover) {
  RectSplit split;
  std::vector<PixelRect> parts;
  for (const PixelRect& c : cover) {
    const PixelRect part = r.intersection(c);
    if (!part.empty()) parts.push_back(part);
  }
  split.inside = disjointCover(parts);
  subtract(r, split.inside, split.outside);
  return split;
}

void RedrawTracker::addCaster(const Frame& frame, std::size_t i,
                              std::vector<PixelRect>& texels) const {
  const DrawInstance& inst = frame.instances[i];
  if (shadowMapSize_ <= 0 || !inst.castsShadow || inst.surface == Surface::unlit) return;
  // The shadow map's clip space maps to its texels as the camera's does to pixels; the
  // projection is orthographic (w = 1), so the bound always exists.
  const std::optional<PixelRect> r =
      projectPoints(frame.shadow, frame.corners[i], 0, shadowMapSize_, shadowMapSize_,
                    kMarginPixels, kAlignPixels);
  if (r && !r->empty()) texels.push_back(*r);
}

bool RedrawTracker::mayCast(std::size_t instance, const PixelRect& texels) const {
  if (!last_ || instance >= last_->corners.size() || shadowMapSize_ <= 0) return true;
  const std::optional<PixelRect> r = projectPoints(
      last_->shadow, last_->corners[instance], 0, shadowMapSize_, shadowMapSize_, kMarginPixels, 1);
  return !r || r->intersects(texels);
}

bool RedrawTracker::maySee(std::size_t instance) const {
  if (!last_ || instance >= last_->corners.size()) return true;
  // The corners in clip space: wholly behind the eye (w <= 0) nothing is drawn; with some
  // behind, the projection is unbounded (kept); all in front, the box's projection is the box
  // of the corners' projections, compared with the frame widened by the margin.
  int behind = 0;
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (const Vec3& p : last_->corners[instance]) {
    const Vec4 c = last_->viewProjection * Vec4(p.x(), p.y(), p.z(), 1);
    if (!(c.w() > 1e-9)) {
      ++behind;
      continue;
    }
    for (int a = 0; a < 2; ++a)
      lo[a] = std::min(lo[a], c[a] / c.w()), hi[a] = std::max(hi[a], c[a] / c.w());
  }
  if (behind == 8) return false;
  if (behind > 0) return true;
  const double size[2] = {static_cast<double>(width_), static_cast<double>(height_)};
  for (int a = 0; a < 2; ++a) {
    const double margin = 2.0 * kMarginPixels / size[a];  // in NDC, which spans 2
    if (hi[a] < -1 - margin || lo[a] > 1 + margin) return false;
  }
  return true;
}

bool RedrawTracker::mayCover(std::size_t instance, const PixelRect& rect) const {
  if (!last_ || instance >= last_->corners.size()) return true;
  const std::optional<PixelRect> r = projectPoints(last_->viewProjection, last_->corners[instance],
                                                   0, width_, height_, kMarginPixels, 1);
  return !r || r->intersects(rect);
}

}  // namespace vf
