// importMesh: OBJ, STL (ascii and binary), PLY, glTF (embedded base64) and GLB written by the
// test; welding; node transforms; errors; the two real meshes in tests/data.
#include "sim/geometry/mesh_import.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/geometry/mass_properties.h"
#include "sim/geometry/mesh_checks.h"
#include "tests/sim/test_meshes.h"

namespace vf {
namespace {

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  ASSERT_TRUE(f.good()) << path;
}

template <typename T>
void appendRaw(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // x86-64 and ARM64 are little-endian, as STL/glTF require
  s.append(b, sizeof(T));
}

// The message of the InputError that `f` throws ("" and a test failure if none).
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

// The message of the InputError that importing `path` throws, which must name that file ("" and
// a test failure if none is thrown).
std::string importErrorOf(const std::string& path) {
  try {
    importMesh(path);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), path);
    return e.message();
  }
  ADD_FAILURE() << "the import of " << path << " should be refused";
  return "";
}

// A unit box [0,1]^3 and the expected result of importing it once.
const TriMesh kUnitBox = test::boxMesh(Vec3(0, 0, 0), Vec3(1, 1, 1));

void expectUnitBox(const TriMesh& m, const Vec3& lo = Vec3::Zero()) {
  EXPECT_EQ(m.vertices.size(), 8u);  // welded: every corner once
  EXPECT_EQ(m.triangles.size(), 12u);
  // Coordinates are small integers: exact in float and double.
  EXPECT_EQ(m.bounds().min(), lo);
  EXPECT_EQ(m.bounds().max(), lo + Vec3(1, 1, 1));
  // Outward orientation survived the round trip: volume +1 (round-off ~1e-16).
  EXPECT_NEAR(test::fluxVolume(m), 1.0, 1e-12);
  TriMesh copy = m;
  EXPECT_NO_THROW(validateClosedMesh(copy, "box"));
}

TEST(MeshImport, ObjQuadsWithNormalsLinesAndPoints) {
  test::TempDir dir;
  // Quads with per-face normals: assimp keeps 24 corner vertices (position+normal differ);
  // position welding must bring them back to 8. The line and point elements are skipped.
  std::ostringstream s;
  s << "# unit cube\n";
  for (const Vec3& v : kUnitBox.vertices)
    s << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  s << "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n";
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int f = 0; f < 6; ++f) {
    s << "f";
    for (int k = 0; k < 4; ++k) s << " " << quads[f][k] + 1 << "//" << f + 1;
    s << "\n";
  }
  s << "l 1 2\np 3\n";
  writeFile(dir.file("cube.obj"), s.str());
  expectUnitBox(importMesh(dir.file("cube.obj")));
}

TEST(MeshImport, AsciiStlTriangleSoupWelds36CornersTo8) {
  test::TempDir dir;
  std::ostringstream s;
  s << "solid cube\n";
  for (const auto& t : kUnitBox.triangles) {
    s << " facet normal 0 0 0\n  outer loop\n";
    for (auto i : t) {
      const Vec3& v = kUnitBox.vertices[i];
      s << "   vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
    }
    s << "  endloop\n endfacet\n";
  }
  s << "endsolid cube\n";
  writeFile(dir.file("cube.stl"), s.str());
  expectUnitBox(importMesh(dir.file("cube.stl")));
}

TEST(MeshImport, BinaryStl) {
  test::TempDir dir;
  std::string b(80, ' ');  // header must not start with "solid" (that means ascii)
  appendRaw<std::uint32_t>(b, 12);
  for (const auto& t : kUnitBox.triangles) {
    for (int k = 0; k < 3; ++k) appendRaw<float>(b, 0.0f);  // normal (ignored)
    for (auto i : t)
      for (int k = 0; k < 3; ++k)
        appendRaw<float>(b, static_cast<float>(kUnitBox.vertices[i][k] + 2));
    appendRaw<std::uint16_t>(b, 0);
  }
  writeFile(dir.file("cube.stl"), b);
  expectUnitBox(importMesh(dir.file("cube.stl")), Vec3(2, 2, 2));
}

