// Which part of a frame can differ from the frame before it, so that the renderer redraws
// only that part and keeps the rest of its targets from the last frame (GL-free, testable).
//
// Why that is exact: a pixel's value is a function of what is drawn over it (the geometry
// covering its samples, the floor, the sky along its ray) and of the shadow-map texels its
// shadow lookups read; nothing else (no screen-space effect reads a neighbour, and the
// derivatives of the floor's grid come from the same 2x2 quad either way). When the camera, the
// light, the floor and the shadow map's projection are the same, a pixel can only change where
// an instance that changed (moved as the GPU sees it, i.e. in single precision; recoloured;
// appeared; left; a trail) covered or now covers it, or where a receiver's shadow lookups reach
// the shadow-map texels such an instance covered or covers. The first is inside the instance's
// mesh box; the second inside that box swept away from the sun, widened by how far a lookup
// reaches from its surface point, where the sweep crosses the height range of a receiver (the
// floor, or an instance's box, and then only where that instance is drawn: inside its own mesh
// box's rectangle). Each part is projected to a screen rectangle; everything outside them is
// provably unchanged. Whenever a premise fails (or a bound reaches behind the camera) the whole
// frame is redrawn. tests/render/incremental_render_test.cpp compares scene clips drawn both
// ways byte for byte.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "render/camera.h"
#include "render/draw_data.h"

namespace vf {

// Pixels [x0, x1) x [y0, y1) of a frame, rows counted from the bottom as GL counts them.
struct PixelRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
  long long area() const { return empty() ? 0 : static_cast<long long>(x1 - x0) * (y1 - y0); }
  // Grows this rectangle to hold `other` too (an empty one adds nothing).
  void unite(const PixelRect& other);
  bool intersects(const PixelRect& other) const;
  // The pixels in both (possibly empty).
  PixelRect intersection(const PixelRect& other) const;
  bool operator==(const PixelRect&) const = default;
};

// The rectangle of a width x height frame that holds the projection through `viewProjection`
// of the convex hull of `points`, each widened to a cube of half-side `grow` (m), itself
// widened by `margin` pixels, aligned outwards to multiples of `align` and clipped to the frame;
// none when a corner of those cubes lies at or behind the eye (the projection is then
// unbounded).
std::optional<PixelRect> projectPoints(const Mat4& viewProjection, std::span<const Vec3> points,
                                       double grow, int width, int height, int margin, int align);

// Rectangles merged until no two overlap (each merged pair replaced by its bounding box).
std::vector<PixelRect> mergeOverlapping(std::vector<PixelRect> rects);
// Rectangles merged pairwise into their bounding box wherever that adds no area (they overlap
// or line up): fewer passes for the same pixels.
std::vector<PixelRect> mergeCheap(std::vector<PixelRect> rects);
// Rectangles that do not overlap and cover the union of `rects`: the disjoint pieces of the
// cheaply merged ones, or, when those would be more than kMaxPieces (48) passes, the bounding
// boxes of overlapping groups (more pixels, fewer passes).
std::vector<PixelRect> coverWithFewPieces(std::vector<PixelRect> rects);
// Rectangles that do not overlap and cover exactly the union of `rects`.
std::vector<PixelRect> disjointCover(std::span<const PixelRect> rects);
// `r` cut along `cover`: `inside`, rectangles that do not overlap and cover exactly the part of
// r in the union of `cover`, and `outside`, likewise the rest of r.
struct RectSplit {
  std::vector<PixelRect> inside, outside;
};
RectSplit splitRect(const PixelRect& r, std::span<const PixelRect> cover);

// The floor is pushed back in depth by glPolygonOffset(factor, units), so that a terrain at
// its level wins (render/gl/render_passes.cpp); floorCovers() allows for exactly this offset.
constexpr float kFloorOffsetFactor = 1.0f;
constexpr float kFloorOffsetUnits = 4.0f;

// Whether the floor square (z = floorHeight, x and y within `half` of `centre`) covers every
// sample of the pixels of `rect` seen by `camera` in a width x height frame, inside the near
// and far planes also after the floor's polygon offset: then no sample there is left to the
// sky. The floor's part in front of the eye projects to a convex region, so it covers the
// rectangle when it covers its corners (taken a pixel further out).
bool floorCovers(const CameraView& camera, int width, int height, double floorHeight,
                 const Eigen::Vector2d& centre, double half, const PixelRect& rect);

class RedrawTracker {
 public:
  // For frames of width x height pixels and, when shadowMapSize > 0, a square shadow map of
  // that many texels a side (see shadowMapRegion()).
  RedrawTracker(int width, int height, int shadowMapSize = 0)
      : width_(width), height_(height), shadowMapSize_(shadowMapSize) {}

