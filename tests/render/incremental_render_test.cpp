// Incremental frames (render/redraw_region.*): the renderer redraws only the part of a frame
// that can have changed since the last one and keeps the rest.
//   - the oracle is the renderer itself drawing every frame whole: scene clips drawn both ways
//     give the same bytes in every frame, while the incremental renderer provably skipped
//     most of the picture (otherwise the comparison would prove nothing); the comparison
//     itself catches a different picture (the control: the whole-frame renderer undithered);
//   - the region is checked against independent geometry: it holds where a moved body was and
//     is, and where the floor receives its shadow before and after (the ray from its centre
//     away from the sun meets the floor), and it is not the whole picture;
//   - bodies that appear or leave redraw only their place (matched by body id); every premise
//     that fails (camera, light, floor fade, a bound behind the eye) redraws all;
//   - the merging of rectangles covers every changed pixel exactly once, also past the cap.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/redraw_region.h"
#include "render/scene_playback.h"
#include "render_test_util.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

constexpr int kWidth = 320, kHeight = 180;

struct ClipComparison {
  int frames = 0;
  int differing = 0;       // frames whose bytes differ between the two renderers
  double meanRedrawn = 0;  // share of pixels the first renderer drew, per frame
  int untouched = 0;       // frames it did not draw at all
  // Shares of pixels the first renderer drew with the cheaper programs, per frame.
  double meanUnshadowedFloor = 0, meanSkyFree = 0;
};

// An OSMesa context, made current, and the default settings at the tests' size.
std::unique_ptr<gl::Context> currentContext() {
  auto context = gl::createContext(gl::Backend::osmesa);
  context->makeCurrent();
  return context;
}
gl::RenderSettings testSettings() {
  gl::RenderSettings settings;
  settings.width = kWidth;
  settings.height = kHeight;
  settings.shaderDir = gl::findShaderDir();
  return settings;
}

// Draws frames 0 .. last of a scene with two renderers: the first with the default settings,
// the second with those `change` makes, and counts the frames whose bytes differ.
ClipComparison compareClip(SceneSpec spec, int last,
                           const std::function<void(gl::RenderSettings&)>& change,
                           int samples = 4) {
  spec.output.width = kWidth;
  spec.output.height = kHeight;
  const auto context = currentContext();
  gl::RenderSettings settings = testSettings();
  settings.samples = samples;
  gl::Renderer first(*context, settings);
  change(settings);
  gl::Renderer second(*context, settings);

  ScenePlayback playback(spec, kWidth, kHeight);
  playback.simulate(false);
  ClipComparison c;
  for (int k = 0; k <= last && k < playback.frameCount(); ++k) {
    const DrawList list = playback.drawList(k);
    const Image a = first.render(list);
    const Image b = second.render(list);
    if (!settings.incremental) {
      EXPECT_EQ(second.redrawnFraction(), 1.0);
    }
    if (a.rgb != b.rgb) ++c.differing;
    c.meanRedrawn += first.redrawnFraction();
    c.meanUnshadowedFloor += first.unshadowedFloorFraction();
    c.meanSkyFree += first.skyFreeFraction();
    if (first.redrawnFraction() == 0) ++c.untouched;
    ++c.frames;
  }
  c.meanRedrawn /= c.frames;
  c.meanUnshadowedFloor /= c.frames;
  c.meanSkyFree /= c.frames;
  return c;
}

// The second renderer of the incremental tests: every frame whole.
void wholeFrames(gl::RenderSettings& s) { s.incremental = false; }

// The second renderer of the hidden-work tests: the same, doing every lookup everywhere.
void everyLookup(gl::RenderSettings& s) { s.skipHiddenWork = false; }

std::string scenePath(const std::string& name) {
  return std::string(VOXFALL_SOURCE_DIR) + "/scenes/" + name;
}

// The cliff's rock seen by the automatic camera of [cameras.overview] (the scene's own chase
// camera moves, so every one of its frames is drawn whole).
SceneSpec cliffOverview() {
  SceneSpec spec = loadScene(scenePath("cliff.toml"));
  selectCamera(spec, "overview");
  return spec;
}

// Ten blocks thrown across the view, drawn with trails (transient meshes, redrawn every frame)
// and as markers while smaller than 12 pixels (unlit, no shadow).
SceneSpec blocksWithTrails() {
  SceneSpec spec = loadScene(scenePath("blocks.toml"));
  spec.camera.trailSeconds = 0.5;
  spec.camera.minPixels = 12;
  return spec;
}

TEST(IncrementalRender, TheComparisonCatchesADifferentPicture) {
  // The control: without the dither the whole-frame renderer draws other bytes, and every
  // frame must be counted as differing (the dither changes most pixels by one step).
  const ClipComparison c = compareClip(loadScene(scenePath("cubes.toml")), 10, [](auto& s) {
    s.incremental = false;
    s.dither = false;
  });
  EXPECT_EQ(c.differing, c.frames);
}

