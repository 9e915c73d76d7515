// importMesh: OBJ, STL (ascii and binary), PLY, glTF (embedded base64) and GLB written by the
// test; welding; node transforms; errors; the two real meshes in tests/data.
#include "sim/geometry/mesh_import.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
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

// The message of the InputError that importing `path` throws, which must name that file, or
// `where` when given ("" and a test failure if none is thrown).
std::string importErrorOf(const std::string& path, const std::string& where = "") {
  try {
    importMesh(path);
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), where.empty() ? path : where);
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
// hold NaN or infinity would overflow the weld grid's keys (undefined behaviour), so it is an
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
// ASCII PLY whose header is cut off inside a property line; the import refuses a PLY header
// without 'end_header' before assimp sees it (without the check this test hangs until CTest's
// timeout).
TEST(MeshImport, FuzzFoundCutOffPlyHeaderIsAnError) {
  test::TempDir dir;
  writeFile(dir.file("cut.ply"), "ply\nformat ascii 1.0\nelement vertex 8\nproperty flo");
  EXPECT_EQ(importErrorOf(dir.file("cut.ply")),
            "PLY header has no 'end_header' line (is the file cut off?)");
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): an ASCII PLY cube with one face
// line garbled (bytes 0xe0 0xd2 for an index, the next line a comment) makes assimp 5.2 flag
// polygons in a mesh of triangles, and its triangulation aborts the process on an assertion:
// assimp reads the garbled line as a face without vertices. The layout check (ply_check.h)
// refuses the line itself: a list of 3 with two words after it. A face list of length 0 is
// well-formed for that check, and gives assimp the same face without vertices: refused after
// assimp has read the file, before its triangulation.
TEST(MeshImport, FuzzFoundGarbledPlyFaceIsAnErrorNotAnAbort) {
  test::TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
      "property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
      "3 0 2 3\n3 0 3 1\n3 4 5 7\n3 4 7 6\n3 0 1 5\n";
  const std::string tail = "3 2 7 3\n3 0 4 6\n3 0 6 2\n3 1 3 7\n3 1 7 5\n";
  writeFile(dir.file("garbled.ply"), header + "3 0 5\xe0\xd2\n# 2 6 7\n" + tail);
  // Line 23: 9 header lines, 8 vertices, then the sixth face.
  EXPECT_EQ(importErrorOf(dir.file("garbled.ply"), dir.file("garbled.ply") + ":23"),
            "PLY list 'vertex_indices' in entry 6 of 12 of element 'face' is 3 long, more than "
            "the 2 numbers after it on its line");
  writeFile(dir.file("empty_face.ply"), header + "0\n3 2 6 7\n" + tail);
  // Which face number assimp's reader gives the empty face is its business: not pinned.
  const std::string message = importErrorOf(dir.file("empty_face.ply"));
  EXPECT_NE(message.find("has no vertices"), std::string::npos) << message;
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): the same hang with the magic
// number followed by other bytes on its line ("plyCCC..."), which assimp still reads as a PLY,
// so the check must take it for one too. Its property of type "fply" is refused because the
// check follows every property's type (FuzzFoundPlyPropertyOfAnUnknownTypeIsRefused); with a
// float in its place and without its second format line the header is cut off as above.
TEST(MeshImport, FuzzFoundPlyMagicWithTrailingBytesAndCutHeaderIsAnError) {
  test::TempDir dir;
  const std::string magic = "ply" + std::string(42, 'C') + "\nformat ascii 1.0\nelement vertex 8\n";
  writeFile(dir.file("cut.ply"), magic + "property fply\nformat aloat x\n.mat as");
  EXPECT_NE(importErrorOf(dir.file("cut.ply"), dir.file("cut.ply") + ":4")
                .find("PLY header line 'property fply' has type 'fply'"),
            std::string::npos);
  writeFile(dir.file("cut.ply"), magic + "property float x\n.mat as");
  EXPECT_EQ(importErrorOf(dir.file("cut.ply")),
            "PLY header has no 'end_header' line (is the file cut off?)");
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz): assimp 5.2 never returns from a
// PLY whose file ends right after "end_header", without its newline, when the header also holds
// a line it does not know (of 11 characters or more; shorter ones, or a "comment", and it
// reports the file empty). In every format. The layout check refuses a header cut off there,
// naming the line (without the check this test hangs until CTest's timeout).
TEST(MeshImport, FuzzFoundPlyEndingInsideItsEndHeaderLineIsAnErrorNotAHang) {
  test::TempDir dir;
  for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
    writeFile(dir.file("cut.ply"),
              std::string("ply\nformat ") + format + " 1.0\nxxxxxxxxxxx\nend_header");
    EXPECT_EQ(importErrorOf(dir.file("cut.ply"), dir.file("cut.ply") + ":4"),
              "PLY file ends inside its 'end_header' line: no newline and no data after it (is "
              "the file cut off?)")
        << format;
  }
}