// Regression for a fuzz finding (tests/fuzz, mesh_stl_fuzz): a binary STL whose coordinates
// hold NaN or infinity overflowed the weld grid's keys (undefined behaviour); now it is an
// error naming the file and the triangle.
TEST(MeshImport, FuzzFoundNonFiniteStlCoordinatesAreAnError) {
  test::TempDir dir;
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    std::string b(80, ' ');
    appendRaw<std::uint32_t>(b, 12);
    int corner = 0;
    for (const auto& t : kUnitBox.triangles) {
      for (int k = 0; k < 3; ++k) appendRaw<float>(b, 0.0f);
      for (auto i : t)
        for (int k = 0; k < 3; ++k)
          appendRaw<float>(b, corner++ == 13 ? bad : static_cast<float>(kUnitBox.vertices[i][k]));
      appendRaw<std::uint16_t>(b, 0);
    }
    writeFile(dir.file("bad.stl"), b);
    // Coordinate 13 is in corner 4, the second corner of triangle 1.
    EXPECT_EQ(importErrorOf(dir.file("bad.stl")),
              "triangle 1 has a non-finite coordinate (NaN or infinity)");
  }
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): assimp 5.2 never returns from an
// ASCII PLY whose header is cut off inside a property line; the import now refuses a PLY header
// without 'end_header' before assimp sees it (without the check this test hangs until CTest's
// timeout).
TEST(MeshImport, FuzzFoundCutOffPlyHeaderIsAnError) {
  test::TempDir dir;
  writeFile(dir.file("cut.ply"), "ply\nformat ascii 1.0\nelement vertex 8\nproperty flo");
  EXPECT_EQ(importErrorOf(dir.file("cut.ply")),
            "PLY header has no 'end_header' line (is the file cut off?)");
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): an ASCII PLY cube with one face
// line garbled (bytes 0xe0 0xd2 for an index, the next line a comment) made assimp 5.2 flag
// polygons in a mesh of triangles, and its triangulation aborted the process on an assertion.
// assimp read the garbled line as a face without vertices: now an error naming the file.
TEST(MeshImport, FuzzFoundGarbledPlyFaceIsAnErrorNotAnAbort) {
  test::TempDir dir;
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
      "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n3 0 5\xe0\xd2\n# 2 6 7\n3 2 7 3\n"
      "3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n";
  writeFile(dir.file("garbled.ply"), s);
  // Which face number assimp's reader gives the garbled line is its business: not pinned.
  const std::string message = importErrorOf(dir.file("garbled.ply"));
  EXPECT_NE(message.find("has no vertices"), std::string::npos) << message;
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): the same hang with the magic
// number followed by other bytes on its line ("plyCCC..."), which assimp still reads as a PLY
// and the check above did not take for one.
TEST(MeshImport, FuzzFoundPlyMagicWithTrailingBytesAndCutHeaderIsAnError) {
  test::TempDir dir;
  writeFile(dir.file("cut.ply"), "ply" + std::string(42, 'C') +
                                     "\nformat ascii 1.0\nelement vertex 8\nproperty fply\n"
                                     "format aloat x\n.mat as");
  EXPECT_EQ(importErrorOf(dir.file("cut.ply")),
            "PLY header has no 'end_header' line (is the file cut off?)");
}

TEST(MeshImport, AsciiPlyWithQuads) {
  test::TempDir dir;
  std::ostringstream s;
  s << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
       "property float z\nelement face 6\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : kUnitBox.vertices) s << v.x() << " " << v.y() << " " << v.z() << "\n";
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads)
    s << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  writeFile(dir.file("cube.ply"), s.str());
  expectUnitBox(importMesh(dir.file("cube.ply")));
}

