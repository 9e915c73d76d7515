// Scene files -> SceneSpec -> World (sim/scene/scene_loader.cpp, scene_build.cpp).
//
// Error tests write a small scene into a temporary folder and check the oracle the user sees:
// the InputError's where() is "file:line:column" of the offending token (found by searching
// the scene text, so the expected position is independent of the loader) and its message.
// Build tests check what buildScene hands the World: centre-of-mass placement (against the
// mesh-file point that is the centroid, transformed by hand), emitter releases, seeded jitter.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "sim/core/error.h"
#include "sim/ground/rock_fall.h"
#include "sim/scene/scene.h"
#include "tests/support/scene_file_test.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

// A shape every error scene can refer to; the mesh file sits next to the scene.
const std::string kShape = "[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\n";

class SceneTest : public test::SceneFileTest {};

// --- syntax and unknown keys ------------------------------------------------------------------

TEST_F(SceneTest, SyntaxErrorCarriesTomlPosition) {
  const std::string path = write("scene.toml", "[simulation]\nduration = 2.0\nlevel = = 4\n");
  try {
    loadScene(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().rfind(path + ":3:", 0), 0u) << e.what();
    EXPECT_EQ(e.message().rfind("TOML syntax error", 0), 0u) << e.what();
  }
}

TEST_F(SceneTest, DuplicateKeyIsASyntaxError) {
  const std::string path = write("scene.toml", "[simulation]\nfps = 30\nfps = 60\n");
  try {
    loadScene(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().rfind(path + ":3:", 0), 0u) << e.what();
  }
}

TEST_F(SceneTest, MissingSceneFile) {
  const std::string path = (dir_ / "nope.toml").string();
  try {
    loadScene(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), path);
    EXPECT_NE(e.message().find("not found"), std::string::npos);
  }
}

TEST_F(SceneTest, OutputLookKeysAreRead) {
  SceneSpec spec = loadScene(write("scene.toml", "[simulation]\nduration = 1.0\n"));
  EXPECT_EQ(spec.output.speed, 1.0);  // the defaults: as drawn before these keys
  EXPECT_FALSE(spec.output.alpha || spec.output.overlayTime || spec.output.overlayScale);
  spec = loadScene(write(
      "scene.toml", "[output]\nspeed = 0.25\nalpha = true\noverlay = [\"scale\", \"time\"]\n"));
  EXPECT_EQ(spec.output.speed, 0.25);
  EXPECT_TRUE(spec.output.alpha);
  EXPECT_TRUE(spec.output.overlayTime);
  EXPECT_TRUE(spec.output.overlayScale);
  spec = loadScene(write("scene.toml", "[output]\noverlay = []\n"));
  EXPECT_FALSE(spec.output.overlayTime || spec.output.overlayScale);
}

TEST_F(SceneTest, UnknownKeySuggestsNearest) {
  const std::string text = "[contact]\nrestitutoin = { body_body = 0.5 }\n";
  expectError(text, "restitutoin",
              "unknown key 'restitutoin' in [contact]; did you mean 'restitution'?");
}

TEST_F(SceneTest, UnknownKeyFarFromAnyListsValidKeys) {
  expectError("[contact]\nbounciness = 0.5\n", "bounciness",
              "unknown key 'bounciness' in [contact]; valid keys: restitution, friction");
}

TEST_F(SceneTest, UnknownKeysInEveryTable) {
  expectError("[simulaton]\nduration = 1\n", "simulaton", "did you mean 'simulation'?");
  expectError("[simulation]\nduraton = 1\n", "duraton", "did you mean 'duration'?");
  expectError("[contact]\nfriction = { body_groud = 0.5 }\n", "body_groud",
              "unknown key 'body_groud' in [contact] friction; did you mean 'body_ground'?");
  expectError("[ground]\nplan = 0\n", "plan", "did you mean 'plane'?");
  expectError(kShape + "colour = [1, 0, 0]\n", "colour",
              "unknown key 'colour' in [shapes.cube]; did you mean 'color'?");
  expectError(kShape + "[[bodies]]\nshape = \"cube\"\npostion = [0, 0, 1]\n", "postion",
              "unknown key 'postion' in [[bodies]]; did you mean 'position'?");
  expectError(kShape + "[[emitters]]\nshape = \"cube\"\nposition = [0, 0, 1]\nintervall = 1\n",
              "intervall", "did you mean 'interval'?");
  expectError(kShape +
                  "[[emitters]]\nshape = \"cube\"\nposition = [0, 0, 1]\n"
                  "jitter = { sed = 3 }\n",
              "sed", "unknown key 'sed' in [[emitters]] jitter; did you mean 'seed'?");
  expectError("[camera]\nlookat = [0, 0, 0]\n", "lookat", "did you mean 'look_at'?");
  expectError("[output]\nwidht = 640\n", "widht", "did you mean 'width'?");
}

TEST_F(SceneTest, FirstUnknownKeyInFileOrderIsReported) {
  // Table iteration is alphabetical; the report must follow the file.
  expectError("[simulation]\nzzz = 1\naaa = 2\n", "zzz", "unknown key 'zzz'");
}

// --- types and values -------------------------------------------------------------------------

TEST_F(SceneTest, WrongTypes) {
  expectError("[simulation]\nduration = \"2\"\n", "\"2\"",
              "'duration' must be a number, got string");
  expectError("[simulation]\nlevel = 4.5\n", "4.5", "'level' must be an integer, got float");
  expectError("[simulation]\ngravity = [0, -9.81]\n", "[0, -9.81]",
              "'gravity' must be an array of 3 numbers [x, y, z], got an array of 2");
  expectError("[simulation]\ngravity = [0, 0, \"down\"]\n", "\"down\"",
              "'gravity[2]' must be a number, got string");
  expectError("[simulation]\nstep = true\n", "true", "'step' must be \"auto\"");
  expectError("[contact]\nrestitution = 0.5\n", "0.5", "'restitution' must be a table, got float");
  expectError(kShape + "[[bodies]]\nshape = \"cube\"\nstatic = 1\n", "1\n",
              "'static' must be true or false, got integer");
  expectError(kShape + "[bodies]\nshape = \"cube\"\n", "[bodies]",
              "'bodies' must be an array of tables");
  expectError("[shapes]\ncube = 3\n", "3", "'shapes.cube' must be a table");
}

TEST_F(SceneTest, ClearanceStepIsAnAutomaticRule) {
  using Kind = StepRule::Kind;
  const SceneSpec spec = loadScene(write("scene.toml", "[simulation]\nstep = \"clearance\"\n"));
  EXPECT_EQ(spec.step.kind, Kind::kClearance);
  EXPECT_EQ(sceneWorldDef(spec).step.kind, Kind::kClearance);
  SceneSpec fixed = spec;
  applyStepOverride(fixed, "1/100");  // `--step 1/100` replaces the rule
  EXPECT_EQ(fixed.step.kind, Kind::kFixed);
  EXPECT_EQ(fixed.step.seconds, 0.01);
  EXPECT_EQ(sceneWorldDef(fixed).step.kind, Kind::kFixed);
  SceneSpec eq20 = spec;
  applyStepOverride(eq20, "auto");
  EXPECT_EQ(eq20.step.kind, Kind::kEq20);
  applyStepOverride(eq20, "clearance");
  EXPECT_EQ(eq20.step.kind, Kind::kClearance);
}