// Regression for a fuzz finding (tests/fuzz, mesh_ply_fuzz: an allocation of 92 GB): assimp 5.2
// reads an element's count from the leading digits after its name, and a name that starts with
// a digit as the count, so "element 30000000face 1" took 700 MB and over two minutes in
// assimp (measured with /usr/bin/time without the check), and a count with letters after it
// ("84294967295y") is not the number the layout check would follow. An element line must be
// "element NAME COUNT" in a header of text: the line is named and nothing allocated.
TEST(MeshImport, FuzzFoundPlyElementLineWithoutAWholeCountIsRefused) {
  test::TempDir dir;
  for (const std::string element : {"30000000face 1", "30000000 1", "face 84294967295y", "face x",
                                    "face", "face -1", "face 99999999999999999999999"}) {
    writeFile(dir.file("e.ply"),
              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement " +
                  element +
                  "\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                  "3 0 1 2\n");
    EXPECT_EQ(importErrorOf(dir.file("e.ply"), dir.file("e.ply") + ":7"),
              "PLY header line 'element " + element +
                  "' should be 'element NAME COUNT', a name that does not start with a digit "
                  "and a whole number");
  }
  // assimp also ends a header line at '\f', '\r' or '\0', so an element line hidden behind one
  // (a fuzz input's, the allocation valgrind could not give) is read by assimp and not by a
  // check that splits at newlines: a control character in a header is refused where it is.
  for (const char control : {'\f', '\r', '\0', '\v'}) {
    std::string s =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z#element 4294967295face 1\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    s[s.find('#')] = control;
    writeFile(dir.file("e.ply"), s);
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02x", static_cast<unsigned char>(control));
    EXPECT_EQ(importErrorOf(dir.file("e.ply"), dir.file("e.ply") + ":6:17"),
              std::string("PLY header line holds the control character ") + byte +
                  "; a PLY header is text");
  }
  // A file is taken for a PLY by its magic number too, whatever its name (assimp does).
  writeFile(dir.file("e.mesh"), "ply\nformat ascii 1.0\nelement face x\nend_header\n");
  EXPECT_EQ(importErrorOf(dir.file("e.mesh"), dir.file("e.mesh") + ":3"),
            "PLY header line 'element face x' should be 'element NAME COUNT', a name that does "
            "not start with a digit and a whole number");
  // Bytes outside printable ASCII (here UTF-8 for "é") are shown as '?' in the message.
  writeFile(dir.file("e.ply"), "ply\nformat ascii 1.0\nelement vertex 3\xc3\xa9\nend_header\n");
  EXPECT_EQ(importErrorOf(dir.file("e.ply"), dir.file("e.ply") + ":3"),
            "PLY header line 'element vertex 3?\?' should be 'element NAME COUNT', a name that "
            "does not start with a digit and a whole number");
}

// A binary PLY of 250 bytes that declares 300 million vertices, one of them a property of type
// "foo", takes assimp 5.2 3.5 GB and 25 s before it gives up (/usr/bin/time, without the check),
// and with a type PLY does not have, the layout check cannot follow the data. So every property
// must have one of PLY's types, a list an integer length, and come after an element line.
TEST(MeshImport, FuzzFoundPlyPropertyOfAnUnknownTypeIsRefused) {
  test::TempDir dir;
  const std::string types =
      "it should be one of PLY's types (char, uchar, short, ushort, int, uint, float, double, "
      "int8, uint8, int16, uint16, int32, uint32, float32, float64)";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"element vertex 300000000\nproperty float x\nproperty foo w",
       "'property foo w' has type 'foo': " + types},
      {"element vertex 300000000\nproperty list foo int x",
       "'property list foo int x' gives a list a length of type 'foo': it should be one of "
       "PLY's integer types"},
      {"element vertex 300000000\nproperty list float int x",
       "'property list float int x' gives a list a length of type 'float': it should be one of "
       "PLY's integer types"},
      {"element vertex 300000000\nproperty list uchar Float x",
       "'property list uchar Float x' has type 'Float': " + types},
      {"property float x\nelement vertex 3", "'property float x' comes before any 'element' line"}};
  for (const auto& [lines, message] : cases) {
    writeFile(dir.file("u.ply"), "ply\nformat binary_little_endian 1.0\n" + lines +
                                     "\nend_header\n" + std::string(60, '0'));
    // The property line: the last one, or line 3 where it comes first.
    const int line = lines.rfind("property", 0) == 0
                         ? 3
                         : 3 + static_cast<int>(std::count(lines.begin(), lines.end(), '\n'));
    EXPECT_EQ(importErrorOf(dir.file("u.ply"), dir.file("u.ply") + ":" + std::to_string(line)),
              "PLY header line " + message);
  }
}

