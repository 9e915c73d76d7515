// The look in rendered pixels, each against geometry worked out here: shadows stay where the
// sun puts them in the world while the camera orbits; a terrain seen from the side shows its
// wall; a draped picture lands on the cells it covers; culling the back faces of bodies
// leaves their pictures as they were.
//
// Pixel oracles: world points projected with the frame's own camera matrices
// (projectToPixel), shadow regions by a ray-box test towards the sun, texel rectangles from the
// raster's geotransform. Thresholds are far from both outcomes (stated at each), so a pixel of
// antialiasing or rounding cannot decide a test.
#include <cpl_conv.h>
#include <gdal.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "render/draw_list.h"
#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render/output/image_diff.h"
#include "render/scene_playback.h"
#include "render_test_util.h"
#include "sim/core/error.h"
#include "sim/shape/drape_import.h"

namespace vf {
namespace {

class LookRender : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::createContext(gl::Backend::osmesa).release(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  static gl::RenderSettings settings(int w, int h) {
    gl::RenderSettings s;
    s.width = w;
    s.height = h;
    s.dither = false;
    s.shaderDir = gl::findShaderDir();
    return s;
  }
  static gl::Context* context_;
};
gl::Context* LookRender::context_ = nullptr;

// Pixel (x right, y down) where world point p projects, and whether it is in front of the eye.
std::optional<Eigen::Vector2i> pixelOf(const CameraView& c, int w, int h, const Vec3& p) {
  const Vec4 clip =
      c.projectionMatrix(double(w) / h) * c.viewMatrix() * Vec4(p.x(), p.y(), p.z(), 1);
  if (!(clip.w() > 0)) return std::nullopt;
  const int x = static_cast<int>(std::floor((clip.x() / clip.w() + 1) / 2 * w));
  const int y = static_cast<int>(std::floor((1 - clip.y() / clip.w()) / 2 * h));
  if (x < 0 || y < 0 || x >= w || y >= h) return std::nullopt;
  return Eigen::Vector2i(x, y);
}

double luminance(const Image& image, const Eigen::Vector2i& p) {
  const std::uint8_t* c = image.pixel(p.x(), p.y());
  return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

// Whether the ray from `from` along `dir` (t > 0) meets the axis-aligned box [lo, hi].
bool rayHitsBox(const Vec3& from, const Vec3& dir, const Vec3& lo, const Vec3& hi,
                double tMax = INFINITY) {
  double t0 = 0, t1 = tMax;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir[k]) < 1e-15) {
      if (from[k] < lo[k] || from[k] > hi[k]) return false;
      continue;
    }
    double a = (lo[k] - from[k]) / dir[k], b = (hi[k] - from[k]) / dir[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  return t0 <= t1;
}

TEST_F(LookRender, AnOrbitingCameraLeavesTheShadowWhereItIsInTheWorld) {
  // A 1 m cube at rest on the floor, and a path camera that swings 90 degrees round it in a
  // second. The shadow worked out from the first frame's sun must be dark, and the floor
  // around it lit, in the first frame and in the last: with a sun that turns with the camera
  // the last frame's shadow lies elsewhere, and these floor points come out lit.
  const auto cube = test::boxShape(Vec3(0.5, 0.5, 0.5));
  const std::vector<BodyView> bodies{test::body(cube, Vec3(0, 0, 0.5))};
  CameraSpec spec;
  // From compass azimuths 250 and 340 degrees: both look along the default sun's shadow, which
  // falls towards 296 (light.h: behind the automatic camera's right shoulder, at 116).
  spec.path = {CameraKey{0, Vec3(-6.58, -2.39, 3.5), Vec3(0, 0, 0.3), 40},
               CameraKey{1, Vec3(-2.39, 6.58, 3.5), Vec3(0, 0, 0.3), 40}};
  const int w = 320, h = 240;
  DrawListBuilder builder(spec, 0.0, w, h, 30);
  for (int k = 0; k <= 30; ++k) builder.observe(bodies);
  const DrawList first = builder.build(bodies, 0), last = builder.build(bodies, 30);
  ASSERT_GT((first.camera.position - last.camera.position).norm(), 5) << "the camera moved";
  const Vec3 sun = first.sunDirection;
  gl::Renderer renderer(*context_, settings(w, h));
  const Image images[2] = {renderer.render(first), renderer.render(last)};
  const CameraView* cameras[2] = {&first.camera, &last.camera};
  const Vec3 lo(-0.5, -0.5, 0), hi(0.5, 0.5, 1);
  for (int f = 0; f < 2; ++f) {
    std::vector<double> shadowed, lit;
    std::vector<Vec3> litAt;
    // Floor points between the 0.1 m grid lines (5 cm from any), off the cube's footprint.
    for (double x = -3.95; x < 4; x += 0.1) {
      for (double y = -3.95; y < 4; y += 0.1) {
        const Vec3 p(x, y, 0);
        if (std::abs(x) < 0.6 && std::abs(y) < 0.6) continue;
        // 0.1 m from the shadow's edge either way: the filtered penumbra is a few texels of
        // about 5 mm.
        bool near = false, in = rayHitsBox(p, sun, lo, hi);
        for (const Vec3& d : {Vec3(0.1, 0, 0), Vec3(-0.1, 0, 0), Vec3(0, 0.1, 0), Vec3(0, -0.1, 0)})
          near = near || rayHitsBox(p + d, sun, lo, hi) != in;
        if (near) continue;
        const Vec3 eye = cameras[f]->position;
        // Behind the cube, or within a pixel or two (2 cm here) of its outline.
        const Vec3 grow = Vec3::Constant(0.05);
        if (rayHitsBox(eye, p - eye, lo - grow, hi + grow, 1.0)) continue;
        const auto px = pixelOf(*cameras[f], w, h, p);
        if (!px) continue;
        (in ? shadowed : lit).push_back(luminance(images[f], *px));
        if (!in) litAt.push_back(p);
      }
    }
    ASSERT_GE(shadowed.size(), 20u) << "frame " << f << " sees the shadow";
    ASSERT_GE(lit.size(), 200u) << "frame " << f;
    std::vector<double> sorted = lit;
    std::sort(sorted.begin(), sorted.end());
    const double litFloor = sorted[sorted.size() / 2];
    // The floor in shadow gets the sky and ambient light only, under half of the sunlit
    // floor's (render/light.h); 0.7 of it parts the two with room either side.
    for (const double v : shadowed) EXPECT_LT(v, 0.7 * litFloor) << "frame " << f;
    for (std::size_t i = 0; i < lit.size(); ++i)
      EXPECT_GT(lit[i], 0.7 * litFloor) << "frame " << f << " at " << litAt[i].transpose();
  }
  EXPECT_EQ(first.sunDirection, last.sunDirection);
}

// A 10 x 10 m terrain of 1 m cells, 1 to 1.3 m high.
std::shared_ptr<Heightfield> smallTerrain() {
  auto h = std::make_shared<Heightfield>();
  h->nx = h->ny = 11;
  h->cell = 1;
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) h->z.push_back(1 + 0.15 * (1 + std::sin(0.7 * i + 0.4 * j)));
  h->zMin = *std::min_element(h->z.begin(), h->z.end());
  h->zMax = *std::max_element(h->z.begin(), h->z.end());
  return h;
}

TEST_F(LookRender, ATerrainSeenFromTheSideShowsItsWallNotWhatLiesBehind) {
  // The camera stands south of the terrain, below its top, looking north at its southern
  // edge; the sun is behind the camera. Points of the southern wall must not look like the
  // same view without the terrain (the sky and the far floor 50 m down): a sheet of a terrain
  // would show exactly that there.
  const int w = 200, h = 150;
  CameraSpec spec;
  spec.given = spec.offsetGiven = true;
  spec.position = Vec3(5, -9, 0.8);
  spec.lookAt = Vec3(5, 0, 0.6);
  SceneLight light;
  light.sunDirection = Vec3(0, -1, 1).normalized();
  const auto terrain = smallTerrain();
  auto drawn = [&](bool withTerrain) {
    DrawListBuilder builder(spec, -50.0, w, h, 30);
    builder.setLight(light);
    if (withTerrain) builder.setTerrain(terrain);
    const std::vector<BodyView> none;
    return builder.build(none);
  };
  const DrawList with = drawn(true), without = drawn(false);
  gl::Renderer renderer(*context_, settings(w, h));
  const Image a = renderer.render(with), b = renderer.render(without);
  int checked = 0;
  for (double x = 1; x <= 9; x += 1) {
    for (const double z : {0.3, 0.6, 0.9}) {  // below the wall's top edge (1 m and more)
      const auto px = pixelOf(with.camera, w, h, Vec3(x, 0, z));
      ASSERT_TRUE(px);
      const std::uint8_t *p = a.pixel(px->x(), px->y()), *q = b.pixel(px->x(), px->y());
      int most = 0;
      for (int c = 0; c < 3; ++c) most = std::max(most, std::abs(int(p[c]) - int(q[c])));
      // The wall is a dark earth lit by the sun, the sky behind it a pale blue-grey: over a
      // hundred codes apart. Equal views differ by nothing (same renderer, no dither).
      EXPECT_GT(most, 40) << "wall point (" << x << ", 0, " << z << ")";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 27);
}

// Writes a GeoTIFF (or, with gt null, a TIFF without georeference) of w x h RGB pixels, grey
// but for pixel (col, row) (row 0 the northern one), which is red.
void writeMarkedRaster(const std::string& path, int w, int h, const double* gt, int col, int row) {
  GDALAllRegister();
  GDALDatasetH ds =
      GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, 3, GDT_Byte, nullptr);
  ASSERT_NE(ds, nullptr);
  if (gt) GDALSetGeoTransform(ds, const_cast<double*>(gt));
  for (int band = 1; band <= 3; ++band) {
    std::vector<std::uint8_t> v(static_cast<std::size_t>(w) * h, 128);
    v[static_cast<std::size_t>(row) * w + col] = band == 1 ? 255 : 0;
    ASSERT_EQ(GDALRasterIO(GDALGetRasterBand(ds, band), GF_Write, 0, 0, w, h, v.data(), w, h,
                           GDT_Byte, 0, 0),
              CE_None);
  }
  GDALClose(ds);
}

// Renders the flat terrain `h` with `drape` from straight above, and checks that the pixels
// that read as red (more red than grey, in linear light) are those whose centres see the world
// rectangle [x0, x1] x [y0, y1], to within one pixel.
void expectRedOn(gl::Context& context, const Heightfield& h,
                 std::shared_ptr<const DrapeImage> drape, double x0, double y0, double x1,
                 double y1) {
  const int size = 160;
  CameraSpec spec;
  spec.given = spec.offsetGiven = true;
  spec.position = Vec3(4, 4, 20);
  spec.lookAt = Vec3(4, 4, 0);
  spec.up = Vec3::UnitY();
  spec.fovDegrees = 30;
  DrawListBuilder builder(spec, std::nullopt, size, size, 30);
  SceneLight light;  // straight down, no sky: the texels' colours scaled by one factor
  light.sunDirection = Vec3::UnitZ();
  light.colors.sun = Vec3::Constant(0.6);  // below the highlight shoulder at 0.8
  light.colors.sky = light.colors.ambient = Vec3::Zero();
  builder.setLight(light);
  builder.setTerrain(std::make_shared<const Heightfield>(h), std::move(drape));
  const std::vector<BodyView> none;
  const DrawList list = builder.build(none);
  gl::RenderSettings s;
  s.width = s.height = size;
  s.dither = false;
  s.shaderDir = gl::findShaderDir();
  gl::Renderer renderer(context, s);
  const Image image = renderer.render(list);
  // One pixel on the ground: the view's width at 20 m over its pixels.
  const double pixel = 2 * 20 * std::tan(15 * std::numbers::pi / 180) / size;
  const auto linear = [](int code) {
    const double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const Mat4 inverse = (list.camera.projectionMatrix(1.0) * list.camera.viewMatrix()).inverse();
  int red = 0;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      // Where the pixel's centre ray meets the ground plane z = 0.
      const Vec4 a = inverse * Vec4((x + 0.5) / size * 2 - 1, 1 - (y + 0.5) / size * 2, -1, 1);
      const Vec4 b = inverse * Vec4((x + 0.5) / size * 2 - 1, 1 - (y + 0.5) / size * 2, 1, 1);
      const Vec3 p0 = a.head<3>() / a.w(), p1 = b.head<3>() / b.w();
      const Vec3 g = p0 + (p1 - p0) * (p0.z() / (p0.z() - p1.z()));
      const std::uint8_t* c = image.pixel(x, y);
      // Red texels give R - G = 0.6 (linear), grey ones 0: the mix weight is (R - G) / 0.6.
      const bool isRed = linear(c[0]) - linear(c[1]) > 0.3;
      const bool inside =
          g.x() > x0 + pixel && g.x() < x1 - pixel && g.y() > y0 + pixel && g.y() < y1 - pixel;
      const bool outside =
          g.x() < x0 - pixel || g.x() > x1 + pixel || g.y() < y0 - pixel || g.y() > y1 + pixel;
      if (inside) {
        EXPECT_TRUE(isRed) << "pixel " << x << ", " << y << " at " << g.transpose();
      }
      if (outside) {
        EXPECT_FALSE(isRed) << "pixel " << x << ", " << y << " at " << g.transpose();
      }
      red += isRed;
    }
  }
  // About (1 m / pixel)^2 of them.
  EXPECT_NEAR(red, (x1 - x0) * (y1 - y0) / (pixel * pixel),
              0.2 * (x1 - x0) * (y1 - y0) / (pixel * pixel));
}