// The scene's `step` takes the text `--step` takes: "1/120" as the paper writes its steps.
// 1/120 is not a double: the step must be the one division, as --step 1/120 gives.
TEST_F(SceneTest, StepAsAFraction) {
  const SceneSpec spec = loadScene(write("scene.toml", "[simulation]\nstep = \"1/120\"\n"));
  EXPECT_EQ(spec.step.kind, StepRule::Kind::kFixed);
  EXPECT_EQ(spec.step.seconds, 1.0 / 120.0);
  SceneSpec option = spec;
  option.step = StepRule::eq20();
  applyStepOverride(option, "1/120");
  EXPECT_EQ(option.step.seconds, spec.step.seconds);
  EXPECT_EQ(loadScene(write("scene.toml", "[simulation]\nstep = \"0.005\"\n")).step.seconds, 0.005);
  expectError("[simulation]\nstep = \"1/0\"\n", "\"1/0\"", "got \"1/0\"");
  expectError("[simulation]\nstep = \"-1/120\"\n", "\"-1/120\"",
              "seconds > 0, e.g. 0.005 or \"1/120\", got \"-1/120\"");
  expectError("[simulation]\nstep = \"1/120s\"\n", "\"1/120s\"", "got \"1/120s\"");
}

TEST_F(SceneTest, IntegersAreNumbers) {
  const std::string path =
      write("scene.toml", "[simulation]\nduration = 3\nstep = 1\ngravity = [0, 0, -10]\n");
  const SceneSpec spec = loadScene(path);
  EXPECT_EQ(spec.duration, 3.0);
  EXPECT_EQ(spec.step.kind, StepRule::Kind::kFixed);
  EXPECT_EQ(spec.step.seconds, 1.0);
  EXPECT_EQ(spec.gravity, Vec3(0, 0, -10));
}

TEST_F(SceneTest, ImpossibleValues) {
  expectError("[simulation]\nduration = 0\n", "0", "'duration' must be > 0 s, got 0");
  expectError("[simulation]\nduration = -1.5\n", "-1.5", "'duration' must be > 0 s, got -1.5");
  expectError("[simulation]\nduration = nan\n", "nan", "'duration' must be a finite number");
  expectError("[simulation]\nduration = inf\n", "inf", "'duration' must be a finite number");
  expectError("[simulation]\nfps = 0\n", "0", "'fps' must be > 0");
  expectError("[simulation]\nlevel = 0\n", "0", "'level' must be an integer from 1 to 10, got 0");
  expectError("[simulation]\nlevel = 11\n", "11",
              "'level' must be an integer from 1 to 10, got 11");
  expectError("[simulation]\nstep = 0\n", "0",
              "'step' must be \"auto\" (eq. 20), \"clearance\" (eq. 17 only where");
  expectError("[simulation]\nstep = -0.01\n", "-0.01", "got -0.01");
  expectError("[simulation]\nstep = \"fast\"\n", "\"fast\"", "got \"fast\"");
  expectError("[simulation]\ngravity = [0, 0, -inf]\n", "-inf", "'gravity[2]' must be a finite");
  expectError("[contact]\nrestitution = { body_body = 1.5 }\n", "1.5",
              "'restitution.body_body' must be between 0 and 1, got 1.5");
  expectError("[contact]\nrestitution = { body_ground = -0.1 }\n", "-0.1",
              "'restitution.body_ground' must be between 0 and 1");
  expectError("[contact]\nfriction = { body_ground = -0.1 }\n", "-0.1",
              "'friction.body_ground' must be >= 0");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = -800\n", "-800",
              "'density' must be > 0 kg/m^3, got -800");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\nlevel = 12\n", "12",
              "'level' must be an integer from 1 to 10");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\nscale = 0.0\n", "0.0",
              "'scale' must be > 0");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\nscale = [1, 0, 1]\n", "[1, 0, 1]",
              "'scale' factors must be > 0");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\ncolor = [1, 2, 0]\n", "2",
              "'color' components must be between 0 and 1");
  expectError(kShape + "[[bodies]]\nshape = \"cube\"\norientation = [0, 0, 0, 0]\n", "[0, 0, 0, 0]",
              "'orientation' must be a non-zero quaternion");
  expectError(kShape + "[[emitters]]\nshape = \"cube\"\ncount = -2\nposition = [0, 0, 1]\n", "-2",
              "'count' must be an integer from 1 to");
  expectError(kShape + "[[emitters]]\nshape = \"cube\"\ninterval = -1\nposition = [0, 0, 1]\n",
              "-1", "'interval' must be >= 0 s, got -1");
  expectError(kShape +
                  "[[emitters]]\nshape = \"cube\"\nposition = [0, 0, 1]\n"
                  "jitter = { direction = 200 }\n",
              "200", "'jitter.direction' must be between 0 and 180");
  expectError("[output]\nwidth = 0\n", "0", "the frame width must be 1..16384 pixels, got 0");
  expectError("[output]\nheight = 16385\n", "16385",
              "the frame height must be 1..16384 pixels, got 16385");
  expectError("[output]\ncrf = 52\n", "52", "'crf' must be an integer from 0 to 51, got 52");
  expectError("[output]\nspeed = 0\n", "0", "'speed' must be > 0");
  expectError("[output]\nalpha = 1\n", "1", "'alpha' must be true or false");
  expectError("[output]\noverlay = \"time\"\n", "\"time\"", "'overlay' must be an array");
  expectError("[output]\noverlay = [\"time\", \"scael\"]\n", "\"scael\"",
              "unknown overlay 'scael'; did you mean 'scale'?");
  expectError("[camera]\nfov = 180\n", "180", "'fov' must be a vertical field of view");
}

TEST_F(SceneTest, LightBySunDirectionOrDateAndItsColours) {
  const LightSpec byDirection =
      loadScene(write("a.toml",
                      "[light]\nazimuth = 135\nelevation = 30\n"
                      "intensity = 2\ncolor = [1, 0.9, 0.8]\n"
                      "sky = [0.1, 0.2, 0.3]\nambient = [0.05, 0.05, 0.04]\n"))
          .light;
  EXPECT_EQ(byDirection.azimuthDegrees, 135);
  EXPECT_EQ(byDirection.elevationDegrees, 30);
  EXPECT_FALSE(byDirection.date);
  EXPECT_EQ(byDirection.intensity, 2);
  EXPECT_EQ(byDirection.color, (Color{1.0f, 0.9f, 0.8f}));
  EXPECT_EQ(byDirection.sky, (Color{0.1f, 0.2f, 0.3f}));
  EXPECT_EQ(byDirection.ambient, (Color{0.05f, 0.05f, 0.04f}));
  // A date needs the terrain's place: any DEM file will do for the loader (the renderer asks
  // it for its CRS).
  fs::copy_file(std::string(VOXFALL_SOURCE_DIR) + "/scenes/terrain/cliff.asc", dir_ / "dem.asc");
  const LightSpec byDate =
      loadScene(write("b.toml",
                      "[ground]\nheightfield = \"dem.asc\"\n[light]\ndate = 2024-06-21\n"
                      "time = 10:30:15\n"))
          .light;
  ASSERT_TRUE(byDate.date);
  EXPECT_EQ(*byDate.date, (CivilDate{2024, 6, 21}));
  EXPECT_EQ(byDate.utcSeconds, 10 * 3600 + 30 * 60 + 15);
  EXPECT_FALSE(byDate.azimuthDegrees);
  // Unset: the defaults, no sun direction (the renderer's default sun).
  const LightSpec none = loadScene(write("c.toml", "")).light;
  EXPECT_FALSE(none.azimuthDegrees || none.date);
  EXPECT_TRUE(none.where.empty());
}