std::string base64(const std::string& in) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    std::uint32_t n = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) n |= static_cast<unsigned char>(in[i + 1]) << 8;
    if (i + 2 < in.size()) n |= static_cast<unsigned char>(in[i + 2]);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < in.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < in.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

// A glTF scene with one unit-box mesh instanced twice:
//   node 0: translation (10,0,0), child node 1: scale 2 -> box [10,12]x[0,2]x[0,2]
//   node 2: mirror x (scale -1,1,1) and translation (-5,0,0) -> box [-6,-5]x[0,1]x[0,1]
// Returns the JSON; `bin` receives the buffer; `uri` (if not empty) is the buffer's uri.
std::string gltfJson(std::string& bin, bool embedUri) {
  bin.clear();
  for (const Vec3& v : kUnitBox.vertices)
    for (int k = 0; k < 3; ++k) appendRaw<float>(bin, static_cast<float>(v[k]));
  const std::size_t posBytes = bin.size();
  for (const auto& t : kUnitBox.triangles)
    for (auto i : t) appendRaw<std::uint16_t>(bin, static_cast<std::uint16_t>(i));
  const std::size_t idxBytes = bin.size() - posBytes;
  std::ostringstream j;
  j << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,2]}],)"
    << R"("nodes":[{"translation":[10,0,0],"children":[1]},{"mesh":0,"scale":[2,2,2]},)"
    << R"({"mesh":0,"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, -5,0,0,1]}],)"
    << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":4}]}],)"
    << R"("buffers":[{"byteLength":)" << bin.size();
  if (embedUri) j << R"(,"uri":"data:application/octet-stream;base64,)" << base64(bin) << "\"";
  j << R"(}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" << posBytes
    << R"(,"target":34962},{"buffer":0,"byteOffset":)" << posBytes << R"(,"byteLength":)"
    << idxBytes << R"(,"target":34963}],)"
    << R"("accessors":[{"bufferView":0,"componentType":5126,"count":8,"type":"VEC3",)"
    << R"("min":[0,0,0],"max":[1,1,1]},)"
    << R"({"bufferView":1,"componentType":5123,"count":36,"type":"SCALAR"}]})";
  return j.str();
}

void expectGltfScene(const TriMesh& m) {
  EXPECT_EQ(m.vertices.size(), 16u);
  EXPECT_EQ(m.triangles.size(), 24u);
  // Node transforms compose parent * child and are applied: bounds from both instances.
  EXPECT_EQ(m.bounds().min(), Vec3(-6, 0, 0));
  EXPECT_EQ(m.bounds().max(), Vec3(12, 2, 2));
  // Volume 2^3 + 1 = 9 only if the mirrored instance's winding was flipped back (else 7).
  EXPECT_NEAR(test::fluxVolume(m), 9.0, 1e-12);
}

TEST(MeshImport, GltfEmbeddedBufferWithNodeTransforms) {
  test::TempDir dir;
  std::string bin;
  writeFile(dir.file("scene.gltf"), gltfJson(bin, true));
  expectGltfScene(importMesh(dir.file("scene.gltf")));
}