TEST(IncrementalRender, CubesClipIsByteIdenticalToWholeFrames) {
  const ClipComparison c = compareClip(loadScene(scenePath("cubes.toml")), 60, wholeFrames);
  EXPECT_EQ(c.frames, 61);
  EXPECT_EQ(c.differing, 0);
  // Two cubes in a 320x180 view: measured about a tenth redrawn per frame; a half means the
  // region grew to most of the picture and the test no longer shows the skipping is exact.
  EXPECT_LT(c.meanRedrawn, 0.5);
  EXPECT_GT(c.untouched, 0) << "the cubes come to rest before frame 60";
}

TEST(IncrementalRender, SupersampledFramesAreByteIdenticalToWholeFrames) {
  // 64 samples is more than llvmpipe offers: the renderer falls back to 2x2 supersampling, whose
  // scene target has twice the output's pixels per axis (the scissor is scaled for it).
  const ClipComparison c = compareClip(loadScene(scenePath("cubes.toml")), 30, wholeFrames, 64);
  EXPECT_EQ(c.differing, 0);
  EXPECT_LT(c.meanRedrawn, 0.5);
}

TEST(IncrementalRender, CrossesReleasedOneByOneAreByteIdenticalToWholeFrames) {
  // 26 non-convex bodies released in turn (instances appear), falling onto each other (bodies
  // receive each other's shadows).
  const ClipComparison c = compareClip(loadScene(scenePath("crosses.toml")), 150, wholeFrames);
  EXPECT_EQ(c.differing, 0);
  EXPECT_LT(c.meanRedrawn, 0.5);
}

TEST(IncrementalRender, ARockOnTerrainIsByteIdenticalToWholeFrames) {
  // The cliff's heightfield (a terrain instance: slope colours, smooth normals) receives the
  // rock's shadow.
  const SceneSpec spec = cliffOverview();
  const ClipComparison c = compareClip(spec, 90, wholeFrames);
  EXPECT_EQ(c.differing, 0);
  EXPECT_LT(c.meanRedrawn, 0.5);
}

TEST(IncrementalRender, ThrownBlocksWithTrailsAreByteIdenticalToWholeFrames) {
  const SceneSpec spec = blocksWithTrails();
  const ClipComparison c = compareClip(spec, 90, wholeFrames);
  EXPECT_EQ(c.differing, 0);
  EXPECT_LT(c.meanRedrawn, 0.9);
}

// Hidden work (RenderSettings::skipHiddenWork): the floor is shaded without shadow lookups
// where no caster's shadow can reach it, and presented without the sky where it covers every
// sample. The oracle is the same renderer doing that work everywhere: the same bytes in every
// frame, while the cheaper programs drew a good share of the pixels (else the comparison would
// show nothing; the bounds are about half the measured shares, of the frame's pixels).
struct HiddenWorkClip {
  const char* name;
  SceneSpec (*scene)();
  int last;
  int samples;  // 64: more than llvmpipe has, supersampling
  double minUnshadowedFloor, minSkyFree;
};

class HiddenWork : public ::testing::TestWithParam<HiddenWorkClip> {};

TEST_P(HiddenWork, SkippingItChangesNoByte) {
  const HiddenWorkClip& clip = GetParam();
  const ClipComparison c = compareClip(clip.scene(), clip.last, everyLookup, clip.samples);
  EXPECT_EQ(c.differing, 0);
  EXPECT_GT(c.meanUnshadowedFloor, clip.minUnshadowedFloor);
  EXPECT_GT(c.meanSkyFree, clip.minSkyFree);
}

SceneSpec cubes() { return loadScene(scenePath("cubes.toml")); }
SceneSpec crosses() { return loadScene(scenePath("crosses.toml")); }

INSTANTIATE_TEST_SUITE_P(
    Clips, HiddenWork,
    ::testing::Values(
        // Measured 2.1 % and 10 % (of 12 % redrawn): the floor beside the cubes and their
        // shadows, and all of it below the horizon.
        HiddenWorkClip{"cubes", cubes, 60, 4, 0.01, 0.05},
        // Measured 2.7 % and 16 % (of 17 % redrawn).
        HiddenWorkClip{"crosses", crosses, 150, 4, 0.01, 0.08},
        // Measured 4.1 % and 20 % (of 24 % redrawn).
        HiddenWorkClip{"supersampled", cubes, 30, 64, 0.02, 0.1},
        // Measured 12 % and 1.9 % (of 26 % redrawn).
        HiddenWorkClip{"thrown_blocks", blocksWithTrails, 90, 4, 0.06, 0.01},
        // The terrain is itself a caster whose shadow can reach all the floor in view, and
        // hides it: nothing may be skipped (measured 0 % and 0.1 %), so this guards that case.
        HiddenWorkClip{"rock_on_terrain", cliffOverview, 90, 4, -1, -1}),
    [](const ::testing::TestParamInfo<HiddenWorkClip>& info) { return info.param.name; });