// Regression for a fuzz finding (valgrind over mutated PLY files, each checked): assimp 5.2 goes
// on with "format binary_little_end_header" and a vertex count of 42949672958, allocating
// until the memory runs out. A PLY header has one format line, of PLY's three formats.
TEST(MeshImport, FuzzFoundPlyWithAFormatPlyDoesNotHaveIsRefused) {
  test::TempDir dir;
  const std::string rest =
      "element vertex 42949672958\nproperty float x\nproperty float y\nproperty float z\n"
      "end_header\n" +
      std::string(60, '0');
  writeFile(dir.file("f.ply"), "ply\nformat binary_little_end_header\nendian 0/0\n" + rest);
  EXPECT_EQ(importErrorOf(dir.file("f.ply"), dir.file("f.ply") + ":2"),
            "PLY header line 'format binary_little_end_header' should be 'format ascii 1.0', "
            "'format binary_little_endian 1.0' or 'format binary_big_endian 1.0'");
  writeFile(dir.file("f.ply"), "ply\nformat ascii 1.0\nformat binary_big_endian 1.0\n" + rest);
  EXPECT_EQ(importErrorOf(dir.file("f.ply"), dir.file("f.ply") + ":3"),
            "PLY header has a second 'format' line");
  writeFile(dir.file("f.ply"), "ply\ncomment no format\n" + rest);
  EXPECT_EQ(importErrorOf(dir.file("f.ply"), dir.file("f.ply") + ":7"),
            "PLY header ends without a 'format' line (ascii, binary_little_endian or "
            "binary_big_endian)");
}

