// Tiny frames read back from the GL renderer with exact expectations (Filament's 16x16 habit):
// the sky gradient against its formula restated here, orientation via an unlit triangle,
// determinism, shader error messages, and the EGL backend against OSMesa.
//
// Tolerance: +-1 of 255 per channel where the shader's float math meets the double formula
// here. The GPU side evaluates pow() and the sRGB curve in 32-bit floats (llvmpipe's pow is a
// polynomial approximation), stores light in half floats (11-bit mantissa, 1/2048 relative)
// and converts to 8 bits with its own rounding, so a value within a hair of .5 may land on
// either side. A wrong formula, a flipped image or a wrong colour is off by far more than 1.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "render/draw_list.h"
#include "render/gl/gl_context.h"
#include "render/gl/renderer.h"
#include "render/gl/shader_program.h"
#include "render_test_util.h"
#include "sim/core/error.h"

namespace vf {
namespace {

using test::srgbByte;

gl::RenderSettings tinySettings(int w = 16, int h = 16) {
  gl::RenderSettings s;
  s.width = w;
  s.height = h;
  s.dither = false;  // exact expectations
  s.shaderDir = gl::findShaderDir();
  return s;
}

// A camera at the origin looking along +y, level: the horizon runs through the middle.
DrawList emptyLevelView() {
  DrawList list;
  list.camera.position = Vec3::Zero();
  list.camera.lookAt = Vec3(0, 1, 0);
  list.camera.up = Vec3::UnitZ();
  list.camera.fovYDegrees = 40;
  list.camera.nearPlane = 0.1;
  list.camera.farPlane = 100;
  return list;
}

// shaders/common.glsl skyColor(), restated.
Vec3 skyFormula(const Vec3& d) {
  const Vec3 zenith(0.170, 0.320, 0.660), horizon(0.700, 0.760, 0.840), below(0.560, 0.590, 0.620);
  const double e = std::clamp(d.z(), -1.0, 1.0);
  if (e >= 0) {
    const double u = 1 - e;
    const double t = 1 - u * u * u;
    return horizon * (1 - t) + zenith * t;
  }
  const double t = std::min(-e * 8, 1.0);
  return horizon * (1 - t) + below * t;
}

// The view ray through the centre of pixel (x, y), y = 0 the top row.
Vec3 pixelRay(const CameraView& c, int w, int h, int x, int y) {
  Mat4 rotation = c.viewMatrix();
  rotation.block<3, 1>(0, 3).setZero();
  const Mat4 inverse = (c.projectionMatrix(double(w) / h) * rotation).inverse();
  const double ndcX = (x + 0.5) / w * 2 - 1;
  const double ndcY = (h - 1 - y + 0.5) / h * 2 - 1;  // GL rows count from the bottom
  const Vec4 p = inverse * Vec4(ndcX, ndcY, 1, 1);
  return (p.head<3>() / p.w()).normalized();
}

void expectPixel(const Image& image, int x, int y, int r, int g, int b) {
  const std::uint8_t* p = image.pixel(x, y);
  EXPECT_NEAR(p[0], r, 1) << "red at (" << x << ", " << y << ")";
  EXPECT_NEAR(p[1], g, 1) << "green at (" << x << ", " << y << ")";
  EXPECT_NEAR(p[2], b, 1) << "blue at (" << x << ", " << y << ")";
}

class Readback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { context_ = gl::createContext(gl::Backend::osmesa).release(); }
  static void TearDownTestSuite() {
    delete context_;
    context_ = nullptr;
  }
  static gl::Context* context_;
};
gl::Context* Readback::context_ = nullptr;

TEST_F(Readback, SkyOnlyFrameMatchesTheGradientFormula) {
  gl::Renderer renderer(*context_, tinySettings());
  const DrawList list = emptyLevelView();
  const Image image = renderer.render(list);
  ASSERT_EQ(image.width, 16);
  ASSERT_EQ(image.height, 16);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      // Sky values stay below 0.8, where present.frag's highlight shoulder is the identity.
      const Vec3 c = skyFormula(pixelRay(list.camera, 16, 16, x, y));
      expectPixel(image, x, y, srgbByte(c.x()), srgbByte(c.y()), srgbByte(c.z()));
    }
  }
  // Orientation: the top row is the bluer, higher sky.
  EXPECT_LT(image.pixel(8, 0)[0] + 10, image.pixel(8, 15)[0]);
  EXPECT_GT(image.pixel(8, 0)[2] - image.pixel(8, 0)[0], 40);
}