// A box on a floor at z = 0 seen by a fixed camera; the sun as DrawList's default.
DrawList boxOnFloor(const Vec3& at) {
  static const auto shape = test::boxShape(Vec3(0.25, 0.25, 0.25));
  DrawListBuilder builder(CameraSpec{}, 0.0, kWidth, kHeight, 30);
  const std::vector<BodyView> bodies = {test::body(shape, at)};
  builder.observe(bodies);
  DrawList list = builder.build(bodies, 0);
  list.camera.position = Vec3(6, -8, 4);
  list.camera.lookAt = Vec3(0, 0, 0.5);
  list.camera.nearPlane = 0.1;
  list.camera.farPlane = 100;
  list.casterCentre = Vec3::Zero();
  list.casterRadius = 3;
  // The builder derives these from its framing, which follows the box: hold them still.
  list.sunDirection = Vec3(0.3, -0.4, 0.87).normalized();
  list.groundFadeStart = 20;
  list.groundFadeEnd = 60;
  return list;
}

ShadowProjection shadowOf(const DrawList& list) {
  return fitShadowProjection(list.sunDirection, list.casterCentre, list.casterRadius, 0, 2048);
}

// The pixel (GL orientation, row 0 at the bottom) where world point p appears.
Eigen::Vector2d pixelOf(const DrawList& list, const Vec3& p) {
  const Mat4 vp = list.camera.projectionMatrix(static_cast<double>(kWidth) / kHeight) *
                  list.camera.viewMatrix();
  const Vec4 c = vp * Vec4(p.x(), p.y(), p.z(), 1);
  return Eigen::Vector2d((c.x() / c.w() * 0.5 + 0.5) * kWidth,
                         (c.y() / c.w() * 0.5 + 0.5) * kHeight);
}

bool contains(const PixelRect& r, const Eigen::Vector2d& p) {
  return p.x() >= r.x0 && p.x() < r.x1 && p.y() >= r.y0 && p.y() < r.y1;
}

// Where the ray from p away from the sun meets the floor z = 0.
Vec3 shadowOnFloor(const DrawList& list, const Vec3& p) {
  const Vec3 toSun = list.sunDirection.normalized();
  return p - toSun * (p.z() / toSun.z());
}

// A rolling 200 x 200 m grid of 1 m cells (80,000 triangles: drawn as 16 tiles, see
// kTerrainTileTriangles), smooth normals, and its height.
double hillHeight(double x, double y) { return 1.5 * std::sin(0.21 * x) * std::cos(0.17 * y); }
std::shared_ptr<const TriMesh> hills() {
  auto mesh = std::make_shared<TriMesh>();
  constexpr int kCells = 200;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) mesh->vertices.push_back(Vec3(i, j, hillHeight(i, j)));
  auto at = [](int i, int j) { return static_cast<std::uint32_t>(j * (kCells + 1) + i); };
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      mesh->triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh->triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return mesh;
}

// A builder of frames over the hills (one for a clip: its terrain tiles are the same meshes
// from frame to frame, as in a playback).
std::unique_ptr<DrawListBuilder> hillsBuilder(
    const std::shared_ptr<const TriMesh>& terrain,
    const std::shared_ptr<const std::vector<Vec3>>& normals) {
  auto builder = std::make_unique<DrawListBuilder>(CameraSpec{}, std::nullopt, kWidth, kHeight, 30);
  builder->setTerrain(terrain, normals);
  return builder;
}

// Frame k of the builder: a 3 m box over the hills at (x, y), seen from a fixed camera, the
// shadow map fitted to the whole terrain.
DrawList boxOverHills(DrawListBuilder& builder, int k, double x, double y) {
  static const auto shape = test::boxShape(Vec3(1.5, 1.5, 1.5));
  const std::vector<BodyView> bodies = {test::body(shape, Vec3(x, y, hillHeight(x, y) + 2.5))};
  builder.observe(bodies);
  DrawList list = builder.build(bodies, k);
  list.camera.position = Vec3(100, -90, 110);
  list.camera.lookAt = Vec3(100, 90, 0);
  list.camera.nearPlane = 1;
  list.camera.farPlane = 800;
  list.casterCentre = Vec3(100, 100, 0);
  list.casterRadius = 150;
  list.sunDirection = Vec3(0.3, -0.4, 0.87).normalized();
  // The builder derives these from its framing, which follows the box: hold them still.
  list.groundFadeStart = 200;
  list.groundFadeEnd = 400;
  return list;
}

