// `voxfall export`, read back with assimp's glTF 2.0 importer as a viewer
// would: one node per body named after its shape and id, one animation channel per body, a
// key per frame at t = k / fps, and the pose at a key equal to the state `voxfall simulate
// --csv` reports for that frame; unit normals (a body's its faces', the terrain's upward); one
// mesh per shape shared by its bodies' nodes; the DEM's CRS and offset in the root's extras;
// a draped texture embedded as a PNG (decoded by libpng) with texture coordinates that put each
// terrain vertex on the texel of the raster that covers it.
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <png.h>

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
  // Exports `scene` to rocks.glb and reads it back with `importer` (null on failure, with
  // a test failure naming why).
  const aiScene* exportAndRead(const std::string& scene, Assimp::Importer& importer) {
    if (run("export '" + scene + "' -o rocks.glb") != 0) {
      ADD_FAILURE() << err_;
      return nullptr;
    }
    const aiScene* read = importer.ReadFile(dir_.file("rocks.glb"), 0);
    if (!read) ADD_FAILURE() << importer.GetErrorString();
    return read;
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
  Assimp::Importer importer;
  const aiScene* scene = exportAndRead(rocksOnADem(dir_), importer);
  ASSERT_NE(scene, nullptr);
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
  Assimp::Importer importer;
  const aiScene* scene = exportAndRead(rocksOnADem(dir_), importer);
  ASSERT_NE(scene, nullptr);
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

// An orthophoto over rocksOnADem's DEM (raster extent x 999..1013, y 1999..2011 in EPSG:31287):
// 1 m texels, 14 x 12, grey 60 but for the texel in column 9 and row 3 from the top (grey 250),
// which covers x 1008..1009, y 2007..2008: world x 8..9, y 7..8 after the offset.
std::string rocksOnATexturedDem(const vf::test::ScratchDir& dir) {
  const std::string scene = rocksOnADem(dir);
  std::ofstream photo(dir.file("photo.asc"));
  photo << "ncols 14\nnrows 12\nxllcorner 999\nyllcorner 1999\ncellsize 1\n";
  for (int row = 0; row < 12; ++row) {
    for (int col = 0; col < 14; ++col) photo << (row == 3 && col == 9 ? 250 : 60) << " ";
    photo << "\n";
  }
  photo.close();
  const std::string command = "gdal_translate -q -ot Byte -a_srs EPSG:31287 '" +
                              dir.file("photo.asc") + "' '" + dir.file("photo.tif") + "'";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  std::string text = readFile(scene);
  const std::string dem = "heightfield = \"dem.tif\"\n";
  text.replace(text.find(dem), dem.size(), dem + "texture = \"photo.tif\"\n");
  std::ofstream(scene) << text;
  return scene;
}

struct Picture {
  unsigned width = 0, height = 0;
  std::vector<unsigned char> rgb;  // top row first
  unsigned char red(unsigned col, unsigned row) const { return rgb[3 * (row * width + col)]; }
};

// An embedded compressed texture (mHeight 0: mWidth bytes) decoded by libpng.
Picture decodePng(const aiTexture& t) {
  Picture out;
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&png, t.pcData, t.mWidth)) return out;
  png.format = PNG_FORMAT_RGB;
  out.rgb.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, out.rgb.data(), 0, nullptr)) return {};
  out.width = png.width;
  out.height = png.height;
  return out;
}

