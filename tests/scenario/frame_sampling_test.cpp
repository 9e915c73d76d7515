// Frames between steps invent no motion (sim/frame_interp.h): a body at rest in its step states
// is at rest in every frame, at an output rate that does not divide the step (100 fps over
// 1/60 s steps puts most frames inside a step). What is checked is what the CSV writes for a
// frame (render/run/run_report.cpp): the frame's position and v = P / M, w = I^-1 L.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <vector>

#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/world.h"
#include "tests/support/chute_dem.h"
#include "tests/support/test_world.h"

namespace vf {
namespace {

constexpr double kStep = 1.0 / 60.0;
constexpr double kFps = 100.0;

// Body 0 of a run through its step states and its frames.
struct Track {
  std::vector<double> stepTime;
  std::vector<Vec3> stepX, stepV;
  std::vector<double> frameTime;
  std::vector<Vec3> frameX, frameV, frameW;
};

Track record(World& world, double duration) {
  Track tr;
  Recorder recorder(world, kFps, duration);
  recorder.setAfterStep([&] {
    tr.stepTime.push_back(world.time());
    tr.stepX.push_back(world.state(0).x);
    tr.stepV.push_back(world.velocity(0));
  });
  for (int k = 0; k < recorder.frameCount(); ++k) {
    recorder.advanceToFrame(k);
    const BodyState& y = recorder.frameStates()[0];
    tr.frameTime.push_back(recorder.frameTime(k));
    tr.frameX.push_back(y.x);
    tr.frameV.push_back(world.velocity(0, y));
    tr.frameW.push_back(world.angularVelocity(0, y));
  }
  return tr;
}

// From the first step after which every step state has speed below vRest: the frames from that
// step on show the body where the steps hold it and as still as they hold it. A frame is a
// convex combination of its two bracketing step states, so its speed is at most theirs and its
// position within theirs; the slack is the rounding of that combination (a few ulps of a
// coordinate of 100 m). The old sampling moved the frame by gravity's free motion over the part
// of a step before it: v off by up to g dt = 0.16 m/s, x sunk by up to g dt^2 / 2 = 1.4 mm.
void expectStillAfterRest(const Track& tr, double vRest) {
  std::size_t rest = tr.stepV.size();
  while (rest > 0 && tr.stepV[rest - 1].norm() < vRest) --rest;
  ASSERT_LT(rest + 30, tr.stepV.size()) << "the body does not rest for half a second";
  const double restTime = tr.stepTime[rest];
  double stepSpeed = 0, stepDrift = 0;
  for (std::size_t i = rest; i < tr.stepV.size(); ++i) {
    stepSpeed = std::max(stepSpeed, tr.stepV[i].norm());
    stepDrift = std::max(stepDrift, (tr.stepX[i] - tr.stepX[rest]).norm());
  }
  const double slack = 1e-12;
  int checked = 0, inside = 0;
  for (std::size_t k = 0; k < tr.frameTime.size(); ++k) {
    if (tr.frameTime[k] < restTime) continue;
    ++checked;
    const double s = tr.frameTime[k] / kStep;
    inside += std::abs(s - std::round(s)) > 1e-6 ? 1 : 0;
    EXPECT_LE(tr.frameV[k].norm(), stepSpeed + slack) << "t = " << tr.frameTime[k];
    EXPECT_LE((tr.frameX[k] - tr.stepX[rest]).norm(), stepDrift + slack)
        << "t = " << tr.frameTime[k];
  }
  EXPECT_GT(inside, checked / 2) << "most frames fall inside a step";
  // At rest means at rest: the steps' own speed is far below gravity's one-step increment.
  EXPECT_LT(stepSpeed, 1e-3);
}

// The plane z = -x tan(theta) as a terrain of 1 m cells over x in [-4, 16], y in [-4, 4].
std::shared_ptr<const Heightfield> incline(double theta) {
  auto h = std::make_shared<Heightfield>(test::flatHeightfield(21, 9, 1.0, 0.0, -4.0, -4.0));
  for (int j = 0; j < h->ny; ++j)
    for (int i = 0; i < h->nx; ++i)
      h->z[static_cast<std::size_t>(j) * h->nx + i] = -(h->x0 + i) * std::tan(theta);
  h->zMin = -16 * std::tan(theta);
  h->zMax = 4 * std::tan(theta);
  return h;
}

// A box set flat on a 30-degree slope, friction 0.8 > tan 30: it settles and stays.
TEST(FrameSampling, ABoxAtRestOnASlopeIsStillInEveryFrame) {
  const double theta = 30.0 * std::numbers::pi / 180.0;
  WorldDef def;
  def.terrain = incline(theta);
  def.step = StepRule::fixed(kStep);
  test::RockFallWorld rock(def, {});  // with the rock monitor, as a scene on terrain has
  World& world = rock.world;
  const auto box = test::boxShape(0.2, 0.2, 0.2, 800, 3);
  const Vec3 normal(std::sin(theta), 0, std::cos(theta));
  BodyDef b = test::bodyAt(
      box, Vec3(2, 0, -2 * std::tan(theta)) + (test::restOffset(*box) + 1e-3) * normal);
  b.orientation = Quat(Eigen::AngleAxisd(theta, Vec3::UnitY()));
  world.addBody(b);
  const Track tr = record(world, 2.0);
  expectStillAfterRest(tr, 1e-3);
}

// A rock set on a DEM (a 15-degree chute read from a GeoTIFF, with a rock-fall material):
// the rock comes to rest on real terrain and every frame after shows it still.
TEST(FrameSampling, ARockAtRestOnADemIsStillInEveryFrame) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("voxfall_frame_sampling_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  test::ChuteDem dem;
  dem.slopeDegrees = 15;
  ASSERT_TRUE(test::writeChuteDem(dir / "chute.tif", dem));
  {
    std::ofstream f(dir / "scene.toml");
    f << "[simulation]\nduration = 3.0\nlevel = 2\nstep = \"1/60\"\nfps = 100\n"
         "rotation = \"midpoint\"\n"
         "[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
         "material = \"glacial_deposits\"\n"
         "[shapes.rock]\nmesh = \""
      << VOXFALL_SOURCE_DIR
      << "/scenes/meshes/rock.obj\"\nscale = 0.5\ndensity = 2600\n"
         "[[bodies]]\nshape = \"rock\"\nposition = [40.0, 12.0, 0.0]\ndrop_height = 0.02\n";
  }
  SceneSpec spec = loadScene((dir / "scene.toml").string());
  BuiltScene built = buildScene(spec);
  std::filesystem::remove_all(dir);
  const Track tr = record(*built.world, spec.duration);
  expectStillAfterRest(tr, 1e-3);
}

}  // namespace
}  // namespace vf