TEST_F(Readback, UnlitTriangleOverTheTopHalfIsOnTop) {
  gl::Renderer renderer(*context_, tinySettings());
  DrawList list = emptyLevelView();
  // A huge triangle in the plane y = 5 covering everything above the horizon (z >= 0) in view.
  auto mesh = std::make_shared<TriMesh>();
  mesh->vertices = {Vec3(-100, 5, 0), Vec3(100, 5, 0), Vec3(0, 5, 100)};
  mesh->triangles = {{0, 1, 2}};
  list.meshes.push_back(DrawMesh{mesh.get(), mesh, nullptr});
  DrawInstance inst;
  inst.mesh = 0;
  inst.color = Color{0.5f, 0.1f, 0.05f};
  inst.surface = Surface::unlit;
  list.instances.push_back(inst);
  const Image image = renderer.render(list);
  const int r = srgbByte(0.5), g = srgbByte(0.1), b = srgbByte(0.05);
  // The horizon falls exactly between rows 7 and 8, so every sample of rows 0..7 is covered
  // and none of rows 8..15.
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      if (y < 8) {
        expectPixel(image, x, y, r, g, b);
      } else {
        const Vec3 c = skyFormula(pixelRay(list.camera, 16, 16, x, y));
        expectPixel(image, x, y, srgbByte(c.x()), srgbByte(c.y()), srgbByte(c.z()));
      }
    }
  }
}

// A small lit scene: boxes on the floor with shadows, grid and sky; every pass runs.
DrawList litScene(const std::vector<BodyView>& bodies, double aspect) {
  DrawListBuilder builder(CameraSpec{}, 0.0, aspect);
  return builder.build(bodies);
}

TEST_F(Readback, SameDrawListRendersIdenticalBytes) {
  const auto cube = test::boxShape(Vec3(0.25, 0.25, 0.25));
  const std::vector<BodyView> bodies{
      test::body(cube, Vec3(0, 0, 0.25), Quat::Identity(), 0),
      test::body(cube, Vec3(0.6, 0.2, 0.9),
                 Quat(Eigen::AngleAxisd(0.6, Vec3(1, 1, 0).normalized())), 1)};
  gl::RenderSettings settings = tinySettings(96, 64);
  settings.dither = true;
  const DrawList list = litScene(bodies, 96.0 / 64.0);
  gl::Renderer first(*context_, settings);
  const Image a = first.render(list);
  const Image b = first.render(list);
  gl::Renderer second(*context_, settings);  // fresh framebuffers and meshes
  const Image c = second.render(list);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.rgb, c.rgb);
  // Not trivially equal: the frame has bodies, floor and sky in it.
  int distinct = 0;
  for (std::size_t i = 3; i < a.rgb.size(); i += 3) distinct += a.rgb[i] != a.rgb[i - 3];
  EXPECT_GT(distinct, 500);
}

TEST_F(Readback, ShadowMapIsReusedOnlyWhileTheCastersStayPut) {
  // The renderer keeps the shadow map while the light and every caster are unchanged. A frame
  // after a body moved must equal the same frame from a fresh renderer (the map was redrawn),
  // and going back must give the first frame again. The moved cube's shadow is part of the
  // picture, so a stale map would show it in the wrong place.
  const auto cube = test::boxShape(Vec3(0.25, 0.25, 0.25));
  const auto posed = [&](const Vec3& x) {
    return std::vector<BodyView>{test::body(cube, Vec3(0, 0, 0.25)), test::body(cube, x)};
  };
  gl::RenderSettings settings = tinySettings(96, 64);
  // One builder: the same automatic camera and shadow box for both poses (only the caster moves).
  DrawListBuilder builder(CameraSpec{}, 0.0, 96.0 / 64.0);
  builder.observe(posed(Vec3(0.7, 0.1, 0.6)));
  builder.observe(posed(Vec3(0.7, 0.4, 0.6)));
  const DrawList a = builder.build(posed(Vec3(0.7, 0.1, 0.6)));
  DrawList b = builder.build(posed(Vec3(0.7, 0.4, 0.6)));
  b.casterCentre = a.casterCentre;  // same light box: only the caster differs
  b.casterRadius = a.casterRadius;
  gl::Renderer renderer(*context_, settings);
  const Image first = renderer.render(a);
  const Image moved = renderer.render(b);
  const Image back = renderer.render(a);
  gl::Renderer fresh(*context_, settings);
  EXPECT_EQ(moved.rgb, fresh.render(b).rgb);
  EXPECT_EQ(first.rgb, back.rgb);
  EXPECT_NE(first.rgb, moved.rgb);
}