TEST_F(SceneTest, LightErrorsNameTheKey) {
  expectError("[light]\nazimuth = 10\n", "10", "'azimuth' needs 'elevation' too");
  expectError("[light]\nelevation = 10\n", "10", "'elevation' needs 'azimuth' too");
  expectError("[light]\nazimuth = 11\nelevation = 0\n", "0\n",
              "'elevation' must be above 0 and at most 90 degrees");
  expectError("[light]\nazimuth = 10\nelevation = 95\n", "95", "got 95");
  expectError("[light]\nazimuth = 400\nelevation = 10\n", "400",
              "'azimuth' must be between -360 and 360");
  expectError("[light]\nazimuth = 10\nelevation = 10\ndate = 2024-06-21\n", "2024",
              "either by 'azimuth' and 'elevation' or by 'date' and 'time'");
  expectError("[light]\ndate = 2024-06-21\ntime = 12:00:00\n", "2024",
              "give [ground] heightfield (a georeferenced DEM)");
  expectError("[light]\ndate = \"2024-06-21\"\ntime = 12:00:00\n", "\"2024",
              "'date' must be a TOML date, YYYY-MM-DD without quotes, got string");
  expectError("[light]\ndate = 2024-06-21\n", "2024", "'date' needs 'time' too (UTC)");
  expectError("[light]\ntime = 12:00:00\n", "12:", "'time' needs 'date' too");
  expectError("[light]\ndate = 1700-06-21\ntime = 12:00:00\n", "1700",
              "'date' must be in the years 1800 to 2200, got 1700");
  expectError("[light]\nintensity = -1\n", "-1", "'intensity' must be between 0 and 100");
  expectError("[light]\nsky = [0.1, 2, 0.1]\n", "2", "'sky' components must be between 0 and 1");
  expectError("[light]\nsun = 1\n", "sun", "unknown key 'sun' in [light]");
}

TEST_F(SceneTest, TerrainTextureAndSmoothShapes) {
  fs::copy_file(std::string(VOXFALL_SOURCE_DIR) + "/scenes/terrain/cliff.asc", dir_ / "dem.asc");
  std::ofstream(dir_ / "photo.tif") << "a file; the loader only checks that it exists";
  const SceneSpec spec =
      loadScene(write("a.toml", "[ground]\ntexture = \"photo.tif\"\nheightfield = \"dem.asc\"\n" +
                                    kShape + "smooth = 30\n"));
  EXPECT_EQ(spec.terrainTexturePath, (dir_ / "photo.tif").string());
  ASSERT_EQ(spec.shapes.size(), 1u);
  EXPECT_EQ(spec.shapes[0].smoothDegrees, 30);
  EXPECT_FALSE(loadScene(write("b.toml", kShape)).shapes[0].smoothDegrees);
  expectError("[ground]\ntexture = \"photo.tif\"\n", "\"photo",
              "'texture' is draped on the heightfield; give 'heightfield' too");
  expectError("[ground]\nheightfield = \"dem.asc\"\ntexture = \"none.tif\"\n", "\"none",
              "texture raster not found");
  expectError(kShape + "smooth = 200\n", "200", "'smooth' must be between 0 and 180");
}

TEST_F(SceneTest, MissingRequiredKeys) {
  expectError("[shapes.cube]\ndensity = 800\n", "[shapes.cube]",
              "missing required key 'mesh' (a mesh file) or 'rock' (a generated rock");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\n", "[shapes.cube]",
              "missing required key 'density' in [shapes.cube]");
  expectError(kShape + "[[bodies]]\nposition = [0, 0, 1]\n", "[[bodies]]",
              "missing required key 'shape' in [[bodies]]");
  expectError(kShape + "[[emitters]]\nshape = \"cube\"\ncount = 2\n", "[[emitters]]",
              "missing required key 'position' (or 'positions'");
  expectError(kShape +
                  "[[emitters]]\nshape = \"cube\"\nposition = [0, 0, 1]\n"
                  "positions = [[0, 0, 1]]\n",
              "[[0, 0, 1]]", "either 'position' or 'positions'");
}

TEST_F(SceneTest, UndefinedShapeSuggestsNearest) {
  expectError(kShape + "[[bodies]]\nshape = \"cubee\"\n", "\"cubee\"",
              "unknown shape 'cubee'; did you mean 'cube'?");
  expectError(kShape + "[[emitters]]\nshape = \"rock\"\nposition = [0, 0, 1]\n", "\"rock\"",
              "unknown shape 'rock'; defined shapes: cube");
  expectError("[[bodies]]\nshape = \"cube\"\n", "\"cube\"", "no shapes are defined");
}

TEST_F(SceneTest, MissingMeshNamesResolvedPath) {
  const std::string text = "[shapes.rock]\nmesh = \"meshes/rock.obj\"\ndensity = 2500\n";
  const std::string resolved = (dir_ / "meshes" / "rock.obj").string();
  expectError(text, "\"meshes/rock.obj\"", "mesh file not found: '" + resolved + "'");
  // A near miss in the same folder is suggested.
  expectError("[shapes.cube]\nmesh = \"cub.obj\"\ndensity = 800\n", "\"cub.obj\"",
              "did you mean '" + (dir_ / "cube.obj").string() + "'?");
}

TEST_F(SceneTest, CameraFollowMustNameABody) {
  expectError(kShape +
                  "[[bodies]]\nshape = \"cube\"\n"
                  "[[emitters]]\nshape = \"cube\"\ncount = 3\nposition = [0, 0, 1]\n"
                  "[camera]\nfollow = 4\n",
              "4\n", "'follow' must be a body index from 0 to 3");
  const std::string path = write("scene.toml", kShape +
                                                   "[[bodies]]\nshape = \"cube\"\n"
                                                   "[camera]\nfollow = 0\nfov = 50\n");
  const SceneSpec spec = loadScene(path);
  EXPECT_TRUE(spec.camera.given);
  EXPECT_EQ(spec.camera.followBody, 0);
  EXPECT_EQ(spec.camera.fovDegrees, 50);
}

