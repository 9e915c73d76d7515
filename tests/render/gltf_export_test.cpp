// `voxfall export`, read back with assimp's glTF 2.0 importer as a viewer
// would: one node per body named after its shape and id, one animation channel per body, a
// key per frame at t = k / fps, and the pose at a key equal to the state `voxfall simulate
// --csv` reports for that frame; unit normals (a body's its faces', the terrain's upward); one
// mesh per shape shared by its bodies' nodes; the DEM's CRS and offset in the root's extras.
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdlib>
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
    if (std::string(anim->mChannels[c]->mNodeName.C_Str()) == "cube_1") thrown = anim->mChannels[c];
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

// Three rocks of one shape and colour and a box over a small DEM with a CRS (a GeoTIFF that
// gdal_translate tags EPSG:31287), moved near the origin by [ground] offset.
std::string rocksOnADem(const vf::test::ScratchDir& dir) {
  std::ofstream grid(dir.file("dem.asc"));
  grid << "ncols 7\nnrows 6\nxllcenter 1000\nyllcenter 2000\ncellsize 2\nNODATA_value -9999\n";
  for (int j = 0; j < 6; ++j) {
    for (int i = 0; i < 7; ++i) grid << 1.0 + 0.25 * i + 0.1 * j << " ";
    grid << "\n";
  }
  grid.close();
  const std::string command = "gdal_translate -q -a_srs EPSG:31287 '" + dir.file("dem.asc") +
                              "' '" + dir.file("dem.tif") + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  const std::string cube = std::string(VOXFALL_SOURCE_DIR) + "/scenes/meshes/cube.obj";
  std::ofstream(dir.file("rocks.toml"))
      << "[simulation]\nduration = 0.2\nlevel = 2\n"
         "[ground]\nheightfield = \"dem.tif\"\noffset = [-1000.0, -2000.0, 0.5]\n"
         "[shapes.rock]\nmesh = \""
      << cube
      << "\"\nscale = 0.2\ndensity = 800\ncolor = [0.5, 0.4, 0.3]\n"
         "[shapes.box]\nmesh = \""
      << cube
      << "\"\nscale = 0.3\ndensity = 800\n"
         "[[bodies]]\nshape = \"rock\"\nposition = [3.0, 3.0, 6.0]\n"
         "[[bodies]]\nshape = \"rock\"\nposition = [5.0, 3.0, 6.0]\n"
         "[[bodies]]\nshape = \"rock\"\nposition = [7.0, 3.0, 6.0]\n"
         "[[bodies]]\nshape = \"box\"\nposition = [5.0, 6.0, 6.0]\n";
  return dir.file("rocks.toml");
}

const aiNode* child(const aiScene* scene, const std::string& name) {
  const aiNode* root = scene->mRootNode;
  for (unsigned i = 0; i < root->mNumChildren; ++i)
    if (name == root->mChildren[i]->mName.C_Str()) return root->mChildren[i];
  return nullptr;
}

TEST_F(GltfExport, BodiesOfAShapeShareItsMeshWithUnitFaceNormalsAndNodesNamedAfterIt) {
  ASSERT_EQ(run("export '" + rocksOnADem(dir_) + "' -o rocks.glb"), 0) << err_;
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir_.file("rocks.glb"), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  // rock_0..2 share one mesh, box_3 has its own, and the terrain its own.
  EXPECT_EQ(scene->mNumMeshes, 3u);
  std::vector<unsigned> meshOf;
  for (const char* name : {"rock_0", "rock_1", "rock_2", "box_3", "terrain"}) {
    const aiNode* node = child(scene, name);
    ASSERT_NE(node, nullptr) << name;
    ASSERT_EQ(node->mNumMeshes, 1u) << name;
    meshOf.push_back(node->mMeshes[0]);
  }
  EXPECT_EQ(meshOf[1], meshOf[0]);
  EXPECT_EQ(meshOf[2], meshOf[0]);
  EXPECT_NE(meshOf[3], meshOf[0]);
  EXPECT_NE(meshOf[4], meshOf[0]);
  EXPECT_NE(meshOf[4], meshOf[3]);
  // Normals on every vertex, of unit length (to float rounding); a body's are its face's
  // (flat, outward: the cross product of the face's edges in its winding), the terrain's up.
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    ASSERT_TRUE(mesh->HasNormals()) << "mesh " << m;
    for (unsigned v = 0; v < mesh->mNumVertices; ++v)
      ASSERT_NEAR(mesh->mNormals[v].Length(), 1.0, 1e-6) << "mesh " << m << " vertex " << v;
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      ASSERT_EQ(face.mNumIndices, 3u);
      const aiVector3D a = mesh->mVertices[face.mIndices[0]], b = mesh->mVertices[face.mIndices[1]],
                       c = mesh->mVertices[face.mIndices[2]];
      const aiVector3D n = ((b - a) ^ (c - a)).Normalize();
      for (unsigned k = 0; k < 3; ++k) {
        const aiVector3D& vn = mesh->mNormals[face.mIndices[k]];
        if (m == meshOf[4]) {
          EXPECT_GT(vn.z, 0.9) << "terrain vertex " << face.mIndices[k];  // gentle slopes
        } else {
          EXPECT_NEAR(vn * n, 1.0, 1e-5) << "mesh " << m << " face " << f;
        }
      }
    }
  }
}

// The root node's extras, as assimp reads them into its metadata.
TEST_F(GltfExport, TheDemsCrsAndOffsetAreInTheRootNodesExtras) {
  ASSERT_EQ(run("export '" + rocksOnADem(dir_) + "' -o rocks.glb"), 0) << err_;
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(dir_.file("rocks.glb"), 0);
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  const aiMetadata* extras = scene->mRootNode->mMetaData;
  ASSERT_NE(extras, nullptr) << "no extras on the root node";
  aiString crs, wkt;
  ASSERT_TRUE(extras->Get("crs", crs));
  EXPECT_STREQ(crs.C_Str(), "EPSG:31287");
  ASSERT_TRUE(extras->Get("crs_wkt", wkt));
  EXPECT_NE(std::string(wkt.C_Str()).find("Austria Lambert"), std::string::npos) << wkt.C_Str();
  const aiMetadataEntry* entry = nullptr;
  for (unsigned k = 0; k < extras->mNumProperties; ++k)
    if (std::string(extras->mKeys[k].C_Str()) == "dem_offset") entry = &extras->mValues[k];
  ASSERT_NE(entry, nullptr) << "no dem_offset";
  ASSERT_EQ(entry->mType, AI_AIMETADATA);
  const auto* offset = static_cast<const aiMetadata*>(entry->mData);
  ASSERT_EQ(offset->mNumProperties, 3u);
  const double expected[3] = {-1000.0, -2000.0, 0.5};  // [ground] offset
  for (unsigned i = 0; i < 3; ++i) {
    ASSERT_EQ(offset->mValues[i].mType, AI_DOUBLE) << i;
    EXPECT_EQ(*static_cast<const double*>(offset->mValues[i].mData), expected[i]) << i;
  }
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