// Pixel position (x right, y down, pixel centres at +0.5) where a world point projects.
Eigen::Vector2d projectToPixel(const CameraView& c, int w, int h, const Vec3& p) {
  const Vec4 clip =
      c.projectionMatrix(double(w) / h) * c.viewMatrix() * Vec4(p.x(), p.y(), p.z(), 1);
  const double ndcX = clip.x() / clip.w(), ndcY = clip.y() / clip.w();
  return Eigen::Vector2d((ndcX + 1) / 2 * w, (1 - ndcY) / 2 * h);
}

TEST_F(Readback, TrailAndMinimumSizeMarkerAppearWhereProjected) {
  // A 2 cm cube 300 m away (well under a pixel) flies left to right in front of the sky. With
  // min_pixels = 9 it is drawn as a flat marker; its trail of the last second is a ribbon two
  // pixels wide. Oracles: the camera's own projection matrices (restated in projectToPixel),
  // and the unlit colour through the sRGB encoding (srgbByte).
  const int w = 160, h = 90;
  CameraSpec spec;
  spec.given = true;
  spec.position = Vec3(0, -300, 10);
  spec.lookAt = Vec3(0, 0, 10);
  spec.fovDegrees = 20;
  spec.minPixels = 9;
  spec.trailSeconds = 1;
  const auto pebble = test::boxShape(Vec3(0.01, 0.01, 0.01));
  const Color red{0.7f, 0.05f, 0.05f};
  DrawListBuilder builder(spec, std::nullopt, w, h, 30);
  DrawList list;
  const auto at = [](int k) { return Vec3(-20 + 0.8 * k, 0, 6 + 0.1 * k); };
  for (int k = 0; k <= 40; ++k) {
    BodyView b = test::body(pebble, at(k));
    b.color = red;
    list = builder.build(std::vector<BodyView>{b});
  }
  gl::Renderer renderer(*context_, tinySettings(w, h));
  const Image image = renderer.render(list);
  const int r = srgbByte(0.7), g = srgbByte(0.05), b = srgbByte(0.05);
  const auto isRed = [&](int x, int y) {
    const std::uint8_t* p = image.pixel(x, y);
    return std::abs(p[0] - r) <= 1 && std::abs(p[1] - g) <= 1 && std::abs(p[2] - b) <= 1;
  };
  // The marker: centred where the body projects, as wide as its scaled cube projects.
  const Eigen::Vector2d centre = projectToPixel(list.camera, w, h, at(40));
  const int cx = static_cast<int>(centre.x()), cy = static_cast<int>(centre.y());
  EXPECT_TRUE(isRed(cx, cy)) << "marker centre at " << cx << ", " << cy;
  // Measured up and down (the trail joins the marker from the left).
  const Mat4& model = list.instances[0].model;
  double lo = 1e9, hi = -1e9;
  for (const Vec3& v : pebble->mesh.vertices) {
    const Vec4 world = model * Vec4(v.x(), v.y(), v.z(), 1);
    const double y = projectToPixel(list.camera, w, h, world.head<3>()).y();
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  int top = cy, bottom = cy;
  while (top > 0 && isRed(cx, top - 1)) --top;
  while (bottom + 1 < h && isRed(cx, bottom + 1)) ++bottom;
  // Fully covered pixels lie within the projected extent; partly covered edge pixels are mixed.
  EXPECT_GE(top, std::floor(lo));
  EXPECT_LE(bottom + 1, std::ceil(hi));
  EXPECT_GE(bottom - top + 1, std::floor(hi - lo) - 1);
  EXPECT_GE(hi - lo, 9 / std::sqrt(3.0) - 1e-9);  // the cube inside a 9-pixel sphere
  // The trail: where the body was 10 and 25 frames ago, in its colour; nothing red off it.
  for (const int k : {15, 30}) {
    const Eigen::Vector2d p = projectToPixel(list.camera, w, h, at(k));
    EXPECT_TRUE(isRed(static_cast<int>(p.x()), static_cast<int>(p.y()))) << "frame " << k;
    EXPECT_FALSE(isRed(static_cast<int>(p.x()), static_cast<int>(p.y()) + 4)) << "frame " << k;
  }
  // And nothing before the trail's one second (30 frames) begins: frame 5 is 35 frames ago.
  const Eigen::Vector2d old = projectToPixel(list.camera, w, h, at(5));
  EXPECT_FALSE(isRed(static_cast<int>(old.x()), static_cast<int>(old.y())));
}

TEST_F(Readback, OddSizesAndNoMultisamplingStillRender) {
  // 2x2 supersampling path (samples = 1 asked: none; samples = 64: more than llvmpipe has).
  const auto cube = test::boxShape(Vec3(0.25, 0.25, 0.25));
  const std::vector<BodyView> bodies{test::body(cube, Vec3(0, 0, 0.25))};
  gl::RenderSettings settings = tinySettings(33, 17);
  settings.samples = 64;
  gl::Renderer renderer(*context_, settings);
  EXPECT_EQ(renderer.antialiasing(), "2x2 supersampling");
  const Image image = renderer.render(litScene(bodies, 33.0 / 17.0));
  EXPECT_EQ(image.width, 33);
  EXPECT_EQ(image.height, 17);
}

// Copies of the real shaders into a scratch folder, with one file replaced.
std::string shaderCopy(const test::ScratchDir& dir, const std::string& name,
                       const std::string& text) {
  for (const auto& entry : std::filesystem::directory_iterator(gl::findShaderDir())) {
    std::filesystem::copy_file(entry.path(), dir.path() / entry.path().filename(),
                               std::filesystem::copy_options::overwrite_existing);
  }
  std::ofstream(dir.file(name)) << text;
  return dir.path().string();
}

TEST_F(Readback, ShaderCompileErrorNamesFileAndLine) {
  test::ScratchDir dir("shader_error");
  gl::RenderSettings settings = tinySettings();
  settings.shaderDir = shaderCopy(dir, "scene.frag",
                                  "#version 450 core\n"
                                  "out vec4 fragColor;\n"
                                  "void main() {\n"
                                  "  fragColor = vec4(undeclaredThing, 1.0);\n"
                                  "}\n");
  try {
    gl::Renderer renderer(*context_, settings);
    FAIL() << "a broken shader compiled";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene.frag:4"), std::string::npos) << what;
    EXPECT_NE(what.find("undeclaredThing"), std::string::npos) << what;
  }
}

TEST_F(Readback, ShaderErrorInAnIncludedFileNamesThatFile) {
  test::ScratchDir dir("include_error");
  // Line 5 of the included file is broken; the including file's line numbers must not leak.
  gl::RenderSettings settings = tinySettings();
  settings.shaderDir = shaderCopy(dir, "common.glsl",
                                  "// line 1\n// line 2\n// line 3\n// line 4\n"
                                  "float broken( { }\n");
  try {
    gl::Renderer renderer(*context_, settings);
    FAIL() << "a broken include compiled";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("common.glsl:5"), std::string::npos) << what;
  }
}