TEST_F(SceneTest, SeveralNamedCamerasAndPickingOne) {
  const std::string text = kShape +
                           "[[bodies]]\nshape = \"cube\"\n[[bodies]]\nshape = \"cube\"\n"
                           "[camera]\nposition = [4, -6, 3]\nlook_at = [0, 0, 0]\n"
                           "[cameras.wide]\nmin_pixels = 5\ntrail = 2.5\n"
                           "[cameras.chase]\nfollow = [0, 1]\nsmoothing = 0.4\n"
                           "position = [0, -5, 2]\nlook_at = [0, 0, 0]\n"
                           "[cameras.fly]\npath = [{ time = 0, position = [0, -9, 3], look_at = "
                           "[0, 0, 0] }, { time = 2, position = [9, 0, 3], look_at = [0, 0, 1], "
                           "fov = 30 }]\n";
  SceneSpec spec = loadScene(write("scene.toml", text));
  EXPECT_TRUE(spec.camera.given);
  ASSERT_EQ(spec.cameras.size(), 3u);  // file order, not key order
  EXPECT_EQ(spec.cameras[0].name, "wide");
  EXPECT_FALSE(spec.cameras[0].given);  // automatic, with markers and trails
  EXPECT_EQ(spec.cameras[0].minPixels, 5);
  EXPECT_EQ(spec.cameras[0].trailSeconds, 2.5);
  EXPECT_EQ(spec.cameras[1].followGroup, (std::vector<int>{0, 1}));
  EXPECT_EQ(spec.cameras[1].smoothing, 0.4);
  ASSERT_EQ(spec.cameras[2].path.size(), 2u);
  EXPECT_EQ(spec.cameras[2].path[0].fovDegrees, 40);  // the camera's fov by default
  EXPECT_EQ(spec.cameras[2].path[1].fovDegrees, 30);
  EXPECT_EQ(spec.cameras[2].path[1].lookAt, Vec3(0, 0, 1));
  selectCamera(spec, "chase");
  EXPECT_EQ(spec.camera.name, "chase");
  EXPECT_EQ(spec.camera.smoothing, 0.4);
  try {
    selectCamera(spec, "drone");
    ADD_FAILURE() << "an unknown camera was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no camera named 'drone'; the scene has: camera, wide, "
                                         "chase, fly"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(SceneTest, CameraPathKeysMustBeInTimeOrder) {
  expectError(kShape +
                  "[cameras.fly]\npath = [{ time = 1, position = [0, -9, 3], look_at = [0, "
                  "0, 0] }, { time = 0.5, position = [9, 0, 3], look_at = [0, 0, 1] }]\n",
              "0.5, position", "path key times must increase");
  expectError(kShape + "[cameras.fly]\npath = [{ time = 1, position = [0, -9, 3] }]\n", "{ time",
              "missing required key 'look_at'");
  expectError(kShape + "[cameras.x]\ntrails = 2\n", "trails", "did you mean 'trail'?");
}

TEST_F(SceneTest, MethodSetsBothExtensionsAndEachKeyOverridesIt) {
  auto extensions = [&](const std::string& simulation) {
    const SceneSpec spec = loadScene(write("scene.toml", "[simulation]\n" + simulation));
    return std::make_pair(spec.contactReduction, spec.sleep);
  };
  using P = std::pair<bool, bool>;
  EXPECT_EQ(extensions(""), P(true, true)) << "no key: the fast path";
  EXPECT_EQ(extensions("method = \"fast\"\n"), P(true, true));
  EXPECT_EQ(extensions("method = \"paper\"\n"), P(false, false));
  EXPECT_EQ(extensions("method = \"paper\"\nsleep = true\n"), P(false, true));
  EXPECT_EQ(extensions("contact_reduction = false\nmethod = \"fast\"\n"), P(false, true))
      << "a key overrides the method wherever it stands";
  EXPECT_EQ(extensions("sleep = false\n"), P(true, false));
}

TEST_F(SceneTest, UnknownMethodIsAnError) {
  expectError("[simulation]\nmethod = \"quick\"\n", "\"quick\"",
              "'method' must be \"fast\" (contact reduction and sleeping, the default) or "
              "\"paper\"");
}

// --- what loads -------------------------------------------------------------------------------

TEST_F(SceneTest, DefaultsAndNormalisation) {
  const std::string path =
      write("my_scene.toml", kShape + "[[bodies]]\nshape = \"cube\"\norientation = [2, 0, 0, 0]\n");
  const SceneSpec spec = loadScene(path);
  EXPECT_EQ(spec.name, "my_scene");
  EXPECT_EQ(spec.path, path);
  EXPECT_EQ(spec.step.kind, StepRule::Kind::kEq20);  // the paper's rule
  EXPECT_EQ(spec.level, 4);
  EXPECT_FALSE(spec.groundPlane.has_value());
  EXPECT_FALSE(spec.camera.given);
  ASSERT_EQ(spec.bodies.size(), 1u);
  EXPECT_EQ(spec.bodies[0].orientation.coeffs(), Quat::Identity().coeffs());
  EXPECT_EQ(spec.bodies[0].where, path + ":4:1");
  EXPECT_EQ(spec.shapes[0].where, path + ":1:1");
}

TEST_F(SceneTest, RelativeMeshPathsResolveAgainstTheSceneFolder) {
  fs::create_directories(dir_ / "meshes");
  fs::copy_file(dir_ / "cube.obj", dir_ / "meshes" / "box.obj");
  const std::string path = write("sub/scene.toml",
                                 "[shapes.a]\nmesh = \"../meshes/box.obj\"\ndensity = 1\n"
                                 "[shapes.b]\nmesh = \"" +
                                     (dir_ / "cube.obj").string() + "\"\ndensity = 1\n");
  const SceneSpec spec = loadScene(path);
  ASSERT_EQ(spec.shapes.size(), 2u);
  EXPECT_EQ(spec.shapes[0].name, "a");
  EXPECT_EQ(fs::path(spec.shapes[0].meshPath), (dir_ / "meshes" / "box.obj").lexically_normal());
  EXPECT_EQ(spec.shapes[1].meshPath, (dir_ / "cube.obj").string());
}

TEST_F(SceneTest, ShapesKeepFileOrder) {
  const std::string path =
      write("scene.toml",
            "[shapes.zeta]\nmesh = \"cube.obj\"\ndensity = 1\n"
            "[shapes.alpha]\nmesh = \"cube.obj\"\ndensity = 1\nscale = [1, 2, 3]\n");
  const SceneSpec spec = loadScene(path);
  ASSERT_EQ(spec.shapes.size(), 2u);
  EXPECT_EQ(spec.shapes[0].name, "zeta");
  EXPECT_EQ(spec.shapes[1].name, "alpha");
  EXPECT_EQ(spec.shapes[1].scale, Vec3(1, 2, 3));
}

TEST_F(SceneTest, EmitterPositionsAndJitter) {
  const std::string path =
      write("scene.toml", kShape +
                              "[[emitters]]\nshape = \"cube\"\ncount = 5\nstart = 1\n"
                              "interval = 0.5\npositions = [[0, 0, 1], [2, 0, 1]]\n"
                              "jitter = { position = 0.1, direction = 30, orientation = true, "
                              "seed = 7 }\n");
  const SceneSpec spec = loadScene(path);
  ASSERT_EQ(spec.emitters.size(), 1u);
  const EmitterSpec& e = spec.emitters[0];
  EXPECT_EQ(e.count, 5);
  EXPECT_EQ(e.start, 1.0);
  EXPECT_EQ(e.interval, 0.5);
  ASSERT_EQ(e.positions.size(), 2u);
  EXPECT_EQ(e.positions[1], Vec3(2, 0, 1));
  EXPECT_EQ(e.positionJitter, 0.1);
  EXPECT_EQ(e.directionJitter, 30.0);
  EXPECT_TRUE(e.randomOrientation);
  EXPECT_EQ(e.seed, 7u);
}

TEST(ShippedScenes, CubesIsExample1) {
  const std::string path = std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml";
  const SceneSpec spec = loadScene(path);
  EXPECT_EQ(spec.name, "cubes");
  EXPECT_EQ(spec.duration, 2.0);
  EXPECT_EQ(spec.level, 4);
  EXPECT_EQ(spec.step.kind, StepRule::Kind::kEq20);
  EXPECT_EQ(spec.gravity, Vec3(0, 0, -9.81));
  EXPECT_EQ(spec.contact.restitutionBodyBody, 0.5);
  EXPECT_EQ(spec.contact.restitutionBodyGround, 0.3);
  EXPECT_EQ(spec.contact.frictionBodyBody, 0.3);
  EXPECT_EQ(spec.contact.frictionBodyGround, 0.5);  // example 1's floor friction
  EXPECT_EQ(spec.groundPlane, 0.0);
  ASSERT_EQ(spec.shapes.size(), 1u);
  EXPECT_EQ(spec.shapes[0].scale, Vec3::Constant(0.30));
  EXPECT_EQ(spec.shapes[0].density, 800);
  EXPECT_TRUE(fs::is_regular_file(spec.shapes[0].meshPath));
  ASSERT_EQ(spec.bodies.size(), 2u);
  EXPECT_EQ(spec.bodies[0].position, Vec3(0, 0, 0.15));
  EXPECT_EQ(spec.bodies[0].velocity, Vec3::Zero());
  EXPECT_EQ(spec.bodies[1].position, Vec3(1.0, 0.2, 0.3));
  EXPECT_EQ(spec.bodies[1].velocity, Vec3(-5, 0, 0));
  EXPECT_EQ(spec.bodies[1].angularVelocity, Vec3::Zero());
}

TEST(ShippedScenes, BlocksIsExample2) {
  const std::string path = std::string(VOXFALL_SOURCE_DIR) + "/scenes/blocks.toml";
  const SceneSpec spec = loadScene(path);
  EXPECT_EQ(spec.name, "blocks");
  EXPECT_EQ(spec.duration, 5.0);
  EXPECT_EQ(spec.level, 4);
  EXPECT_EQ(spec.step.kind, StepRule::Kind::kEq20);
  EXPECT_EQ(spec.contact.frictionBodyGround, 0.8);
  ASSERT_EQ(spec.emitters.size(), 1u);
  const EmitterSpec& e = spec.emitters[0];
  EXPECT_EQ(e.count, 10);
  EXPECT_EQ(e.start, 0.0);
  EXPECT_EQ(e.interval, 0.4);
  EXPECT_NEAR(e.start + (e.count - 1) * e.interval, 3.6, 1e-12);  // last throw at t = 3.6 s
  ASSERT_EQ(e.positions.size(), 1u);
  EXPECT_EQ(e.positions[0], Vec3(0, 0, 1));
  EXPECT_EQ(e.velocity, Vec3(2, 0, 0.5));
  EXPECT_EQ(spec.shapes[0].density, 800);
}

// --- buildScene -------------------------------------------------------------------------------

// A unit cube with a corner at the mesh file's origin: its centroid is (0.5, 0.5, 0.5).
const char* kCornerCubeObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
    "f 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";

TEST_F(SceneTest, OffCentreMeshIsPlacedByItsFileOrigin) {
  write("corner.obj", kCornerCubeObj);
  // Scale 0.5 and a quarter turn about z: the file origin goes to `position`, so the centroid
  // (0.25, 0.25, 0.25) after scaling lands at position + Rz(90) * (0.25, 0.25, 0.25).
  const std::string path = write("scene.toml",
                                 "[simulation]\nlevel = 2\n"
                                 "[shapes.c]\nmesh = \"corner.obj\"\nscale = 0.5\ndensity = 1000\n"
                                 "[[bodies]]\nshape = \"c\"\nposition = [1, 2, 3]\n"
                                 "orientation = [0.7071067811865476, 0, 0, 0.7071067811865476]\n");
  const BuiltScene built = buildScene(loadScene(path));
  ASSERT_EQ(built.world->bodyCount(), 1);
  const Vec3 expected = Vec3(1, 2, 3) + Vec3(-0.25, 0.25, 0.25);
  EXPECT_LT((built.world->state(0).x - expected).norm(), 1e-12);
  EXPECT_NEAR(built.world->shape(0).mass, 1000 * 0.125, 1e-9);
}

TEST_F(SceneTest, MassInsteadOfDensityAndYUpMeshes) {
  write("corner.obj", kCornerCubeObj);
  // The unit corner cube scaled [1, 2, 4] (in the file's axes) has volume 8 m^3: mass 100 kg
  // is density 12.5. With up = "y" the file's y (2 m) becomes z and the file's z (4 m) -y.
  const std::string path =
      write("scene.toml",
            "[simulation]\nlevel = 2\n"
            "[shapes.a]\nmesh = \"corner.obj\"\nscale = [1, 2, 4]\nmass = 100\n"
            "[shapes.b]\nmesh = \"corner.obj\"\nscale = [1, 2, 4]\nmass = 100\nup = \"y\"\n"
            "[[bodies]]\nshape = \"a\"\n[[bodies]]\nshape = \"b\"\nposition = [5, 0, 0]\n");
  const BuiltScene built = buildScene(loadScene(path));
  const World& w = *built.world;
  EXPECT_NEAR(w.shape(0).mass, 100.0, 1e-9);
  EXPECT_NEAR(w.shape(1).mass, 100.0, 1e-9);
  // Box a: 1 x 2 x 4 (x, y, z); box b after the rotation: 1 x 4 x 2. Compare inertia about z:
  // m (x^2 + y^2) / 12.
  EXPECT_NEAR(w.shape(0).inertiaBody(2, 2), 100.0 * (1 + 4) / 12, 1e-9);
  EXPECT_NEAR(w.shape(1).inertiaBody(2, 2), 100.0 * (1 + 16) / 12, 1e-9);
  // File origin -> position: the corner at (0, 0, 0) of the file; b's centroid is at
  // (0.5, -2, 1) after the rotation (file z in [0, 4] goes to y in [-4, 0]).
  EXPECT_LT((w.state(1).x - Vec3(5.5, -2, 1)).norm(), 1e-12);
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\ndensity = 800\nmass = 3\n", "3",
              "give either 'density' or 'mass' in [shapes.cube], not both");
  expectError("[shapes.cube]\nmesh = \"cube.obj\"\nmass = 3\nup = \"x\"\n", "\"x\"",
              "'up' must be \"z\" (the default) or \"y\"");
}

TEST_F(SceneTest, DropHeightOfABodyMeasuresFromTheSurfaceUnderIt) {
  // Terrain z = 0.5 x on a 5 m grid (slope 26.6 degrees), the unit cube dropped 0.1 m: its
  // lowest corner above the surface by exactly 0.1 m, measured straight down (not from the
  // highest grid node near it, which would be up to 2.5 m higher).
  std::string grid = "ncols 5\nnrows 5\nxllcenter 0\nyllcenter 0\ncellsize 5\n";
  for (int row = 0; row < 5; ++row) {
    for (int i = 0; i < 5; ++i) grid += std::to_string(0.5 * 5 * i) + " ";
    grid += "\n";
  }
  write("slope.asc", grid);
  const std::string path =
      write("scene.toml",
            kShape +
                "[ground]\nheightfield = \"slope.asc\"\n"
                "[[bodies]]\nshape = \"cube\"\nposition = [7.3, 10, 50]\ndrop_height = 0.1\n");
  const BuiltScene built = buildScene(loadScene(path));
  const World& w = *built.world;
  const Mat3 R = w.state(0).q.toRotationMatrix();
  double gap = INFINITY;
  for (const Vec3& v : w.shape(0).mesh.vertices) {
    const Vec3 p = w.state(0).x + R * v;
    gap = std::min(gap, p.z() - 0.5 * p.x());
  }
  EXPECT_NEAR(gap, 0.1, 1e-9);

  // `offset` moves the DEM: world = file coordinates + offset, and remembers the shift.
  const std::string moved =
      write("moved.toml", kShape + "[ground]\nheightfield = \"slope.asc\"\noffset = [-5, 2, 1]\n");
  const BuiltScene m = buildScene(loadScene(moved));
  const Heightfield& t = *m.world->def().terrain;
  EXPECT_NEAR(t.heightAt(3.0, 4.0), 0.5 * (3.0 + 5) + 1, 1e-12);
  EXPECT_EQ(t.shift, Vec3(-5, 2, 1));
}

TEST_F(SceneTest, GroundMaterialsByNameOrByClassRaster) {
  // DEM 4 x 3 samples of 10 m, flat; class raster on the same grid: west half class 1, east
  // half class 2, one NODATA sample (falls back to `material`).
  const std::string head =
      "ncols 4\nnrows 3\nxllcenter 0\nyllcenter 0\ncellsize 10\nNODATA_value -1\n";
  write("dem.asc", head + "0 0 0 0\n0 0 0 0\n0 0 0 0\n");
  write("classes.asc", head + "1 1 2 2\n1 1 2 2\n1 -1 2 2\n");
  const std::string path = write(
      "scene.toml",
      kShape +
          "[contact]\nfriction = { body_ground = 0.7 }\n"
          "[ground]\nheightfield = \"dem.asc\"\nmaterial = \"bedrock\"\n"
          "classes = \"classes.asc\"\nclass_materials = { 1 = \"meadow\", 2 = \"colluvial\" }\n"
          "[ground.materials.meadow]\nrolling_resistance = 0.9\nrestitution = 0.1\n"
          "tangential_restitution = 0.45\n");
  const BuiltScene built = buildScene(loadScene(path));
  const GroundMap& g = *built.rockFall->def().ground;
  // STONE table (Guzzetti et al. 2002): non-schist bedrock 0.30 / Rn 65 % / Rt 75 %, colluvial
  // 0.80 / 15 % / 40 %.
  EXPECT_EQ(g.at(4, 4).name, "meadow");
  EXPECT_EQ(g.at(4, 4).rollingResistance, 0.9);
  EXPECT_EQ(g.at(4, 4).friction, 0.7);  // unset: [contact] body_ground
  EXPECT_EQ(g.at(4, 4).tangentialRestitution, 0.45);
  EXPECT_EQ(g.at(26, 4).name, "colluvial");
  EXPECT_EQ(g.at(26, 4).rollingResistance, 0.80);
  EXPECT_EQ(g.at(26, 4).restitution, 0.15);
  EXPECT_EQ(g.at(26, 4).tangentialRestitution, 0.40);
  EXPECT_EQ(g.at(10, 0).name, "bedrock");  // the NODATA class sample
  EXPECT_EQ(g.at(10, 0).rollingResistance, 0.30);
  EXPECT_EQ(g.at(10, 0).restitution, 0.65);
  EXPECT_EQ(g.at(10, 0).tangentialRestitution, 0.75);
  // Without `material` the paper's model stands: no ground map at all.
  const std::string plain = write("plain.toml", kShape + "[ground]\nheightfield = \"dem.asc\"\n");
  EXPECT_EQ(buildScene(loadScene(plain)).rockFall->def().ground, nullptr);
  expectError(kShape + "[ground.materials.scree]\ntangential_restitution = 1.5\n", "1.5",
              "'tangential_restitution' must be between 0 and 1, got 1.5");
  expectError(kShape + "[ground]\nplane = 0\nmaterial = \"bedrok\"\n", "\"bedrok\"",
              "unknown ground material 'bedrok'; did you mean 'bedrock'?");
  // A class raster on another grid is refused.
  write("small.asc", "ncols 2\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 10\n1 1\n1 1\n");
  const std::string off =
      write("off.toml", kShape +
                            "[ground]\nheightfield = \"dem.asc\"\nmaterial = \"bedrock\"\n"
                            "classes = \"small.asc\"\nclass_materials = { 1 = \"bedrock\" }\n");
  EXPECT_THROW(buildScene(loadScene(off)), InputError);
}

// The slip law's presets load with their published numbers (Lu et al. 2019 citing Bartelt et
// al. 2016; Leine et al. 2014 section 5.1) and record their sources; a custom slip material
// takes its four coefficients and eps_N 0 by default; mixing laws across classes works; the
// per-cell variability keys reach the ground map.
TEST_F(SceneTest, SlipLawPresetsCustomMaterialsAndVariability) {
  const std::string head = "ncols 4\nnrows 3\nxllcenter 0\nyllcenter 0\ncellsize 10\n";
  write("dem.asc", head + "0 0 0 0\n0 0 0 0\n0 0 0 0\n");
  write("classes.asc", head + "1 1 2 2\n1 1 2 2\n1 1 2 2\n");
  const std::string path = write(
      "scene.toml", kShape +
                        "[contact]\nrestitution = { body_ground = 0.4 }\n"
                        "[ground]\nheightfield = \"dem.asc\"\nmaterial = \"ramms_chant_sura\"\n"
                        "classes = \"classes.asc\"\n"
                        "class_materials = { 1 = \"scar\", 2 = \"glacial_deposits\" }\n"
                        "variability = 0.1\nvariability_seed = 42\n"
                        "[ground.materials.scar]\nlaw = \"slip\"\nmu_min = 0.3\nmu_max = 0.9\n"
                        "kappa = 2\nbeta = 50\n");
  const BuiltScene built = buildScene(loadScene(path));
  const GroundMap& g = *built.rockFall->def().ground;
  // A slip material's numbers (mu_min, mu_max, kappa, beta, eps_N) and a word of its source.
  auto expectSlip = [](const GroundMaterial& m, std::array<double, 5> v, const std::string& word) {
    EXPECT_EQ(m.law, GroundLawKind::kSlip) << m.name;
    EXPECT_EQ((std::array<double, 5>{m.muMin, m.muMax, m.kappa, m.beta, m.restitution}), v)
        << m.name;
    EXPECT_NE(m.source.find(word), std::string::npos) << m.source;
  };
  expectSlip(g.materials[0], {0.55, 2.0, 3.0, 185.0, 0.0}, "Bartelt");
  EXPECT_NE(g.materials[0].source.find("Lu"), std::string::npos) << g.materials[0].source;
  expectSlip(*groundPreset("leine2014_demo", 0.8), {0.2, 1.3, 0.7, 20.0, 0.0}, "Leine");
  // The custom slip class: its four numbers, eps_N 0 (not [contact]'s 0.4); the STONE class.
  const GroundMaterial& scar = g.at(4, 4);
  EXPECT_EQ(scar.name, "scar");
  expectSlip(scar, {0.3, 0.9, 2.0, 50.0, 0.0}, "scene");
  EXPECT_EQ(g.at(26, 4).name, "glacial_deposits");
  EXPECT_EQ(g.at(26, 4).law, GroundLawKind::kStone);
  EXPECT_TRUE(g.hasSlip());
  EXPECT_EQ(g.variability, 0.1);
  EXPECT_EQ(g.variabilitySeed, 42u);
  EXPECT_EQ(g.cells, built.world->def().terrain);
  // mu(s) at s = 0 and far along: mu_min and (nearly) mu_max.
  EXPECT_EQ(slipFriction(scar, 0.0), 0.3);
  EXPECT_NEAR(slipFriction(scar, 1e9), 0.9, 1e-9);
  // STONE scenes: no slip material, variability off unless asked.
  const std::string stone =
      write("stone.toml", kShape + "[ground]\nplane = 0\nmaterial = \"bedrock\"\n");
  const BuiltScene stoneBuilt = buildScene(loadScene(stone));  // owns the ground map below
  const GroundMap& s = *stoneBuilt.rockFall->def().ground;
  EXPECT_FALSE(s.hasSlip());
  EXPECT_EQ(s.variability, 0.0);
}

// Bad slip-law and variability input: one error naming the key, at its place in the file.
TEST_F(SceneTest, SlipLawAndVariabilityErrorsNameTheKey) {
  const std::string slip = "[ground.materials.scar]\nlaw = \"slip\"\n";
  const std::string four = "mu_min = 0.3\nmu_max = 0.9\nkappa = 2\nbeta = 50\n";
  expectError(kShape + "[ground.materials.scar]\nlaw = \"ramms\"\n", "\"ramms\"",
              "'law' must be \"stone\" (STONE's bounce and rolling, the default) or \"slip\"");
  expectError(kShape + slip + "mu_min = 0.3\nmu_max = 0.9\nkappa = -2\nbeta = 50\n", "-2",
              "'kappa' must be >= 0 1/m (slippage hardening), got -2");
  expectError(kShape + slip + "mu_min = 0.3\nmu_max = 0.9\nkappa = 2\nbeta = -5\n", "-5",
              "'beta' must be >= 0 1/s (slippage softening), got -5");
  expectError(kShape + slip + "mu_min = 0.3\nmu_max = 0.2\nkappa = 2\nbeta = 5\n", "0.2",
              "'mu_max' must be >= 'mu_min' (0.3): friction grows with slippage, got 0.2");
  expectError(kShape + slip + "mu_min = 0.3\nkappa = 2\nbeta = 5\n", "[ground.materials.scar]",
              "has law = \"slip\" and needs mu_min, mu_max, kappa and beta; 'mu_max' is missing");
  expectError(kShape + slip + four + "friction = 0.5\n", "0.5\n",
              "'friction' is not used by law = \"slip\"");
  expectError(kShape + "[ground.materials.scar]\nkappa = 2\n", "2",
              "'kappa' belongs to law = \"slip\"; give law = \"slip\" in [ground.materials.scar]");
  expectError(kShape + "[ground]\nplane = 0\nmaterial = \"bedrock\"\nvariability = 1.5\n", "1.5",
              "'variability' must be >= 0 and < 1");
  expectError(kShape + "[ground]\nplane = 0\nmaterial = \"bedrock\"\nvariability = 0.1\n", "0.1",
              "'variability' perturbs the ground per DEM cell; give 'heightfield' too");
  expectError(kShape + "[ground]\nplane = 0\nvariability_seed = 3\n", "3",
              "'variability_seed' seeds 'variability'; give 'variability' too");
}

TEST_F(SceneTest, RockfallRunKeys) {
  write("flat.asc", "ncols 2\nnrows 2\nxllcenter 0\nyllcenter 0\ncellsize 1\n0 0\n0 0\n");
  const std::string path =
      write("scene.toml", kShape +
                              "[simulation]\nstop = \"all_at_rest\"\nrotation = \"midpoint\"\n"
                              "rest = { speed = 0.2, time = 2.0 }\n"
                              "[ground]\nheightfield = \"flat.asc\"\nedge = \"wall\"\n");
  const SceneSpec spec = loadScene(path);
  EXPECT_TRUE(spec.stopWhenSettled);
  EXPECT_EQ(spec.rotation, RotationUpdate::kMidpoint);
  EXPECT_EQ(spec.rest.speed, 0.2);
  EXPECT_EQ(spec.rest.time, 2.0);
  EXPECT_EQ(spec.terrainEdge, TerrainEdge::kWall);
  const BuiltScene built = buildScene(spec);
  EXPECT_EQ(built.world->def().rotation, RotationUpdate::kMidpoint);
  EXPECT_EQ(built.rockFall->def().terrainEdge, TerrainEdge::kWall);
  // Defaults: the paper's rotation update, run to the duration, edge policy automatic.
  const SceneSpec plain = loadScene(write("plain.toml", kShape));
  EXPECT_EQ(plain.rotation, RotationUpdate::kExplicitEuler);
  EXPECT_FALSE(plain.stopWhenSettled);
  EXPECT_EQ(plain.terrainEdge, TerrainEdge::kAuto);
  // With a ground material the default becomes the midpoint rule; an explicit key still wins.
  const std::string rock = kShape + "[ground]\nplane = 0\nmaterial = \"bedrock\"\n";
  EXPECT_EQ(loadScene(write("rock.toml", rock)).rotation, RotationUpdate::kMidpoint);
  EXPECT_EQ(loadScene(write("euler.toml", "[simulation]\nrotation = \"euler\"\n" + rock)).rotation,
            RotationUpdate::kExplicitEuler);
  expectError(kShape + "[simulation]\nstop = \"never\"\n", "\"never\"", "'stop' must be");
  expectError(kShape + "[simulation]\nrotation = \"rk4\"\n", "\"rk4\"", "'rotation' must be");
  expectError(kShape + "[ground]\nplane = 0\nedge = \"bounce\"\n", "\"bounce\"", "'edge' must be");
}

TEST_F(SceneTest, ShapesShareTreesAndColoursFallBack) {
  const std::string path =
      write("scene.toml",
            "[simulation]\nlevel = 2\n"
            "[shapes.a]\nmesh = \"cube.obj\"\ndensity = 800\ncolor = [0.1, 0.2, 0.3]\n"
            "[shapes.b]\nmesh = \"cube.obj\"\ndensity = 2500\n"
            "[shapes.c]\nmesh = \"cube.obj\"\ndensity = 800\nlevel = 3\n"
            "[[bodies]]\nshape = \"a\"\nposition = [0, 0, 0]\n"
            "[[bodies]]\nshape = \"b\"\nposition = [3, 0, 0]\n"
            "[[bodies]]\nshape = \"c\"\nposition = [6, 0, 0]\n"
            "[[bodies]]\nshape = \"a\"\nposition = [9, 0, 0]\ncolor = [1, 1, 1]\n");
  const BuiltScene built = buildScene(loadScene(path));
  ASSERT_EQ(built.world->bodyCount(), 4);
  const World& w = *built.world;
  // Same mesh, scale and level: one tree whatever the density; another level: another tree.
  EXPECT_EQ(w.shape(0).tree.get(), w.shape(1).tree.get());
  EXPECT_NE(w.shape(0).tree.get(), w.shape(2).tree.get());
  EXPECT_EQ(w.shape(0).tree->leafLevel(), 2);
  EXPECT_EQ(w.shape(2).tree->leafLevel(), 3);
  EXPECT_EQ(w.shapePtr(0).get(), w.shapePtr(3).get());
  EXPECT_NEAR(w.shape(1).mass, 2500.0, 1e-9);
  EXPECT_EQ(built.shapeOf, (std::vector<std::string>{"a", "b", "c", "a"}));
  EXPECT_EQ(built.colors[0], (Color{0.1f, 0.2f, 0.3f}));  // shape colour
  EXPECT_EQ(built.colors[3], (Color{1.0f, 1.0f, 1.0f}));  // body colour wins
  EXPECT_EQ(built.colors[1], defaultBodyColor(1));        // palette, by body id
  EXPECT_EQ(built.colors[2], defaultBodyColor(2));
  EXPECT_NE(built.colors[1], built.colors[2]);
}

TEST_F(SceneTest, BodiesOfOneShapeGetDistinctPaletteColours) {
  // Example 1's two cubes share a shape: told apart only if each body gets its own colour.
  const BuiltScene built =
      buildScene(loadScene(std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml"));
  ASSERT_EQ(built.colors.size(), 2u);
  EXPECT_NE(built.colors[0], built.colors[1]);
  for (const Color& c : built.colors)
    for (float v : c) EXPECT_TRUE(v >= 0 && v <= 1);
}

// An emitter of `count` cubes cycling through three spots far apart, no ground.
std::string emitterScene(int seed, double positionJitter, double directionJitter,
                         bool orientation) {
  return kShape +
         "[simulation]\nlevel = 2\nduration = 3\n"
         "[[emitters]]\nshape = \"cube\"\ncount = 7\nstart = 0.25\ninterval = 0.5\n"
         "positions = [[-20, 0, 0], [0, 20, 0], [20, 0, 0]]\nvelocity = [1, 0, 2]\n"
         "jitter = { position = " +
         std::to_string(positionJitter) + ", direction = " + std::to_string(directionJitter) +
         ", orientation = " + (orientation ? "true" : "false") +
         ", seed = " + std::to_string(seed) + " }\n";
}

TEST_F(SceneTest, EmitterReleasesInTurnAtTheirTimes) {
  const std::string path = write("scene.toml", emitterScene(1, 0, 0, false));
  BuiltScene built = buildScene(loadScene(path));
  World& w = *built.world;
  ASSERT_EQ(w.bodyCount(), 7);
  const Vec3 spots[] = {{-20, 0, 0}, {0, 20, 0}, {20, 0, 0}};
  for (int i = 0; i < 7; ++i) {
    // The cube mesh is centred, so the centre of mass is the given position.
    EXPECT_LT((w.state(i).x - spots[i % 3]).norm(), 1e-12) << "body " << i;
    EXPECT_LT((w.velocity(i) - Vec3(1, 0, 2)).norm(), 1e-12) << "body " << i;
  }
  // Body i is released at 0.25 + 0.5 i: halfway to the next release, exactly 0..i are active.
  for (int i = 0; i < 7; ++i) {
    w.advanceTo(0.25 + 0.5 * i + 0.25);
    for (int j = 0; j < 7; ++j)
      EXPECT_EQ(w.isActive(j), j <= i) << "t " << w.time() << " body " << j;
  }
}

TEST_F(SceneTest, JitterIsSeededAndBounded) {
  auto build = [&](int seed) {
    return buildScene(loadScene(write("scene.toml", emitterScene(seed, 0.1, 30, true))));
  };
  const BuiltScene a = build(5), b = build(5), c = build(6);
  const Vec3 spots[] = {{-20, 0, 0}, {0, 20, 0}, {20, 0, 0}};
  bool anyDifferent = false;
  for (int i = 0; i < 7; ++i) {
    const BodyState& sa = a.world->state(i);
    const BodyState& sb = b.world->state(i);
    const BodyState& sc = c.world->state(i);
    // Same seed: bit-identical.
    EXPECT_EQ(sa.x, sb.x);
    EXPECT_EQ(sa.q.coeffs(), sb.q.coeffs());
    EXPECT_EQ(a.world->velocity(i), b.world->velocity(i));
    anyDifferent = anyDifferent || sa.x != sc.x || sa.q.coeffs() != sc.q.coeffs();
    // Bounded: the centred cube's centre stays within the jitter cube about its spot; the
    // direction turns about z only, keeping the horizontal speed and the vertical part.
    const Vec3 d = sa.x - spots[i % 3];
    EXPECT_LE(d.cwiseAbs().maxCoeff(), 0.1 + 1e-12) << "body " << i;
    const Vec3 v = a.world->velocity(i);
    EXPECT_NEAR(v.z(), 2.0, 1e-12);
    EXPECT_NEAR(std::hypot(v.x(), v.y()), 1.0, 1e-12) << "body " << i;
    EXPECT_LE(std::abs(std::atan2(v.y(), v.x())), 30 * std::numbers::pi / 180 + 1e-12);
    EXPECT_NEAR(sa.q.norm(), 1.0, 1e-12);
  }
  EXPECT_TRUE(anyDifferent) << "seeds 5 and 6 gave the same releases";
}

}  // namespace
}  // namespace vf

namespace vf {
namespace {

// [simulation] collider: "voxel" (default) or "polygon"; anything else names the key's value.
TEST_F(SceneTest, ColliderSelectsTheContactMethod) {
  EXPECT_EQ(loadScene(write("a.toml", kShape)).collider, ColliderMethod::kVoxel);
  EXPECT_EQ(loadScene(write("b.toml", "[simulation]\ncollider = \"polygon\"\n" + kShape)).collider,
            ColliderMethod::kPolygon);
  expectError("[simulation]\ncollider = \"polygons\"\n", "\"polygons\"",
              "'collider' must be \"voxel\"");
  // A convex cube builds with polygons: every body gets the cube's polyhedron.
  SceneSpec spec =
      loadScene(write("c.toml", "[simulation]\ncollider = \"polygon\"\n" + kShape +
                                    "[[bodies]]\nshape = \"cube\"\nposition = [0, 0, 1]\n"));
  const BuiltScene built = buildScene(spec);
  EXPECT_NE(built.world->shape(0).polyhedron, nullptr);
}

}  // namespace
}  // namespace vf