TEST_F(LookRender, ADrapedRasterLandsOnTheCellsItCovers) {
  // A flat 8 x 8 sample DEM in file coordinates 100.5 .. 107.5 (its raster's extent 100 .. 108),
  // moved by -100 into the world; a texture on the same grid with one red cell.
  Heightfield h;
  h.nx = h.ny = 8;
  h.cell = 1;
  h.x0 = h.y0 = 100.5;
  h.z.assign(64, 0.0);
  shiftHeightfield(h, Vec3(-100, -100, 0));
  const test::ScratchDir dir("drape");
  const double gt[6] = {100, 1, 0, 108, 0, -1};  // top-left corner, 1 m pixels, north up
  writeMarkedRaster(dir.file("photo.tif"), 8, 8, gt, 5, 2);
  // Column 5 covers file x 105..106, row 2 from the top y 105..106: world 5..6 x 5..6.
  expectRedOn(*context_, h, std::make_shared<const DrapeImage>(loadDrape(dir.file("photo.tif"), h)),
              5, 5, 6, 6);
  // Without a georeference a raster is stretched over the DEM's extent: pixel (3, 12) of a
  // 16 x 16 one covers world x 1.5..2 and y 8 - 13/2 .. 8 - 12/2 = 1.5..2.
  writeMarkedRaster(dir.file("plain.tif"), 16, 16, nullptr, 3, 12);
  expectRedOn(*context_, h, std::make_shared<const DrapeImage>(loadDrape(dir.file("plain.tif"), h)),
              1.5, 1.5, 2, 2);
}