// EGL surfaceless is the second backend, with the same llvmpipe pixels (README: Using it).
TEST(EglBackend, RendersTheSamePixelsAsOsmesa) {
  const auto cube = test::boxShape(Vec3(0.25, 0.25, 0.25));
  const std::vector<BodyView> bodies{test::body(cube, Vec3(0, 0, 0.25))};
  const DrawList list = litScene(bodies, 1.5);
  const gl::RenderSettings settings = tinySettings(48, 32);
  Image osmesa;
  {
    auto context = gl::createContext(gl::Backend::osmesa);
    gl::Renderer renderer(*context, settings);
    osmesa = renderer.render(list);
  }
  std::unique_ptr<gl::Context> context;
  try {
    context = gl::createContext(gl::Backend::egl);
  } catch (const gl::GlError& e) {
    GTEST_SKIP() << "no EGL surfaceless context here: " << e.what();
  }
  if (context->description().find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "EGL runs on a GPU (" << context->description() << "): pixels may differ";
  }
  gl::Renderer renderer(*context, settings);
  EXPECT_EQ(renderer.render(list).rgb, osmesa.rgb);
}

TEST(ShaderDir, MissingExplicitFolderIsAClearError) {
  try {
    gl::findShaderDir("/nonexistent/voxfall/shaders");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/voxfall/shaders"), std::string::npos);
  }
}

TEST(GlBackend, UnknownNameIsRejected) {
  EXPECT_THROW(gl::parseBackend("vulkan"), gl::GlError);
  EXPECT_EQ(gl::parseBackend("egl"), gl::Backend::egl);
}

}  // namespace
}  // namespace vf
