// A transparent background (RenderSettings::alpha, [output] alpha, `render --alpha`), drawn
// in-process as `voxfall render` draws it, against the same frame drawn opaque: the sky and the
// bare floor are clear (alpha 0), a body is opaque (alpha 255) with the colour the opaque frame
// gives it, and the cube's shadow on the floor is kept as black with some opacity. The camera
// looks 23 degrees down at a cube at the origin, so the picture's centre is on the cube and
// its top rows (7 degrees above the horizon) are sky.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "render/gl/gl_context.h"
#include "render/gl/shader_program.h"
#include "render/scene_playback.h"
#include "render_test_util.h"
#include "sim/scene/scene.h"

namespace vf {
namespace {

const std::string kScenes = std::string(VOXFALL_SOURCE_DIR) + "/scenes";

SceneSpec cubeOnTheFloor(const test::ScratchDir& dir, bool alpha) {
  std::ofstream(dir.file("cube.toml"))
      << "[simulation]\nduration = 0.1\nlevel = 2\n[ground]\nplane = 0.0\n"
         "[shapes.cube]\nmesh = \""
      << kScenes
      << "/meshes/cube.obj\"\nscale = 0.3\ndensity = 800\n"
         "[[bodies]]\nshape = \"cube\"\nposition = [0.0, 0.0, 0.15]\n"
         "[camera]\nposition = [0.0, -3.0, 1.4]\nlook_at = [0.0, 0.0, 0.15]\nfov = 60\n"
         "[output]\nwidth = 192\nheight = 128\nalpha = "
      << (alpha ? "true" : "false") << "\n";
  return loadScene(dir.file("cube.toml"));
}

// The sun fixed in front of the camera and to its right, 40 degrees high: the shadow falls to
// the left and away from the camera, in view whatever the default light.
Image draw(const SceneSpec& spec) {
  auto context = gl::createContext(gl::Backend::osmesa);
  const auto sun = [](DrawList& list) { list.sunDirection = Vec3(0.6, -0.35, 0.64).normalized(); };
  return renderSceneFrames(spec, {0}, *context, gl::findShaderDir(), sun).images.at(0);
}

std::uint8_t alphaAt(const Image& image, int x, int y) {
  return image.alpha[static_cast<std::size_t>(y) * image.width + x];
}

TEST(AlphaRender, SkyAndBareFloorAreClearABodyIsOpaqueAndItsShadowKept) {
  test::ScratchDir dir("alpha_render");
  const Image clear = draw(cubeOnTheFloor(dir, true));
  const Image opaque = draw(cubeOnTheFloor(dir, false));
  EXPECT_TRUE(opaque.alpha.empty());
  ASSERT_EQ(clear.alpha.size(), static_cast<std::size_t>(192 * 128));
  // The sky: the top rows.
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 192; ++x) ASSERT_EQ(alphaAt(clear, x, y), 0) << x << ", " << y;
  // The floor in the bottom corners, over a metre from the cube and its shadow.
  EXPECT_EQ(alphaAt(clear, 0, 127), 0);
  EXPECT_EQ(alphaAt(clear, 191, 127), 0);
  // The cube around the picture's centre (it is 11 pixels wide there): opaque, in the opaque
  // frame's colours.
  for (int y = 62; y <= 66; ++y) {
    for (int x = 94; x <= 98; ++x) {
      EXPECT_EQ(alphaAt(clear, x, y), 255) << x << ", " << y;
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(clear.pixel(x, y)[c], opaque.pixel(x, y)[c])
            << x << ", " << y << " channel " << c;
    }
  }
  // The shadow: black, partly opaque, where the opaque frame shows floor darker than lit floor.
  int shadow = 0;
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 192; ++x) {
      const std::uint8_t* p = clear.pixel(x, y);
      if (p[0] == 0 && p[1] == 0 && p[2] == 0 && alphaAt(clear, x, y) >= 64) ++shadow;
    }
  }
  EXPECT_GT(shadow, 10) << "no shadow kept on the clear floor";  // it covers about 40 pixels
}

}  // namespace
}  // namespace vf