TEST(IncrementalRender, TiledTerrainDrawsTheSamePixelsAsTheWholeMesh) {
  // The split changes which draw call a triangle is in and their order, never a vertex: the
  // picture must be the same bytes as with the terrain drawn as one mesh.
  const auto terrain = hills();
  const auto normals = std::make_shared<const std::vector<Vec3>>(smoothVertexNormals(*terrain));
  DrawList tiled = boxOverHills(*hillsBuilder(terrain, normals), 0, 40, 50);
  DrawList whole = tiled;
  whole.instances.clear();
  int tiles = 0;
  for (const DrawInstance& inst : tiled.instances) {
    if (inst.surface == Surface::terrain) {
      ++tiles;
      continue;
    }
    whole.instances.push_back(inst);
  }
  EXPECT_GT(tiles, 1);
  whole.meshes.push_back(DrawMesh{terrain.get(), terrain, normals});
  DrawInstance inst;
  inst.mesh = static_cast<int>(whole.meshes.size()) - 1;
  inst.color = tiled.instances.back().color;
  inst.surface = Surface::terrain;
  whole.instances.push_back(inst);

  const auto context = currentContext();
  const gl::RenderSettings settings = testSettings();
  // From above the whole terrain, and from low inside it looking away from a tile that then
  // lies wholly behind the eye (a whole frame skips the tiles out of view: RedrawTracker::maySee).
  for (const bool close : {false, true}) {
    if (close) {
      for (DrawList* list : {&tiled, &whole}) {
        list->camera.position = Vec3(100, 100, 6);
        list->camera.lookAt = Vec3(160, 60, 0);
        list->camera.nearPlane = 0.5;
      }
      RedrawTracker tracker(kWidth, kHeight, settings.shadowMapSize);
      const ShadowProjection shadow = fitShadowProjection(
          tiled.sunDirection, tiled.casterCentre, tiled.casterRadius, 0, settings.shadowMapSize);
      tracker.update(tiled, shadow, 0);
      int unseen = 0;
      for (std::size_t i = 0; i < tiled.instances.size(); ++i) unseen += tracker.maySee(i) ? 0 : 1;
      EXPECT_GT(unseen, 0);
    }
    const Image a = gl::Renderer(*context, settings).render(tiled);
    const Image b = gl::Renderer(*context, settings).render(whole);
    EXPECT_TRUE(a.rgb == b.rgb) << (close ? "close" : "overview");
    // Not trivially equal: the hills fill the view with shades.
    int distinct = 0;
    for (std::size_t i = 3; i < a.rgb.size(); i += 3) distinct += a.rgb[i] != a.rgb[i - 3];
    EXPECT_GT(distinct, 5000) << (close ? "close" : "overview");
  }
}

TEST(IncrementalRender, BoxOverTiledTerrainIsByteIdenticalToWholeFrames) {
  // Partial redraws draw only the tiles whose boxes reach the redrawn pixels, and redraw the
  // shadow map only with the tiles that reach its changed texels: the same bytes as every
  // frame drawn whole, with most of each frame skipped.
  const auto terrain = hills();
  const auto normals = std::make_shared<const std::vector<Vec3>>(smoothVertexNormals(*terrain));
  const auto context = currentContext();
  gl::RenderSettings settings = testSettings();
  gl::Renderer incremental(*context, settings);
  settings.incremental = false;
  gl::Renderer whole(*context, settings);
  const auto builder = hillsBuilder(terrain, normals);
  double redrawn = 0;
  constexpr int kFrames = 8;
  for (int k = 0; k < kFrames; ++k) {
    const DrawList list = boxOverHills(*builder, k, 30 + 3 * k, 40 + k);
    const Image a = incremental.render(list);
    const Image b = whole.render(list);
    EXPECT_TRUE(a.rgb == b.rgb) << "frame " << k;
    if (k > 0) redrawn += incremental.redrawnFraction();
  }
  // A box and its shadow: a small part of the view (a half would mean nothing was skipped).
  EXPECT_LT(redrawn / (kFrames - 1), 0.5);
}

TEST(RedrawTracker, FirstFrameIsWholeAndAnUnchangedOneIsEmpty) {
  RedrawTracker tracker(kWidth, kHeight);
  const DrawList list = boxOnFloor(Vec3(0, 0, 1.5));
  EXPECT_FALSE(tracker.update(list, shadowOf(list), 0.05).has_value());
  const std::optional<std::vector<PixelRect>> again = tracker.update(list, shadowOf(list), 0.05);
  ASSERT_TRUE(again.has_value());
  EXPECT_TRUE(again->empty());
}