// Two vertex lists, or two face lists, make assimp 5.2's PLY reader write past the arrays it
// sized by the first (valgrind: "Invalid write" inside libassimp, for each file below
// without the header check); found from an AddressSanitizer allocator failure in the PLY fuzz
// target. The header check refuses them, naming the second declaration's line.
TEST(MeshImport, FuzzFoundPlyWithTwoVertexOrFaceListsIsRefusedBeforeAssimpOverrunsItsArrays) {
  test::TempDir dir;
  const std::string vertex3 =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string faces1 = "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string data = "0 0 0\n1 0 0\n0 1 0\n";
  std::string more;
  for (int i = 0; i < 20; ++i) more += "0 0 1\n";
  writeFile(dir.file("vertices.ply"), "ply\nformat ascii 1.0\n" + vertex3 +
                                          "element vertex 20\nproperty float nx\nproperty "
                                          "float ny\nproperty float nz\n" +
                                          faces1 + "end_header\n" + data + more + "3 0 1 2\n");
  EXPECT_EQ(importErrorOf(dir.file("vertices.ply"), dir.file("vertices.ply") + ":7"),
            "PLY header declares a second vertex list ('element vertex') (the first is on line "
            "3); a mesh has one");
  std::string faces;
  for (int i = 0; i < 30; ++i) faces += "3 0 1 2\n";
  writeFile(dir.file("faces.ply"),
            "ply\nformat ascii 1.0\n" + vertex3 + faces1 +
                "element\ttristrips 1\nproperty list int int vertex_indices\n"  // any blank
                "element face 30\nproperty list uchar int vertex_indices\nend_header\n" +
                data + "3 0 1 2\n3 0 1 2 0\n" + faces);
  EXPECT_EQ(importErrorOf(dir.file("faces.ply"), dir.file("faces.ply") + ":9"),
            "PLY header declares a second face list ('element face' or 'element tristrips') "
            "(the first is on line 7); a mesh has one");
}

// A binary PLY of the unit box: 8 float vertices, 12 triangles as lists whose length has type
// `lengthType` (of `lengthBytes` bytes), indices int; `vertexCount` is what the header declares.
std::string binaryBoxPly(bool bigEndian, const std::string& lengthType, int lengthBytes,
                         std::uint64_t vertexCount = 8) {
  std::string s = std::string("ply\nformat binary_") + (bigEndian ? "big" : "little") +
                  "_endian 1.0\nelement vertex " + std::to_string(vertexCount) +
                  "\nproperty float x\nproperty float y\nproperty float z\nelement face 12\n"
                  "property list " +
                  lengthType + " int vertex_indices\nend_header\n";
  const auto put = [&](const void* v, int bytes) {
    const char* b = static_cast<const char*>(v);
    for (int k = 0; k < bytes; ++k) s += b[bigEndian ? bytes - 1 - k : k];  // x86-64: LE
  };
  for (const Vec3& v : kUnitBox.vertices)
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(v[k]);
      put(&f, 4);
    }
  for (const auto& t : kUnitBox.triangles) {
    const std::uint32_t three = 3;  // the low bytes of 3, whatever the length's width
    put(&three, lengthBytes);
    for (auto i : t) {
      const std::int32_t index = static_cast<std::int32_t>(i);
      put(&index, 4);
    }
  }
  return s;
}