TEST(Drape, RasterThatIsNotOneIsAnErrorNamingIt) {
  Heightfield h;
  h.nx = h.ny = 2;
  h.z.assign(4, 0.0);
  const test::ScratchDir dir("drape_bad");
  std::ofstream(dir.file("bad.tif")) << "not a raster";
  try {
    loadDrape(dir.file("bad.tif"), h);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), dir.file("bad.tif"));
    EXPECT_NE(e.message().find("cannot read the texture raster"), std::string::npos) << e.what();
  }
}

// Bodies' back faces are culled (DrawMesh::closed): from outside a closed, outward mesh they
// lie behind its front faces, so the frame is the one drawn with them. The oracle is the same
// frame with every mesh drawn whole. Where a back face's interpolated depth came out in front
// of the front face's at a silhouette, the whole draw shaded that sample from behind: a pixel
// or two per frame may differ, within the golden suite's tolerance (0.05 %). Culling the
// wrong side shows the insides of the bodies instead: thousands of pixels.
TEST_F(LookRender, CullingTheBackFacesOfBodiesLeavesTheFrameAsDrawnWhole) {
  SceneSpec spec = loadScene(std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml");
  spec.output.width = 320;
  spec.output.height = 180;
  const std::string shaders = gl::findShaderDir();
  int closedMeshes = 0;
  const Image culled = renderSceneFrames(spec, {6}, *context_, shaders, [&](DrawList& list) {
                         for (const DrawMesh& m : list.meshes) closedMeshes += m.closed ? 1 : 0;
                       }).images.at(0);
  ASSERT_GT(closedMeshes, 0);  // the bodies' meshes are marked closed, so culling happens
  const Image whole = renderSceneFrames(spec, {6}, *context_, shaders, [](DrawList& list) {
                        for (DrawMesh& m : list.meshes) m.closed = false;
                      }).images.at(0);
  const DiffMetrics d = compareImages(whole, culled, 8);
  EXPECT_LE(d.differingFraction, 0.0005) << describe(d, whole, culled);
}

}  // namespace
}  // namespace vf