TEST(RedrawTracker, AMovedBodyRedrawsWhereItAndItsShadowWereAndAre) {
  RedrawTracker tracker(kWidth, kHeight);
  const Vec3 from(0, 0, 1.5), to(0.6, 0.2, 1.2);
  const DrawList before = boxOnFloor(from), after = boxOnFloor(to);
  tracker.update(before, shadowOf(before), 0.05);
  const std::optional<std::vector<PixelRect>> r = tracker.update(after, shadowOf(after), 0.05);
  ASSERT_TRUE(r.has_value());
  long long area = 0;
  for (const PixelRect& rect : *r) area += rect.area();
  for (const Vec3& p : {from, to, shadowOnFloor(before, from), shadowOnFloor(after, to)}) {
    bool inside = false;
    for (const PixelRect& rect : *r) inside = inside || contains(rect, pixelOf(after, p));
    EXPECT_TRUE(inside) << "(" << p.transpose() << ") at pixel " << pixelOf(after, p).transpose();
  }
  EXPECT_LT(area, kWidth * kHeight / 2) << "a box and its shadow, not the whole view";
  // The rectangles do not overlap: no pixel is drawn twice.
  for (std::size_t a = 0; a < r->size(); ++a) {
    for (std::size_t b = a + 1; b < r->size(); ++b) EXPECT_FALSE((*r)[a].intersects((*r)[b]));
  }
}

TEST(RedrawTracker, AMovedCasterRedrawsItsShadowMapTexelsBeforeAndAfter) {
  constexpr int kMap = 512;
  RedrawTracker tracker(kWidth, kHeight, kMap);
  const Vec3 from(0, 0, 1.5), to(0.6, 0.2, 1.2);
  const DrawList before = boxOnFloor(from), after = boxOnFloor(to);
  const ShadowProjection shadow = shadowOf(before);  // the same for both: fitted to casterRadius
  tracker.update(before, shadow, 0.05);
  ASSERT_TRUE(tracker.update(after, shadow, 0.05).has_value());
  const std::vector<PixelRect>& texels = tracker.shadowMapRegion();
  // The texel under each centre, computed from the projection directly.
  for (const Vec3& p : {from, to}) {
    const Vec4 c = shadow.viewProjection * Vec4(p.x(), p.y(), p.z(), 1);
    const Eigen::Vector2d texel((c.x() * 0.5 + 0.5) * kMap, (c.y() * 0.5 + 0.5) * kMap);
    bool inside = false;
    for (const PixelRect& r : texels) inside = inside || contains(r, texel);
    EXPECT_TRUE(inside) << "(" << p.transpose() << ") at texel " << texel.transpose();
  }
  long long area = 0;
  for (const PixelRect& r : texels) area += r.area();
  EXPECT_LT(area, kMap * kMap / 4) << "one box's footprint, not the whole map";
  // Nothing moved: nothing to redraw in the map either.
  ASSERT_TRUE(tracker.update(after, shadow, 0.05).has_value());
  EXPECT_TRUE(tracker.shadowMapRegion().empty());
}

TEST(RedrawTracker, ABodyThatAppearsOrLeavesRedrawsOnlyItsPlace) {
  // Instances are matched by id, so a released body does not shift the others' comparison.
  DrawList one = boxOnFloor(Vec3(0, 0, 1.5));
  one.instances.front().id = 3;
  DrawList two = one;
  DrawInstance other = one.instances.front();
  other.id = 1;  // drawn first, as the lower body id
  other.model = bodyModelMatrix(Vec3(1.5, 1, 0.25), Quat::Identity());
  two.instances.insert(two.instances.begin(), other);
  for (const auto& [from, to] : {std::pair{one, two}, std::pair{two, one}}) {
    RedrawTracker tracker(kWidth, kHeight);
    tracker.update(from, shadowOf(from), 0.05);
    const std::optional<std::vector<PixelRect>> r = tracker.update(to, shadowOf(to), 0.05);
    ASSERT_TRUE(r.has_value());
    ASSERT_FALSE(r->empty());
    bool holdsNew = false, holdsKept = false;
    for (const PixelRect& rect : *r) {
      holdsNew = holdsNew || contains(rect, pixelOf(to, Vec3(1.5, 1, 0.25)));
      holdsKept = holdsKept || contains(rect, pixelOf(to, Vec3(0, 0, 1.5)));
    }
    EXPECT_TRUE(holdsNew) << "where the body appeared or left";
    EXPECT_FALSE(holdsKept) << "the body that stayed put is not redrawn";
  }
}

TEST(RedrawTracker, ChangedViewLightOrFloorRedrawEverything) {
  const DrawList base = boxOnFloor(Vec3(0, 0, 1.5));
  auto afterChange = [&](const DrawList& changed) {
    RedrawTracker tracker(kWidth, kHeight);
    tracker.update(base, shadowOf(base), 0.05);
    return tracker.update(changed, shadowOf(changed), 0.05);
  };
  DrawList moved = base;
  moved.camera.position.x() += 0.01;
  EXPECT_FALSE(afterChange(moved).has_value()) << "camera";
  DrawList sun = base;
  sun.sunDirection = Vec3(0.31, -0.4, 0.87).normalized();
  EXPECT_FALSE(afterChange(sun).has_value()) << "sun";
  DrawList sky = base;
  sky.light.sky *= 1.01;
  EXPECT_FALSE(afterChange(sky).has_value()) << "sky light";
  DrawList fade = base;
  fade.groundFadeEnd += 1;
  EXPECT_FALSE(afterChange(fade).has_value()) << "floor fade";
  // A body moved behind the eye: its bound cannot be projected.
  DrawList behind = base;
  behind.instances.front().model = bodyModelMatrix(Vec3(12, -16, 6), Quat::Identity());
  EXPECT_FALSE(afterChange(behind).has_value()) << "behind the camera";
}