// The PLY layout check (sim/geometry/ply_check.h): assimp 5.2 allocates what a PLY file's counts
// ask for before it reads the data, so a file of a few hundred bytes that declares 300 million
// vertices took 3.5 GB and over 20 s, and the fuzz target's face list of length
// "344444...4" (assimp's 32 bits keep 477 million of it) over 6 GB (measured with
// /usr/bin/time -v without the check). So each such count is refused against what the file holds.
TEST(MeshImport, FuzzFoundPlyCountsBeyondTheFileAreRefusedBeforeAssimpAllocatesThem) {
  test::TempDir dir;
  // ASCII: an entry per line, as assimp reads it. 4 data lines (10-13) for 300 million vertices.
  const std::string header3 =
      "ply\nformat ascii 1.0\nelement vertex 300000000\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  writeFile(dir.file("vertices.ply"), header3 + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(importErrorOf(dir.file("vertices.ply"), dir.file("vertices.ply") + ":13"),
            "PLY data ends in entry 5 of 300000000 of element 'vertex' (is the file cut off, or "
            "a count in it wrong?)");
  // A list length past 64 bits, and a negative one (assimp would take it as 4294967295).
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  for (const std::string length : {"3444444444444444444444444", "-1"}) {
    writeFile(dir.file("list.ply"), header + length + " 0 1 2\n");
    EXPECT_EQ(importErrorOf(dir.file("list.ply"), dir.file("list.ply") + ":13"),
              "PLY list 'vertex_indices' in entry 1 of 1 of element 'face' is " + length +
                  " long, more than the 3 numbers after it on its line");
  }

  // Binary, little- and big-endian, lengths of 1 and 4 bytes: the well-formed box loads (so the
  // check reads each length in the file's byte order and width)...
  for (bool bigEndian : {false, true}) {
    writeFile(dir.file("box.ply"), binaryBoxPly(bigEndian, "uchar", 1));
    expectUnitBox(importMesh(dir.file("box.ply")));
    writeFile(dir.file("box.ply"), binaryBoxPly(bigEndian, "uint", 4));
    expectUnitBox(importMesh(dir.file("box.ply")));
  }
  // ...and 300 million vertices of 12 bytes do not fit the 252 bytes after the header: its
  // 8 vertices and 12 faces of 1 + 12 bytes hold 21 whole vertices.
  writeFile(dir.file("box.ply"), binaryBoxPly(false, "uchar", 1, 300000000));
  EXPECT_EQ(importErrorOf(dir.file("box.ply")),
            "PLY data ends in entry 22 of 300000000 of element 'vertex' (is the file cut off, or "
            "a count in it wrong?)");
  // A face's length set to 2^32 - 16 (uint), then to -1 (int).
  std::string box = binaryBoxPly(false, "uint", 4);
  box.replace(box.size() - 12 * 16, 4, std::string("\xf0\xff\xff\xff", 4));  // first face
  writeFile(dir.file("box.ply"), box);
  EXPECT_EQ(importErrorOf(dir.file("box.ply")),
            "PLY list 'vertex_indices' in entry 1 of 12 of element 'face' is 4294967280 long, "
            "more than the 188 bytes left in the file hold");
  box = binaryBoxPly(false, "int", 4);
  box.replace(box.size() - 12 * 16, 4, std::string("\xff\xff\xff\xff", 4));
  writeFile(dir.file("box.ply"), box);
  EXPECT_EQ(importErrorOf(dir.file("box.ply")),
            "PLY list 'vertex_indices' in entry 1 of 12 of element 'face' is -1 long, more than "
            "the 188 bytes left in the file hold");
}

// assimp 5.2 pairs a face's texture coordinates with its vertices by reading the vertex list at
// half the coordinate's index, so more than two per vertex read past that list (valgrind,
// "Invalid read" in libassimp, on the file below without the check). Two per vertex load.
TEST(MeshImport, FuzzFoundPlyFaceWithMoreTexcoordsThanVerticesIsRefused) {
  test::TempDir dir;
  const auto box = [](const std::string& face0) {
    std::ostringstream s;
    s << "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
         "property float z\nelement face 12\nproperty list uchar int vertex_indices\n"
         "property list uchar float texcoord\nend_header\n";
    for (const Vec3& v : kUnitBox.vertices) s << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (std::size_t f = 0; f < kUnitBox.triangles.size(); ++f) {
      const auto& t = kUnitBox.triangles[f];
      if (f == 0 && !face0.empty()) {
        s << face0 << "\n";
        continue;
      }
      s << "3 " << t[0] << " " << t[1] << " " << t[2] << " 6 0 0 1 0 0 1\n";
    }
    return s.str();
  };
  writeFile(dir.file("box.ply"), box(""));
  expectUnitBox(importMesh(dir.file("box.ply")));
  writeFile(dir.file("box.ply"), box("1 0 6 0 0 1 0 0 1"));  // line 19: the first face
  EXPECT_EQ(importErrorOf(dir.file("box.ply"), dir.file("box.ply") + ":19"),
            "PLY entry 1 of 12 of element 'face' has 6 texture coordinates for a vertex list of 1 "
            "(at most two per vertex)");
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