  // Takes `list` (whose shadow map is fitted as `shadow`) as the new current frame and returns
  // the parts of the picture that can differ from the previous frame given, as rectangles
  // that do not overlap (none: nothing changed); none at all for the whole picture (the first
  // frame; a changed camera, light, floor, shadow projection or instance list; a bound that
  // reaches behind the eye). `shadowReach` (m): how far from its surface point a receiver's
  // shadow lookups can reach (normal offset plus filter footprint).
  std::optional<std::vector<PixelRect>> update(const DrawList& list, const ShadowProjection& shadow,
                                               double shadowReach);

  // After an update() that returned rectangles: the shadow-map texels that can differ from
  // the last frame's map (where a caster that changed lay or lies), as rectangles that do not
  // overlap, rows from the bottom (texel (0, 0) is the map's origin). Empty without a map size.
  const std::vector<PixelRect>& shadowMapRegion() const { return shadowRegion_; }

  // After any update(): where on the floor of the current frame a shadow lookup can read a
  // shadow-map texel that some caster covers, as rectangles that do not overlap; elsewhere
  // every lookup reads the cleared map, i.e. the floor is fully lit. None: unknown (no floor,
  // the sun too low, a bound behind the eye).
  const std::optional<std::vector<PixelRect>>& floorShadows() const { return floorShadows_; }

  // Whether instance i of the current frame can cover pixels of `rect`: false only when its
  // bounding box provably projects outside it.
  bool mayCover(std::size_t instance, const PixelRect& rect) const;
  // The same in the shadow map: whether instance i can write texels of `texels` (rows from
  // the bottom) when the map is drawn with the current frame's shadow projection.
  bool mayCast(std::size_t instance, const PixelRect& texels) const;
  // Whether instance i of the current frame can cover any pixel of the frame: false only when
  // its bounding box lies wholly behind the eye, or wholly in front of it and projects
  // beyond one edge of the frame (by more than the margin).
  bool maySee(std::size_t instance) const;

 private:
  struct Frame {
    CameraView camera;
    Vec3 sun = Vec3::Zero();
    LightColors light;
    const DrapeImage* drape = nullptr;
    std::optional<double> ground;
    double fadeStart = 0, fadeEnd = 0;
    Mat4 shadow = Mat4::Zero();
    Mat4 viewProjection = Mat4::Identity();
    std::vector<DrawInstance> instances;
    std::vector<GpuTransform> transforms;          // per instance, computed once
    std::vector<const void*> keys;                 // per instance; null for a transient mesh
    std::vector<std::array<Vec3, 8>> corners;      // per instance: its mesh box, in the world
    std::vector<Eigen::AlignedBox3d> boxes;        // per instance: the corners' bounding box
    std::vector<std::optional<PixelRect>> screen;  // per instance: where it can be drawn
  };
  struct MeshBounds {
    std::shared_ptr<const TriMesh> pin;  // keeps the key's owner alive: keys are not reused
    Eigen::AlignedBox3d box;             // mesh frame
  };

  Eigen::AlignedBox3d meshBox(const DrawMesh& mesh);
  // update()'s parts: what of the list a later frame is compared with, with each instance's
  // bounds; floorShadows_ for that frame; whether two frames share camera, light, floor and
  // shadow map (else everything is redrawn); and the rectangles that can differ between two
  // such frames, with shadowRegion_ (none when a bound fails).
  Frame frameOf(const DrawList& list, const ShadowProjection& shadow);
  void findFloorShadows(const Frame& now, double shadowReach);
  static bool sameView(const Frame& a, const Frame& b);
  std::optional<std::vector<PixelRect>> changedRegion(const Frame& before, const Frame& now,
                                                      double shadowReach);
  // Adds to `rects` the screen rectangles instance i of `frame` covers and (if it casts a
  // shadow) those where its shadow can fall on that frame's receivers; false when a bound
  // reaches behind the eye or the sun is too low to bound the shadow.
  bool reach(const Frame& frame, std::size_t i, double shadowReach,
             std::vector<PixelRect>& rects) const;

  // Adds to `rects` the screen rectangle where instance i's shadow lookups can reach receivers
  // in heights [z0, z1]: instance `receiver`'s box (then only where it is drawn), or the floor
  // (none). False when a bound reaches behind the eye or the sun is too low.
  bool shadowOn(const Frame& frame, std::size_t i, double shadowReach, double z0, double z1,
                std::optional<std::size_t> receiver, std::vector<PixelRect>& rects) const;

  // Adds to `texels` the shadow-map rectangle instance i of `frame` covers, if it casts one.
  void addCaster(const Frame& frame, std::size_t i, std::vector<PixelRect>& texels) const;

  int width_, height_, shadowMapSize_;
  std::optional<Frame> last_;
  std::vector<PixelRect> shadowRegion_;
  std::optional<std::vector<PixelRect>> floorShadows_;
  std::unordered_map<const void*, MeshBounds> meshes_;  // lookup only, never iterated
};

}  // namespace vf