TEST(RedrawTracker, OverlappingRectanglesMergeAndSeparateOnesStay) {
  const std::vector<PixelRect> merged =
      mergeOverlapping({PixelRect{0, 0, 10, 10}, PixelRect{50, 50, 60, 60}, PixelRect{8, 8, 20, 12},
                        PixelRect{19, 0, 30, 4}});
  // The first and third overlap; their box then overlaps the fourth; the second stands apart.
  ASSERT_EQ(merged.size(), 2u);
  EXPECT_EQ(merged[0], (PixelRect{0, 0, 30, 12}));
  EXPECT_EQ(merged[1], (PixelRect{50, 50, 60, 60}));
  // Touching edges are not an overlap ([x0, x1) is half-open).
  EXPECT_EQ(mergeOverlapping({PixelRect{0, 0, 10, 10}, PixelRect{10, 0, 20, 10}}).size(), 2u);
}

TEST(RedrawTracker, DisjointCoverHoldsExactlyTheUnion) {
  const std::vector<PixelRect> rects = {PixelRect{0, 0, 10, 10}, PixelRect{5, 5, 15, 15},
                                        PixelRect{2, 2, 4, 4}, PixelRect{20, 0, 24, 3}};
  const std::vector<PixelRect> cover = disjointCover(rects);
  // Pixel by pixel: covered once where the input covers it, never elsewhere.
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 26; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      int inInput = 0, inCover = 0;
      for (const PixelRect& r : rects) inInput += contains(r, p) ? 1 : 0;
      for (const PixelRect& r : cover) inCover += contains(r, p) ? 1 : 0;
      EXPECT_EQ(inCover, inInput > 0 ? 1 : 0) << "pixel " << x << ", " << y;
    }
  }
}

TEST(RedrawTracker, CheapMergesJoinNeighboursAndKeepDistantRectanglesApart) {
  // Side by side (their box adds nothing): one pass. A 100x100 pair 1,000 pixels apart: the
  // box would be 50 times their area, so two passes; so would a pair one pixel apart.
  const std::vector<PixelRect> near =
      mergeCheap({PixelRect{0, 0, 100, 100}, PixelRect{100, 0, 200, 100}});
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0], (PixelRect{0, 0, 200, 100}));
  EXPECT_EQ(mergeCheap({PixelRect{0, 0, 100, 100}, PixelRect{1100, 1100, 1200, 1200}}).size(), 2u);
  EXPECT_EQ(mergeCheap({PixelRect{0, 0, 100, 100}, PixelRect{101, 0, 201, 100}}).size(), 2u);
}

// Pixel by pixel over a w x h area: every pixel of `rects` is in exactly one of `cover`.
void expectDisjointCover(const std::vector<PixelRect>& rects, const std::vector<PixelRect>& cover,
                         int w, int h) {
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      bool inInput = false;
      int inCover = 0;
      for (const PixelRect& r : rects) inInput = inInput || contains(r, p);
      for (const PixelRect& r : cover) inCover += contains(r, p) ? 1 : 0;
      if (inInput) {
        EXPECT_EQ(inCover, 1) << "pixel " << x << ", " << y;
      }
      if (inInput && inCover != 1) return;
    }
  }
}

TEST(RedrawTracker, ManyOverlappingRectanglesStillCoverEverything) {
  // A chain of 120 overlapping rectangles: their disjoint pieces would be more passes than the
  // cap, so overlapping groups are drawn as bounding boxes; nothing may be left out.
  std::vector<PixelRect> rects;
  for (int k = 0; k < 120; ++k) rects.push_back(PixelRect{3 * k, k % 7, 3 * k + 5, k % 7 + 4});
  ASSERT_GT(disjointCover(mergeCheap(rects)).size(), 48u) << "the fallback is what is tested";
  const std::vector<PixelRect> cover = coverWithFewPieces(rects);
  ASSERT_FALSE(cover.empty());
  expectDisjointCover(rects, cover, 370, 12);
  for (std::size_t a = 0; a < cover.size(); ++a) {
    for (std::size_t b = a + 1; b < cover.size(); ++b) EXPECT_FALSE(cover[a].intersects(cover[b]));
  }
}