TEST_F(GltfExport, ADrapedTextureIsEmbeddedAndItsTexelsLieOverTheCellsTheyCover) {
  Assimp::Importer importer;
  const aiScene* scene = exportAndRead(rocksOnATexturedDem(dir_), importer);
  ASSERT_NE(scene, nullptr);
  const aiNode* node = child(scene, "terrain");
  ASSERT_NE(node, nullptr);
  const aiMesh* terrain = scene->mMeshes[node->mMeshes[0]];
  ASSERT_EQ(terrain->mNumVertices, 42u) << "the DEM's 7 x 6 samples";
  ASSERT_TRUE(terrain->HasTextureCoords(0));
  EXPECT_EQ(terrain->mNumUVComponents[0], 2u);

  // The material's base colour texture is the embedded picture.
  const aiMaterial* material = scene->mMaterials[terrain->mMaterialIndex];
  aiString path;
  ASSERT_EQ(material->GetTexture(aiTextureType_DIFFUSE, 0, &path), AI_SUCCESS);
  const aiTexture* texture = scene->GetEmbeddedTexture(path.C_Str());
  ASSERT_NE(texture, nullptr) << path.C_Str();
  EXPECT_EQ(texture->mHeight, 0u) << "stored compressed";
  EXPECT_STREQ(texture->achFormatHint, "png");
  const Picture picture = decodePng(*texture);
  ASSERT_EQ(picture.width, 14u) << "the raster's own 1 m texels over the DEM's extent";
  ASSERT_EQ(picture.height, 12u);
  for (unsigned row = 0; row < 12; ++row)
    for (unsigned col = 0; col < 14; ++col)
      EXPECT_EQ(picture.red(col, row) > 155, col == 9 && row == 3) << col << ", " << row;

  // Every vertex's texture coordinate against the raster's geotransform: world (x, y) is file
  // (x + 1000, y + 2000), texel column x_file - 999 and row 2011 - y_file from the top. glTF's
  // v runs down from the picture's first row; assimp reads it as 1 - v (v up from the last).
  // Float storage: agreement to 1e-5 of the picture, far inside a texel (1/14, 1/12).
  for (unsigned i = 0; i < terrain->mNumVertices; ++i) {
    const aiVector3D& p = terrain->mVertices[i];
    const aiVector3D& uv = terrain->mTextureCoords[0][i];
    ASSERT_GE(uv.x, 0.0f);
    ASSERT_LE(uv.x, 1.0f);
    ASSERT_GE(uv.y, 0.0f);
    ASSERT_LE(uv.y, 1.0f);
    EXPECT_NEAR(uv.x * 14, p.x + 1000 - 999, 1e-4) << "vertex " << i;
    EXPECT_NEAR((1 - uv.y) * 12, 2011 - (p.y + 2000), 1e-4) << "vertex " << i;
  }
  // The marked cell's centre, world (8.5, 7.5), lies in the grid square of the samples at
  // x = 8, 10 and y = 6, 8; texture coordinates are affine there, so its own is the bilinear
  // mix of those four vertices'. It lands on the marked texel, within the texel.
  aiVector3D mix(0, 0, 0);
  int found = 0;
  for (unsigned i = 0; i < terrain->mNumVertices; ++i) {
    const aiVector3D& p = terrain->mVertices[i];
    const bool x8 = std::abs(p.x - 8) < 1e-4, x10 = std::abs(p.x - 10) < 1e-4;
    const bool y6 = std::abs(p.y - 6) < 1e-4, y8 = std::abs(p.y - 8) < 1e-4;
    if (!(x8 || x10) || !(y6 || y8)) continue;
    const double weight = (x8 ? 0.75 : 0.25) * (y8 ? 0.75 : 0.25);
    mix += terrain->mTextureCoords[0][i] * static_cast<float>(weight);
    ++found;
  }
  ASSERT_EQ(found, 4);
  const double col = mix.x * 14, row = (1 - mix.y) * 12;
  EXPECT_NEAR(col, 9.5, 0.5);
  EXPECT_NEAR(row, 3.5, 0.5);
  EXPECT_GT(picture.red(static_cast<unsigned>(col), static_cast<unsigned>(row)), 155);
}

TEST_F(GltfExport, ATerrainWithoutATextureHasNoTextureCoordinates) {
  Assimp::Importer importer;
  const aiScene* scene = exportAndRead(rocksOnADem(dir_), importer);
  ASSERT_NE(scene, nullptr);
  const aiMesh* terrain = scene->mMeshes[child(scene, "terrain")->mMeshes[0]];
  EXPECT_FALSE(terrain->HasTextureCoords(0));
  EXPECT_EQ(scene->mNumTextures, 0u);
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
