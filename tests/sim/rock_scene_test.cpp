// Generated rocks in scene files (sim/scene): `[shapes.NAME] rock = { ... }` loads, builds the
// generator's mesh with the scene's mass, runs, survives a bake, and is refused with one clear
// error when written wrongly; rock families (`rock.seeds`) become variants that bodies name one
// by one and ensembles draw with the entry's weight, each variant built once and shared.
//
// Oracles: the generator's mesh and mass properties computed here from the same RockDef
// (rock_mesh_test checks those against closed forms); binomial bounds on draw counts; the
// errors' positions found by searching the scene text.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>

#include "sim/bake.h"
#include "sim/ensemble/ensemble.h"
#include "sim/geometry/mass_properties.h"
#include "sim/geometry/rock_mesh.h"
#include "sim/scene/scene.h"
#include "tests/support/chute_dem.h"
#include "tests/support/scene_file_test.h"

namespace vf {
namespace {

class RockSceneTest : public test::SceneFileTest {};

// Two rocks over a floor: the field tests' EOTA 221 block by extents and mass, and a compact
// rock by volume and density.
const std::string kRocks =
    "[simulation]\nduration = 1.5\nlevel = 3\n"
    "[ground]\nplane = 0.0\n"
    "[shapes.block]\nrock = { class = \"eota_221\", size = [0.93, 0.93, 0.465] }\nmass = 780\n"
    "[shapes.stone]\nrock = { class = \"compact\", seed = 5, volume = 0.2 }\ndensity = 2600\n"
    "[[bodies]]\nshape = \"block\"\nposition = [0.0, 0.0, 1.0]\n"
    "[[bodies]]\nshape = \"stone\"\nposition = [2.0, 0.0, 1.0]\n"
    "orientation = [0.9, 0.3, 0.2, 0.1]\n";

TEST_F(RockSceneTest, RockShapesLoadBuildTheGeneratorsMeshAndRun) {
  const SceneSpec spec = loadScene(write("rocks.toml", kRocks));
  ASSERT_EQ(spec.shapes.size(), 2u);
  ASSERT_TRUE(spec.shapes[0].rock.has_value());
  EXPECT_TRUE(spec.shapes[0].meshPath.empty());
  EXPECT_EQ(spec.shapes[0].rock->shapeClass, "eota_221");
  EXPECT_EQ(spec.shapes[0].rock->extents, Vec3(0.93, 0.93, 0.465));
  EXPECT_EQ(spec.shapes[1].rock->seed, 5u);
  EXPECT_EQ(spec.shapes[1].rock->volume, 0.2);

  BuiltScene built = buildScene(spec);
  World& w = *built.world;
  ASSERT_EQ(w.bodyCount(), 2);
  // Body 0: the generator's mesh, centred on its centre of mass, with the scene's mass.
  const TriMesh block = makeRockMesh(*spec.shapes[0].rock);
  const MassProperties mp = computeMassProperties(block, 1.0);
  EXPECT_NEAR(w.shape(0).mass, 780, 1e-12 * 780);
  EXPECT_EQ(w.shape(0).mesh.vertices.size(), block.vertices.size());
  EXPECT_EQ(w.shape(0).mesh.bounds().sizes(), block.bounds().sizes());
  const Mat3 inertia = mp.inertia * (780 / mp.volume);
  EXPECT_LE((w.shape(0).inertiaBody - inertia).cwiseAbs().maxCoeff(), 1e-12 * inertia.norm());
  // Body 1: 0.2 m^3 of density 2600.
  EXPECT_NEAR(w.shape(1).volume, 0.2, 1e-13);
  EXPECT_NEAR(w.shape(1).mass, 520, 1e-10);

  // It runs: both fall onto the floor and rest on it, sunk by less than a leaf voxel's edge
  // (eq. 17 and the step rule; a leaf edge is at most the diameter / 2^level).
  const double z0 = w.state(0).x.z(), z1 = w.state(1).x.z();
  w.advanceTo(spec.duration);
  EXPECT_LT(w.state(0).x.z(), z0 - 0.3);
  EXPECT_LT(w.state(1).x.z(), z1 - 0.3);
  const Diagnostics d = w.measure();
  EXPECT_LE(d.maxPenetrationBodyGround, std::ldexp(w.shape(0).diameter, -spec.level));
  EXPECT_EQ(d.tunnelled, 0);
}

TEST_F(RockSceneTest, ARockGivenMassAndDensityHasTheVolumeTheyMake) {
  const SceneSpec spec = loadScene(
      write("s.toml",
            "[shapes.a]\nrock = { class = \"flat\", seed = 2 }\nmass = 1300\ndensity = 2600\n"));
  ASSERT_EQ(spec.shapes.size(), 1u);
  EXPECT_EQ(spec.shapes[0].rock->volume, 0.5);
  const BuiltScene built = buildScene(spec);
  const auto shapes = buildSceneShapes(spec);
  EXPECT_NEAR(shapes.at("a").shape->volume, 0.5, 1e-13);
  EXPECT_NEAR(shapes.at("a").shape->mass, 1300, 1e-10);
}

TEST_F(RockSceneTest, MeshAndRockAreExclusiveAndOneIsRequired) {
  expectError(
      "[shapes.a]\nmesh = \"cube.obj\"\nrock = { class = \"compact\", volume = 1 }\n"
      "density = 1\n",
      "{ class", "give either 'mesh' (a mesh file) or 'rock' (a generated rock) in [shapes.a]");
  expectError("[shapes.a]\ndensity = 1\n", "[shapes.a]",
              "missing required key 'mesh' (a mesh file) or 'rock' (a generated rock");
}

TEST_F(RockSceneTest, AnUnknownClassIsRefusedWithTheListOfClasses) {
  expectError("[shapes.a]\nrock = { class = \"pebble\", volume = 1 }\ndensity = 1\n", "\"pebble\"",
              "unknown rock class 'pebble' (classes: eota_111, eota_221, compact, flat, "
              "elongated, bladed)");
  expectError("[shapes.a]\nrock = { class = \"compcat\", volume = 1 }\ndensity = 1\n",
              "\"compcat\"", "did you mean 'compact'?");
}

TEST_F(RockSceneTest, BadRockSizesAndMeshOnlyKeysAreRefused) {
  expectError("[shapes.a]\nrock = { class = \"compact\", size = 1, volume = 1 }\ndensity = 1\n",
              "1 }", "give either 'rock.size' or 'rock.volume' in [shapes.a], not both");
  expectError("[shapes.a]\nrock = { class = \"flat\", size = [1.0, 1.0, 1.0] }\ndensity = 1\n",
              "[1.0", "are Zingg's equant, class 'compact', not 'flat'");
  expectError("[shapes.a]\nrock = { class = \"compact\", size = [1.0, 0.0, 1.0] }\ndensity = 1\n",
              "[1.0", "'rock.size' extents must be > 0 m");
  expectError("[shapes.a]\nrock = { class = \"compact\", size = -2 }\ndensity = 1\n", "-2",
              "'rock.size' must be > 0 m");
  expectError(
      "[shapes.a]\nrock = { class = \"compact\" }\ndensity = 1\n", "[shapes.a]",
      "a rock needs a size: give 'rock.size' or 'rock.volume', or both 'mass' and 'density'");
  expectError("[shapes.a]\nrock = { class = \"compact\", volume = 1 }\nscale = 2\ndensity = 1\n",
              "2\ndensity", "'scale' applies to a mesh file");
  expectError("[shapes.a]\nrock = { class = \"compact\", volume = 1, sead = 3 }\ndensity = 1\n",
              "sead", "unknown key 'sead' in [shapes.a] rock; did you mean 'seed'?");
  expectError("[shapes.a]\nrock = { class = \"compact\", volume = 1, seeds = 0 }\ndensity = 1\n",
              "0 }", "'rock.seeds' must be an integer from 1 to 1000");
}

const std::string kFamily =
    "[shapes.boulders]\nrock = { class = \"compact\", seed = 10, seeds = 3, volume = 0.3 }\n"
    "density = 2600\n";

TEST_F(RockSceneTest, AFamilyBecomesVariantsWithConsecutiveSeeds) {
  const SceneSpec spec = loadScene(
      write("s.toml", kFamily + "[[bodies]]\nshape = \"boulders#2\"\nposition = [0, 0, 1]\n"));
  ASSERT_EQ(spec.shapes.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const ShapeSpec& s = spec.shapes[static_cast<std::size_t>(k)];
    EXPECT_EQ(s.name, "boulders#" + std::to_string(k));
    EXPECT_EQ(s.family, "boulders");
    EXPECT_EQ(s.rock->seed, 10u + static_cast<unsigned>(k));
  }
  // Each variant is its own rock, built once.
  const auto shapes = buildSceneShapes(spec);
  EXPECT_NE(shapes.at("boulders#0").shape->mesh.vertices[0],
            shapes.at("boulders#1").shape->mesh.vertices[0]);
  EXPECT_NE(shapes.at("boulders#0").shape->tree, shapes.at("boulders#1").shape->tree);
  const BuiltScene built = buildScene(spec);
  EXPECT_EQ(built.shapeOf[0], "boulders#2");
  // A body names one variant, not the family.
  expectError(kFamily + "[[bodies]]\nshape = \"boulders\"\n", "\"boulders\"",
              "'boulders' is a family of 3 rocks (rock.seeds); name one of them, 'boulders#0' to "
              "'boulders#2'");
  // A variant's name taken by another table.
  expectError(kFamily + "[shapes.\"boulders#1\"]\nmesh = \"cube.obj\"\ndensity = 1\n",
              "[shapes.\"boulders#1\"]", "shape 'boulders#1' is defined twice");
}

// An ensemble over the chute (tests/support/chute_dem.h) drawing shape "plain" or family "fam".
std::string ensembleScene(const std::string& familyRock, const std::string& ensemble) {
  return "[simulation]\nduration = 2.0\nlevel = 2\n"
         "[ground]\nheightfield = \"chute.tif\"\noffset = [-1000.0, -5000.0, 0.0]\n"
         "material = \"glacial_deposits\"\n"
         "[shapes.plain]\nrock = { class = \"eota_111\", size = 0.6 }\ndensity = 2600\n"
         "[shapes.fam]\nrock = " +
         familyRock + "\ndensity = 2600\n[ensemble]\n" + ensemble +
         "release = { line = [[1005.0, 5006.3], [1005.0, 5017.7]] }\n";
}

TEST_F(RockSceneTest, AnEnsembleEntryNamingAFamilySharesItsWeightAmongTheVariants) {
  ASSERT_TRUE(test::writeChuteDem(dir_ / "chute.tif"));
  const SceneSpec spec = loadScene(
      write("e.toml", ensembleScene("{ class = \"bladed\", seeds = 4, volume = 0.1 }",
                                    "shapes = [\"plain\", \"fam\"]\nweights = [1, 3]\n")));
  const EnsembleSpec& e = *spec.ensemble;
  const std::vector<std::string> names{"plain", "fam#0", "fam#1", "fam#2", "fam#3"};
  EXPECT_EQ(e.shapes, names);
  EXPECT_EQ(e.weights, (std::vector<double>{1, 0.75, 0.75, 0.75, 0.75}));
  // `shape = "fam"`: the variants, equally likely.
  const SceneSpec one =
      loadScene(write("f.toml", ensembleScene("{ class = \"bladed\", seeds = 2, volume = 0.1 }",
                                              "shape = \"fam\"\n")));
  EXPECT_EQ(one.ensemble->shapes, (std::vector<std::string>{"fam#0", "fam#1"}));
  EXPECT_EQ(one.ensemble->weights, (std::vector<double>{0.5, 0.5}));
  expectError(ensembleScene("{ class = \"bladed\", seeds = 2, volume = 0.1 }",
                            "shapes = [\"plain\", \"fam\"]\nweights = [1, 2, 3]\n"),
              "[1, 2, 3]", "'weights' must be an array of 2 numbers, one per entry of 'shapes'");
}

TEST_F(RockSceneTest, EnsembleDrawsFollowTheWeightsAndShareOneShapePerVariant) {
  ASSERT_TRUE(test::writeChuteDem(dir_ / "chute.tif"));
  const Ensemble ens(loadScene(
      write("e.toml", ensembleScene("{ class = \"elongated\", seed = 3, seeds = 4, volume = 0.1 }",
                                    "shapes = [\"plain\", \"fam\"]\nweights = [1, 3]\n"))));
  // p = 1/4 for "plain" and 3/16 for each variant. Counts over N realisations are binomial;
  // each within 4.5 standard deviations sqrt(N p (1 - p)): a sound draw fails one of the five
  // with probability below 5 * 7e-6, while a wrong share (say the family's weight given to each
  // variant, p = 3/13 instead of 3/16 with N = 4000) is off by 17 standard deviations.
  const int n = 4000;
  const std::vector<double> p{0.25, 3.0 / 16, 3.0 / 16, 3.0 / 16, 3.0 / 16};
  std::vector<int> count(p.size(), 0);
  std::map<int, const Shape*> shapeOf;  // per variant, the one shape every realisation uses
  for (int i = 0; i < n; ++i) {
    const RealisationWorld made = ens.makeWorld(realisationSeed(ens.ensemble().seed, i));
    const auto& w = made.world;
    const int shape = made.shape;
    ASSERT_GE(shape, 0);
    ++count[static_cast<std::size_t>(shape)];
    const auto [it, added] = shapeOf.emplace(shape, &w->shape(0));
    EXPECT_EQ(it->second, &w->shape(0)) << "variant " << shape << " built again";
  }
  for (std::size_t k = 0; k < p.size(); ++k) {
    const double mean = n * p[k], sd = std::sqrt(n * p[k] * (1 - p[k]));
    EXPECT_NEAR(count[k], mean, 4.5 * sd) << "shape " << ens.ensemble().shapes[k];
  }
  // The variants are distinct rocks of the class.
  std::set<double> inertias;
  for (const auto& [k, s] : shapeOf) inertias.insert(s->inertiaBody(0, 0));
  EXPECT_EQ(inertias.size(), p.size());
}

TEST_F(RockSceneTest, ABakeRebuildsTheRockAndAYUpMeshAsTheSceneHadThem) {
  // A y-up mesh stretched by a scale that differs on y and z: its baked mesh must be rotated
  // and scaled as the scene's was.
  const std::string text = kRocks + kFamily +
                           "[shapes.tall]\nmesh = \"cube.obj\"\nup = \"y\"\nscale = [1.0, 2.0, "
                           "0.5]\ndensity = 500\n"
                           "[[bodies]]\nshape = \"boulders#1\"\nposition = [4.0, 0.0, 1.0]\n"
                           "[[bodies]]\nshape = \"tall\"\nposition = [6.0, 0.0, 1.0]\n";
  const SceneSpec spec = loadScene(write("rocks.toml", text));
  const BuiltScene built = buildScene(spec);
  Bake bake = bakeHeader(spec, built);
  addBakeRecord(bake, *built.world);
  const std::string path = (dir_ / "run.bake").string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  writeBake(f, path, bake);
  std::fclose(f);
  const Bake back = readBake(path);
  const auto shapes = bakeShapes(back);
  for (int id = 0; id < built.world->bodyCount(); ++id) {
    const int s = back.bodies[static_cast<std::size_t>(id)].shape;
    const TriMesh& baked = shapes[static_cast<std::size_t>(s)]->mesh;
    const TriMesh& ran = built.world->shape(id).mesh;
    EXPECT_EQ(baked.vertices, ran.vertices) << "body " << id << " (" << built.shapeOf[id] << ")";
    EXPECT_EQ(baked.triangles, ran.triangles) << "body " << id;
  }
}

}  // namespace
}  // namespace vf