TEST(RedrawTracker, SixtyMovedBodiesAreAllRedrawn) {
  // Sixty small boxes in a slanting row, all moved: their rectangles overlap in a chain, and
  // every body must be covered before and after.
  static const auto shape = test::boxShape(Vec3(0.05, 0.05, 0.05));
  DrawList before = boxOnFloor(Vec3(0, 0, 1.5));
  before.instances.clear();
  before.meshes.clear();
  before.meshes.push_back(
      DrawMesh{shape.get(), std::shared_ptr<const TriMesh>(shape, &shape->mesh), {}});
  DrawList after = before;
  std::vector<std::pair<Vec3, Vec3>> moves;
  for (int k = 0; k < 60; ++k) {
    const Vec3 from(-1.5 + 0.05 * k, 0.03 * (k % 5), 0.5 + 0.02 * k);
    const Vec3 to = from + Vec3(0.03, 0, -0.02);
    DrawInstance inst;
    inst.id = k;
    inst.model = bodyModelMatrix(from, Quat::Identity());
    before.instances.push_back(inst);
    inst.model = bodyModelMatrix(to, Quat::Identity());
    after.instances.push_back(inst);
    moves.emplace_back(from, to);
  }
  RedrawTracker tracker(kWidth, kHeight);
  tracker.update(before, shadowOf(before), 0.05);
  const std::optional<std::vector<PixelRect>> r = tracker.update(after, shadowOf(after), 0.05);
  ASSERT_TRUE(r.has_value());
  for (const auto& [from, to] : moves) {
    for (const Vec3& p : {from, to}) {
      bool inside = false;
      for (const PixelRect& rect : *r) inside = inside || contains(rect, pixelOf(after, p));
      EXPECT_TRUE(inside) << "(" << p.transpose() << ")";
    }
  }
}

TEST(RedrawTracker, SphereRectangleHoldsTheExactSilhouette) {
  // A point widened by r is the cube around the sphere of radius r there. A sphere of radius r
  // at distance d on the view axis subtends the half-angle asin(r / d): its silhouette spans
  // tan(asin(r / d)) / tan(fov / 2) of the half-height.
  const Vec3 kOrigin[1] = {Vec3::Zero()};
  CameraView cam;
  cam.position = Vec3(0, -10, 0);
  cam.lookAt = Vec3::Zero();
  cam.fovYDegrees = 40;
  const Mat4 vp = cam.projectionMatrix(static_cast<double>(kWidth) / kHeight) * cam.viewMatrix();
  const double r = 1;
  const std::optional<PixelRect> rect = projectPoints(vp, kOrigin, r, kWidth, kHeight, 0, 1);
  ASSERT_TRUE(rect.has_value());
  const double half =
      std::tan(std::asin(r / 10)) / std::tan(20 * std::numbers::pi / 180) * kHeight / 2;
  EXPECT_LE(rect->y0, kHeight / 2 - half);
  EXPECT_GE(rect->y1, kHeight / 2 + half);
  EXPECT_LE(rect->x0, kWidth / 2 - half);
  EXPECT_GE(rect->x1, kWidth / 2 + half);
  // The cube-corner bound is at most the cube's nearest face seen from d - r: no more than
  // r / (d - r) / tan(fov / 2) of the half-height (plus a pixel of rounding).
  const double loose = r / (10 - r) / std::tan(20 * std::numbers::pi / 180) * kHeight / 2 + 1;
  EXPECT_GE(rect->y0, kHeight / 2 - loose);
  EXPECT_LE(rect->y1, kHeight / 2 + loose);
  // Margin and alignment widen it outwards, clipped to the frame.
  const std::optional<PixelRect> wide = projectPoints(vp, kOrigin, r, kWidth, kHeight, 2, 8);
  ASSERT_TRUE(wide.has_value());
  EXPECT_EQ(wide->x0 % 8, 0);
  EXPECT_EQ(wide->y1 % 8, 0);
  EXPECT_LE(wide->x0, rect->x0 - 2);
  cam.position = Vec3(0, -0.5, 0);  // the eye inside the sphere's cube
  const Mat4 inside = cam.projectionMatrix(1.0) * cam.viewMatrix();
  EXPECT_FALSE(projectPoints(inside, kOrigin, r, kWidth, kHeight, 0, 1));
}

}  // namespace
TEST(HiddenWorkGeometry, FloorCoversOnlyRectanglesWhoseEveryRayMeetsTheFloorSquare) {
  // The independent check: each pixel's corners cast as rays through the camera's own basis
  // (forward, right, up scaled by the field of view), not through the inverse matrix.
  CameraView cam;
  cam.position = Vec3(0.5, -10, 3);
  cam.lookAt = Vec3(0, 0, 0.5);  // the horizon crosses the upper part of the view
  cam.nearPlane = 0.1;
  cam.farPlane = 100;
  const Eigen::Vector2d centre = cam.position.head<2>();
  const double half = 40;
  const Vec3 forward = (cam.lookAt - cam.position).normalized();
  const Vec3 right = forward.cross(cam.up).normalized();
  const Vec3 up = right.cross(forward);
  const double t = std::tan(cam.fovYDegrees / 2 * std::numbers::pi / 180);
  const double aspect = static_cast<double>(kWidth) / kHeight;
  auto meetsSquare = [&](double x, double y) {
    const Vec3 d =
        forward + t * ((2 * x / kWidth - 1) * aspect * right + (2 * y / kHeight - 1) * up);
    if (d.z() >= 0) return false;
    const Vec3 hit = cam.position + d * (-cam.position.z() / d.z());
    return std::abs(hit.x() - centre.x()) < half && std::abs(hit.y() - centre.y()) < half;
  };
  int covered = 0, open = 0;
  for (int y0 = 0; y0 < kHeight; y0 += 20) {
    for (int x0 = 0; x0 < kWidth; x0 += 40) {
      const PixelRect r{x0, y0, x0 + 40, y0 + 20};
      if (!floorCovers(cam, kWidth, kHeight, 0, centre, half, r)) {
        ++open;
        continue;
      }
      ++covered;
      for (int y = r.y0; y <= r.y1; ++y) {
        for (int x = r.x0; x <= r.x1; ++x) {
          ASSERT_TRUE(meetsSquare(x, y)) << "pixel corner " << x << ", " << y;
        }
      }
    }
  }
  // Below the horizon covered, above it not (a rectangle that holds the horizon is not).
  EXPECT_GT(covered, 0);
  EXPECT_GT(open, 0);
  EXPECT_TRUE(floorCovers(cam, kWidth, kHeight, 0, centre, half, PixelRect{0, 0, kWidth, 20}));
  EXPECT_FALSE(
      floorCovers(cam, kWidth, kHeight, 0, centre, half, PixelRect{0, 0, kWidth, kHeight}));
  // A small square leaves sky beside it; a camera under the floor sees none of it.
  EXPECT_FALSE(floorCovers(cam, kWidth, kHeight, 0, centre, 2, PixelRect{0, 0, kWidth, 20}));
  CameraView below = cam;
  below.position.z() = -1;
  EXPECT_FALSE(floorCovers(below, kWidth, kHeight, 0, centre, half, PixelRect{0, 0, 8, 8}));
  // The floor under the bottom rows lies 5 to 6 m away: beyond a far plane at 4 m, or before
  // a near plane at 8 m, it is clipped away, and the sky would show.
  const PixelRect bottom{0, 0, kWidth, 20};
  CameraView shortSight = cam;
  shortSight.farPlane = 4;
  EXPECT_FALSE(floorCovers(shortSight, kWidth, kHeight, 0, centre, half, bottom));
  CameraView farSight = cam;
  farSight.nearPlane = 8;
  EXPECT_FALSE(floorCovers(farSight, kWidth, kHeight, 0, centre, half, bottom));
}