TEST(MeshImport, Glb) {
  test::TempDir dir;
  std::string bin;
  std::string json = gltfJson(bin, false);
  while (json.size() % 4 != 0) json += ' ';  // chunks are 4-byte aligned
  while (bin.size() % 4 != 0) bin += '\0';
  std::string glb;
  appendRaw<std::uint32_t>(glb, 0x46546C67);  // "glTF"
  appendRaw<std::uint32_t>(glb, 2);
  appendRaw<std::uint32_t>(glb, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  appendRaw<std::uint32_t>(glb, static_cast<std::uint32_t>(json.size()));
  appendRaw<std::uint32_t>(glb, 0x4E4F534A);  // "JSON"
  glb += json;
  appendRaw<std::uint32_t>(glb, static_cast<std::uint32_t>(bin.size()));
  appendRaw<std::uint32_t>(glb, 0x004E4942);  // "BIN\0"
  glb += bin;
  writeFile(dir.file("scene.glb"), glb);
  expectGltfScene(importMesh(dir.file("scene.glb")));
}

TEST(MeshImport, NearbyButDistinctVerticesAreNotWelded) {
  // Two triangles whose corners differ by 1e-4 (far above float precision and the weld
  // tolerance of 1e-9 of the diagonal): a crack must stay visible to validateClosedMesh.
  test::TempDir dir;
  writeFile(dir.file("crack.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1.0001 0 0\nv 0 1.0001 0\nv 1 1 0\n"
            "f 1 2 3\nf 4 6 5\n");
  const TriMesh m = importMesh(dir.file("crack.obj"));
  EXPECT_EQ(m.vertices.size(), 6u);
  EXPECT_EQ(m.triangles.size(), 2u);
}

TEST(MeshImport, MissingFile) {
  const std::string path = "/nonexistent/voxfall/missing.obj";
  const std::string msg = inputErrorOf([&] { importMesh(path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST(MeshImport, GarbageFile) {
  test::TempDir dir;
  std::string junk;
  for (int i = 0; i < 1000; ++i) junk += static_cast<char>((i * 7919 + 13) % 256);
  for (const char* name : {"garbage.ply", "garbage.gltf", "garbage.unknownext"}) {
    writeFile(dir.file(name), junk);
    const std::string msg = inputErrorOf([&] { importMesh(dir.file(name)); });
    EXPECT_NE(msg.find(dir.file(name)), std::string::npos) << msg;
  }
}

TEST(MeshImport, FileWithoutTriangles) {
  test::TempDir dir;
  writeFile(dir.file("lines.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  const std::string msg = inputErrorOf([&] { importMesh(dir.file("lines.obj")); });
  EXPECT_NE(msg.find(dir.file("lines.obj")), std::string::npos) << msg;
  EXPECT_NE(msg.find("no triangles"), std::string::npos) << msg;
}

TEST(MeshImport, StanfordBunnyScanLoadsButIsNotClosed) {
  const std::string path = VOXFALL_TEST_DATA_DIR "/stanford_bunny_zipper_res3.ply";
  TriMesh m = importMesh(path);
  EXPECT_EQ(m.triangles.size(), 3851u);  // "element face 3851", all triangles
  EXPECT_LE(m.vertices.size(), 1889u);   // "element vertex 1889", some may be unused/welded
  const std::string msg = inputErrorOf([&] { validateClosedMesh(m, path); });
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("not closed"), std::string::npos) << msg;
}

TEST(MeshImport, SpotCowIsClosedWithPositiveVolume) {
  const std::string path = VOXFALL_TEST_DATA_DIR "/spot.obj";
  TriMesh m = importMesh(path);
  EXPECT_EQ(m.triangles.size(), 5856u);
  // The OBJ has 2930 positions and 3225 texture coordinates: UV seams split corners in
  // assimp, and welding by position must give exactly the file's 2930 vertices back.
  EXPECT_EQ(m.vertices.size(), 2930u);
  ASSERT_NO_THROW(validateClosedMesh(m, path));
  const double volume = computeMassProperties(m, 1.0).volume;
  EXPECT_GT(volume, 0);
  // Independent volume: flux of (x,0,0) through the surface. Both are sums of ~6000 terms of
  // size <= ~1e-3 with round-off ~1e-16 each: 1e-12 relative is ~100x the expected error.
  EXPECT_NEAR(test::fluxVolume(m), volume, 1e-12 * volume);
  // And signed tetrahedra from a far reference point (round-off grows with |ref|^3 ~ 1e3).
  const Vec3 ref(10, -7, 3);
  double v6 = 0;
  for (const auto& t : m.triangles)
    v6 += (m.vertices[t[0]] - ref).dot((m.vertices[t[1]] - ref).cross(m.vertices[t[2]] - ref));
  EXPECT_NEAR(v6 / 6, volume, 1e-9 * volume);
}

}  // namespace
}  // namespace vf
