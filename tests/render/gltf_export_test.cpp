// `voxfall export`, read back with assimp's glTF 2.0 importer as a viewer
// would: one node per body, one animation channel per body, a key per frame at t = k / fps,
// and the pose at a key equal to the state `voxfall simulate --csv` reports for that frame.
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "render_test_util.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;

class GltfExport : public ::testing::Test {
 protected:
  GltfExport() : dir_("gltf_export") {}
  int run(const std::string& args) {
    const vf::test::CommandResult r =
        vf::test::runVoxfall(VOXFALL_EXE, dir_.path(), args + " --quiet");
    err_ = r.err;
    return r.code;
  }
  vf::test::ScratchDir dir_;
  std::string err_;
};

// The CSV row of `body` at `frame`: x, y, z, qw, qx, qy, qz.
std::vector<double> csvPose(const std::string& csv, int frame, int body) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) v.push_back(std::stod(cell));
    if (static_cast<int>(v[0]) == frame && static_cast<int>(v[2]) == body)
      return {v[3], v[4], v[5], v[6], v[7], v[8], v[9]};
  }
  return {};
}

TEST_F(GltfExport, ReadBackHasANodeAndAChannelPerBodyWithKeysAtTheFrameTimes) {
  const std::string cubes = std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml";
  ASSERT_EQ(run("export '" + cubes + "' -o cubes.glb"), 0) << err_;
  ASSERT_EQ(run("simulate '" + cubes + "' --csv cubes.csv"), 0) << err_;
  const std::string csv = readFile(dir_.path() / "cubes.csv");

  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir_.file("cubes.glb"), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  // cubes.toml: two bodies, no terrain; 2 s at 30 fps = frames 0..60.
  const aiNode* root = scene->mRootNode;
  ASSERT_EQ(root->mNumChildren, 2u);
  EXPECT_EQ(scene->mNumMeshes, 2u);
  EXPECT_EQ(scene->mMeshes[0]->mNumFaces, 12u) << "the cube's 12 triangles";
  ASSERT_EQ(scene->mNumAnimations, 1u);
  const aiAnimation* anim = scene->mAnimations[0];
  ASSERT_EQ(anim->mNumChannels, 2u);
  const double tps = anim->mTicksPerSecond > 0 ? anim->mTicksPerSecond : 1.0;
  for (unsigned c = 0; c < anim->mNumChannels; ++c) {
    const aiNodeAnim* ch = anim->mChannels[c];
    EXPECT_NE(root->FindNode(ch->mNodeName), nullptr) << ch->mNodeName.C_Str();
    ASSERT_EQ(ch->mNumPositionKeys, 61u);
    ASSERT_EQ(ch->mNumRotationKeys, 61u);
    for (unsigned k = 0; k < 61; ++k) {
      // glTF stores float seconds: k / 30 to float precision.
      EXPECT_NEAR(ch->mPositionKeys[k].mTime / tps, k / 30.0, 1e-6) << "key " << k;
      EXPECT_NEAR(ch->mRotationKeys[k].mTime / tps, k / 30.0, 1e-6) << "key " << k;
    }
  }
  // The pose at key 30 (t = 1 s) of body 1 (the thrown cube), against simulate's CSV: the
  // glTF holds floats, so agreement is to float rounding (~1e-7 relative, 1e-6 m here).
  const aiNodeAnim* thrown = nullptr;
  for (unsigned c = 0; c < anim->mNumChannels; ++c)
    if (std::string(anim->mChannels[c]->mNodeName.C_Str()) == "body_1") thrown = anim->mChannels[c];
  ASSERT_NE(thrown, nullptr);
  const std::vector<double> pose = csvPose(csv, 30, 1);
  ASSERT_EQ(pose.size(), 7u);
  const aiVector3D& x = thrown->mPositionKeys[30].mValue;
  EXPECT_NEAR(x.x, pose[0], 1e-6);
  EXPECT_NEAR(x.y, pose[1], 1e-6);
  EXPECT_NEAR(x.z, pose[2], 1e-6);
  const aiQuaternion& q = thrown->mRotationKeys[30].mValue;
  const double sign = q.w * pose[3] < 0 ? -1 : 1;  // q and -q are the same rotation
  EXPECT_NEAR(sign * q.w, pose[3], 1e-6);
  EXPECT_NEAR(sign * q.x, pose[4], 1e-6);
  EXPECT_NEAR(sign * q.y, pose[5], 1e-6);
  EXPECT_NEAR(sign * q.z, pose[6], 1e-6);
}

TEST_F(GltfExport, ABakeExportsTheSameFileAsItsScene) {
  const std::string cubes = std::string(VOXFALL_SOURCE_DIR) + "/scenes/cubes.toml";
  ASSERT_EQ(run("simulate '" + cubes + "' --bake run.bake"), 0) << err_;
  ASSERT_EQ(run("export run.bake -o from_bake.glb"), 0) << err_;
  ASSERT_EQ(run("export '" + cubes + "' -o from_scene.glb"), 0) << err_;
  const std::string a = readFile(dir_.path() / "from_bake.glb");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == readFile(dir_.path() / "from_scene.glb"));
  EXPECT_EQ(run("export run.bake -o wrong.gltf"), 1);
  EXPECT_NE(err_.find(".glb"), std::string::npos) << err_;
}

TEST_F(GltfExport, GeneratedRocksExportTheirMeshesFromTheSceneAndItsBakeAlike) {
  // Rocks have no mesh file: the scene's export draws the generated meshes, and the bake's
  // export regenerates them, to the same bytes.
  std::ofstream(dir_.path() / "rocks.toml")
      << "[simulation]\nduration = 0.3\nlevel = 3\n[ground]\nplane = 0.0\n"
         "[shapes.block]\nrock = { class = \"eota_111\", size = 0.8 }\ndensity = 2700\n"
         "[shapes.stones]\nrock = { class = \"flat\", seeds = 2, volume = 0.1 }\n"
         "density = 2700\n"
         "[[bodies]]\nshape = \"block\"\nposition = [0.0, 0.0, 0.5]\n"
         "[[bodies]]\nshape = \"stones#1\"\nposition = [1.0, 0.0, 0.5]\n";
  ASSERT_EQ(run("export rocks.toml -o scene.glb"), 0) << err_;
  ASSERT_EQ(run("simulate rocks.toml --bake rocks.bake"), 0) << err_;
  fs::remove(dir_.path() / "rocks.toml");
  ASSERT_EQ(run("export rocks.bake -o bake.glb"), 0) << err_;
  const std::string a = readFile(dir_.path() / "scene.glb");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == readFile(dir_.path() / "bake.glb"));
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir_.file("scene.glb"), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 2u);
  // The EOTA block: 26 faces, of which 18 four-sided, in 44 triangles; a natural rock is the
  // hull of 24 points on a sphere, 2 * 24 - 4 = 44 triangles.
  EXPECT_EQ(scene->mMeshes[0]->mNumFaces, 44u);
  EXPECT_EQ(scene->mMeshes[1]->mNumFaces, 44u);
}

}  // namespace