TEST(HiddenWorkGeometry, FloorShadowsHoldEveryCastersShadowAndNotTheWholeFloor) {
  RedrawTracker tracker(kWidth, kHeight);
  const Vec3 at(0, 0, 1.5);
  const DrawList list = boxOnFloor(at);
  tracker.update(list, shadowOf(list), 0.05);
  ASSERT_TRUE(tracker.floorShadows().has_value());
  const std::vector<PixelRect>& rects = *tracker.floorShadows();
  long long area = 0;
  bool holdsShadow = false;
  for (const PixelRect& r : rects) {
    area += r.area();
    holdsShadow = holdsShadow || contains(r, pixelOf(list, shadowOnFloor(list, at)));
  }
  EXPECT_TRUE(holdsShadow);
  EXPECT_GT(area, 0);
  EXPECT_LT(area, kWidth * kHeight / 4) << "one box's shadow, not the whole floor";
  // No floor: nothing to say.
  DrawList noFloor = list;
  noFloor.groundHeight.reset();
  tracker.update(noFloor, shadowOf(noFloor), 0.05);
  EXPECT_FALSE(tracker.floorShadows().has_value());
}

TEST(HiddenWorkGeometry, SplitRectCutsExactlyAlongTheCover) {
  const PixelRect r{2, 1, 30, 20};
  const std::vector<PixelRect> cover = {PixelRect{0, 0, 10, 10}, PixelRect{5, 5, 15, 15},
                                        PixelRect{25, 18, 40, 40}, PixelRect{50, 50, 60, 60}};
  const RectSplit split = splitRect(r, cover);
  for (int y = 0; y < 45; ++y) {
    for (int x = 0; x < 45; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      bool inCover = false;
      int inside = 0, outside = 0;
      for (const PixelRect& c : cover) inCover = inCover || contains(c, p);
      for (const PixelRect& c : split.inside) inside += contains(c, p) ? 1 : 0;
      for (const PixelRect& c : split.outside) outside += contains(c, p) ? 1 : 0;
      const bool inR = contains(r, p);
      EXPECT_EQ(inside, inR && inCover ? 1 : 0) << "pixel " << x << ", " << y;
      EXPECT_EQ(outside, inR && !inCover ? 1 : 0) << "pixel " << x << ", " << y;
    }
  }
}

}  // namespace vf
