// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/io/ply_io.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

using namespace dermis;
namespace fs = std::filesystem;

namespace {

// Builds binary PLY data: header text followed by scalars in either byte order.
class Bytes {
 public:
  explicit Bytes(bool big_endian) : big_endian_(big_endian) {}

  Bytes& Text(const std::string& s) {
    data_ += s;
    return *this;
  }

  template <typename T>
  Bytes& Put(T value) {
    static_assert(std::is_arithmetic_v<T>, "scalars only");
    std::uint64_t bits = 0;
    if constexpr (std::is_same_v<T, float>) {
      std::uint32_t u;
      std::memcpy(&u, &value, sizeof(u));
      bits = u;
    } else if constexpr (std::is_same_v<T, double>) {
      std::memcpy(&bits, &value, sizeof(bits));
    } else {
      bits = static_cast<std::uint64_t>(static_cast<std::make_unsigned_t<T>>(value));
    }
    for (size_t i = 0; i < sizeof(T); ++i) {
      const size_t shift = 8 * (big_endian_ ? sizeof(T) - 1 - i : i);
      data_.push_back(static_cast<char>((bits >> shift) & 0xffu));
    }
    return *this;
  }

  // Three floats.
  Bytes& Point(float x, float y, float z) { return Put(x).Put(y).Put(z); }

  const std::string& str() const { return data_; }

 private:
  bool big_endian_;
  std::string data_;
};

std::string FormatLine(bool big_endian) {
  return big_endian ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n";
}

Status Parse(const std::string& bytes, PolygonMesh* m = nullptr) {
  PolygonMesh local;
  return ParsePly(bytes, "in.ply", m ? m : &local);
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) {
    s.replace(p, from.size(), to);
  }
  return s;
}

const char* kAsciiSquareRoof =
    "ply\n"
    "format ascii 1.0\n"
    "comment a unit square and a roof triangle\n"
    "element vertex 5\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 2\n"
    "property list uchar int vertex_indices\n"
    "end_header\n"
    "0 0 0\n"
    "1 0 0\n"
    "1 1 0\n"
    "0 1 0\n"
    "0.5 -0.5 1.25\n"
    "4 0 1 2 3\n"
    "3 1 0 4\n";

// The ascii header used by the error cases: 3 vertices, 1 face, the body starts on line 10.
const char* kAsciiHeader =
    "ply\n"
    "format ascii 1.0\n"
    "element vertex 3\n"
    "property float x\n"
    "property float y\n"
    "property float z\n"
    "element face 1\n"
    "property list uchar int vertex_indices\n"
    "end_header\n";
const char* kAsciiVertices = "0 0 0\n1 0 0\n0 1 0\n";

// A binary file with extra vertex properties, an extra element with a list between vertices and
// faces, and extra face properties around the index list. C and I are the count and index types.
template <typename C, typename I>
std::string BinaryMesh(bool big_endian, const std::string& count_type,
                       const std::string& index_type) {
  Bytes b(big_endian);
  b.Text("ply\n" + FormatLine(big_endian) +
         "comment written by the test\n"
         "obj_info nothing\n"
         "element vertex 4\n"
         "property float x\n"
         "property float y\n"
         "property float z\n"
         "property double nx\n"
         "property uchar red\n"
         "element edge 2\n"
         "property list uchar int vertex_pair\n"
         "property short weight\n"
         "element face 2\n"
         "property uchar flags\n"
         "property list " +
         count_type + " " + index_type +
         " vertex_indices\n"
         "property list uchar float texcoord\n"
         "end_header\n");
  const float pts[4][3] = {{0.1f, 0.2f, 0.3f}, {1, 0, 0}, {1, 1, 0}, {0, 1, -1e30f}};
  for (const auto& p : pts) b.Point(p[0], p[1], p[2]).Put(0.5).Put(std::uint8_t{200});
  b.Put(std::uint8_t{2}).Put(std::int32_t{0}).Put(std::int32_t{1}).Put(std::int16_t{-7});
  b.Put(std::uint8_t{0}).Put(std::int16_t{3});
  b.Put(std::uint8_t{9}).Put(C{3}).Put(I{0}).Put(I{1}).Put(I{2});
  b.Put(std::uint8_t{2}).Put(0.25f).Put(0.75f);
  b.Put(std::uint8_t{9}).Put(C{3}).Put(I{0}).Put(I{2}).Put(I{3});
  b.Put(std::uint8_t{0});
  return b.str();
}

// The binary header used by the error cases: 3 float vertices, then `face_count` faces with
// the given list types.
std::string BinaryHeader(const std::string& vertex_count, const std::string& face_count,
                         const std::string& count_type = "uchar",
                         const std::string& index_type = "int") {
  return "ply\n" + FormatLine(false) + "element vertex " + vertex_count +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + face_count +
         "\nproperty list " + count_type + " " + index_type + " vertex_indices\nend_header\n";
}

Bytes BinaryTriangleVertices() {
  Bytes b(false);
  b.Text(BinaryHeader("3", "1")).Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0);
  return b;
}

fs::path TempDir() {
  const fs::path dir =
      fs::temp_directory_path() / ("dermis_ply_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// Whatever a parse returned, a successful mesh must be consistent.
void CheckConsistent(const PolygonMesh& m) {
  REQUIRE(!m.face_offsets.empty());
  CHECK(m.face_offsets.front() == 0);
  CHECK(static_cast<size_t>(m.face_offsets.back()) == m.face_vertices.size());
  for (Index f = 0; f < m.num_faces(); ++f) CHECK(m.face_size(f) >= 3);
  for (Index v : m.face_vertices) CHECK((v >= 0 && v < m.num_vertices()));
}

}  // namespace

TEST_CASE("ply: ascii with faces", "[ply]") {
  for (const bool crlf : {false, true}) {
    INFO("crlf " << crlf);
    const std::string text =
        crlf ? Replace(kAsciiSquareRoof, "\n", "\r\n") : std::string(kAsciiSquareRoof);
    PolygonMesh m;
    const Status s = Parse(text, &m);
    INFO(s.message());
    REQUIRE(s.ok());
    CHECK(m.source_name == "in.ply");
    REQUIRE(m.num_vertices() == 5);
    CHECK(m.positions[0] == Vec3(0, 0, 0));
    CHECK(m.positions[2] == Vec3(1, 1, 0));
    CHECK(m.positions[4] == Vec3(0.5, -0.5, 1.25));
    REQUIRE(m.num_faces() == 2);
    CHECK(m.face_offsets == std::vector<Index>{0, 4, 7});
    CHECK(m.face_vertices == std::vector<Index>{0, 1, 2, 3, 1, 0, 4});
    CHECK(m.vertex_lines == std::vector<int>{11, 12, 13, 14, 15});
    CHECK(m.face_lines == std::vector<int>{16, 17});
    CHECK(ValidatePolygonMesh(m).ok());
  }
}

TEST_CASE("ply: ascii skips extra vertex properties and extra elements", "[ply]") {
  const std::string text =
      "ply\n"
      "format ascii 1.0\n"
      "obj_info made by hand\n"
      "element material 2\n"
      "property uchar red\n"
      "property list uchar float coeffs\n"
      "comment comments may appear anywhere in the header\n"
      "element vertex 3\n"
      "property double nx\n"
      "property float x\n"
      "property list ushort int neighbours\n"
      "property int16 y\n"
      "property uint8 red\n"
      "property float64 z\n"
      "property float confidence\n"
      "element edge 1\n"
      "property int vertex1\n"
      "property int vertex2\n"
      "element face 1\n"
      "property list uchar float texcoord\n"
      "property list int uint vertex_index\n"
      "property uchar flags\n"
      "element camera 1\n"
      "property float view_px\n"
      "end_header\n"
      "255 2 0.5 0.25\n"
      "\n"
      "0 0\n"
      "0.1 1 2 5 6 2 128 3 0.9\n"
      "-0.1 4 0 -5 0 6.5 nan\n"
      "1e5 7 1 0 8 255 9.25 1\n"
      "0 1\n"
      "6 0 0 1 0 1 1 3 2 1 0 7\n"
      "42.5\n";
  PolygonMesh m;
  const Status s = Parse(text, &m);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(m.num_vertices() == 3);
  CHECK(m.positions[0] == Vec3(1, 2, 3));
  CHECK(m.positions[1] == Vec3(4, -5, 6.5));
  CHECK(m.positions[2] == Vec3(7, 8, 9.25));
  CHECK(m.vertex_lines == std::vector<int>{29, 30, 31});
  REQUIRE(m.num_faces() == 1);
  CHECK(m.face_vertices == std::vector<Index>{2, 1, 0});
  CHECK(m.face_lines == std::vector<int>{33});
}

TEST_CASE("ply: binary little- and big-endian with extra properties and elements", "[ply]") {
  for (const bool big : {false, true}) {
    INFO("big endian " << big);
    std::vector<std::string> files = {
        BinaryMesh<std::uint8_t, std::int32_t>(big, "uchar", "int"),
        BinaryMesh<std::uint16_t, std::uint32_t>(big, "ushort", "uint"),
        BinaryMesh<std::int8_t, std::uint16_t>(big, "int8", "uint16"),
        BinaryMesh<std::uint32_t, std::uint8_t>(big, "uint32", "uchar"),
        BinaryMesh<std::int32_t, std::int16_t>(big, "int", "short"),
    };
    for (size_t i = 0; i < files.size(); ++i) {
      INFO("variant " << i);
      PolygonMesh m;
      const Status s = Parse(files[i], &m);
      INFO(s.message());
      REQUIRE(s.ok());
      CHECK(m.source_name == "in.ply");
      REQUIRE(m.num_vertices() == 4);
      // Floats are widened exactly.
      CHECK(m.positions[0] == Vec3(double{0.1f}, double{0.2f}, double{0.3f}));
      CHECK(m.positions[2] == Vec3(1, 1, 0));
      CHECK(m.positions[3] == Vec3(0, 1, double{-1e30f}));
      CHECK(m.face_offsets == std::vector<Index>{0, 3, 6});
      CHECK(m.face_vertices == std::vector<Index>{0, 1, 2, 0, 2, 3});
      CHECK(m.vertex_lines.empty());
      CHECK(m.face_lines.empty());
      CHECK(ValidatePolygonMesh(m).ok());
    }
  }
}

TEST_CASE("ply: binary coordinates of every scalar type", "[ply]") {
  for (const bool big : {false, true}) {
    INFO("big endian " << big);
    Bytes b(big);
    b.Text("ply\n" + FormatLine(big) +
           "element vertex 2\n"
           "property char a\n"
           "property int16 x\n"
           "property uint32 y\n"
           "property float64 z\n"
           "property ushort b\n"
           "end_header\n");
    b.Put(std::int8_t{-1}).Put(std::int16_t{-300}).Put(std::uint32_t{4000000000u});
    b.Put(1.0 / 3.0).Put(std::uint16_t{65535});
    b.Put(std::int8_t{1}).Put(std::int16_t{32767}).Put(std::uint32_t{0}).Put(-2e300);
    b.Put(std::uint16_t{0});
    PolygonMesh m;
    const Status s = Parse(b.str(), &m);
    INFO(s.message());
    REQUIRE(s.ok());
    REQUIRE(m.num_vertices() == 2);
    CHECK(m.positions[0] == Vec3(-300, 4000000000.0, 1.0 / 3.0));
    CHECK(m.positions[1] == Vec3(32767, 0, -2e300));
    CHECK(m.num_faces() == 0);
  }
  // int8/uint8/int32/float32 and uchar/char/int/uint/float/double as coordinates.
  for (const char* type : {"char", "uchar", "int8", "uint8", "short", "ushort", "int", "uint",
                           "int32", "uint32", "float", "float32", "double", "float64"}) {
    INFO(type);
    const std::string t(type);
    const std::string text = "ply\nformat ascii 1.0\nelement vertex 1\nproperty " + t +
                             " x\nproperty " + t + " y\nproperty " + t + " z\nend_header\n1 2 3\n";
    PolygonMesh m;
    REQUIRE(Parse(text, &m).ok());
    CHECK(m.positions[0] == Vec3(1, 2, 3));
  }
}

TEST_CASE("ply: point-only files have no faces", "[ply]") {
  PolygonMesh m;
  Status s = Parse(
      "ply\r\nformat ascii 1.0\r\nelement vertex 2\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nproperty float intensity\r\nend_header\r\n1 2 3 0.5\r\n4 5 6 0.5\r\n",
      &m);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(m.num_vertices() == 2);
  CHECK(m.num_faces() == 0);
  CHECK(m.face_offsets == std::vector<Index>{0});
  CHECK(m.positions[1] == Vec3(4, 5, 6));
  CHECK(m.vertex_lines == std::vector<int>{9, 10});

  for (const bool big : {false, true}) {
    Bytes b(big);
    b.Text("ply\n" + FormatLine(big) +
           "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
    b.Point(1, 2, 3).Point(4, 5, 6).Point(7, 8, 9.5f);
    PolygonMesh p;
    s = Parse(b.str(), &p);
    INFO(s.message());
    REQUIRE(s.ok());
    CHECK(p.num_vertices() == 3);
    CHECK(p.num_faces() == 0);
    CHECK(p.positions[2] == Vec3(7, 8, 9.5));
  }
}

TEST_CASE("ply: header errors name the file and the line", "[ply]") {
  struct Bad {
    std::string text, expect;
  };
  const std::string vertex_xyz =
      "element vertex 1\nproperty float x\nproperty float y\nproperty float z\n";
  const std::vector<Bad> cases = {
      {"", "in.ply: missing 'ply' magic"},
      {"plx\nformat ascii 1.0\nend_header\n", "in.ply: missing 'ply' magic"},
      {"OFF\n3 1 0\n", "in.ply: missing 'ply' magic"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz + "0 0 0\n", "in.ply: missing end_header"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz, "in.ply: missing end_header"},
      {"ply\nformat text 1.0\n" + vertex_xyz + "end_header\n0 0 0\n",
       "in.ply:2: unknown format 'text'"},
      {"ply\nformat ascii 2.0\n" + vertex_xyz + "end_header\n0 0 0\n",
       "in.ply:2: unsupported PLY version '2.0'"},
      {"ply\nformat ascii\n" + vertex_xyz + "end_header\n0 0 0\n", "in.ply:2: expected 'format"},
      {"ply\n" + vertex_xyz + "end_header\n0 0 0\n", "in.ply: missing format line"},
      {"ply\nformat ascii 1.0\nformat ascii 1.0\n" + vertex_xyz + "end_header\n0 0 0\n",
       "in.ply:3: a second format line"},
      {"ply\nformat ascii 1.0\nelement vertex\nend_header\n", "in.ply:3: expected 'element"},
      {"ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
       "in.ply:3: '-3' is not a valid element count"},
      {"ply\nformat ascii 1.0\nproperty float x\nend_header\n",
       "in.ply:3: a property before any element"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty flt x\nend_header\n",
       "in.ply:4: unknown property type 'flt'"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float\nend_header\n",
       "in.ply:4: expected 'property TYPE NAME'"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz + "property float x\nend_header\n",
       "in.ply:7: property 'x' of element 'vertex' is declared twice"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz + vertex_xyz + "end_header\n",
       "in.ply:7: element 'vertex' is declared twice"},
      {"ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n",
       "in.ply:3: unknown header line 'elemnt'"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz +
           "element face 1\nproperty list float int vertex_indices\nend_header\n",
       "in.ply:8: the list count type 'float' is not an integer"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz +
           "element face 1\nproperty list uchar int vertex_indices extra\nend_header\n",
       "in.ply:8: expected 'property list"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
       "end_header\n0 0\n",
       "in.ply:3: the vertex element has no 'z' property"},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\n"
       "property list uchar float x\nend_header\n1 0 0 0\n",
       "in.ply:3: vertex property 'x' is a list"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz +
           "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n3 0 0 0\n",
       "in.ply:7: the face element has no 'vertex_indices' list property"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz +
           "element face 1\nproperty int vertex_indices\nend_header\n0 0 0\n3\n",
       "in.ply:7: face property 'vertex_indices' is not a list"},
      {"ply\nformat ascii 1.0\n" + vertex_xyz +
           "element face 1\nproperty list uchar float vertex_indices\nend_header\n",
       "in.ply:7: face property 'vertex_indices' has non-integer indices"},
      {"ply\nformat ascii 1.0\nelement point 1\nproperty float x\nend_header\n0\n",
       "in.ply: no vertex element"},
      {"ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n",
       "in.ply:3: vertex count 99999999999 is too large"},
  };
  for (const Bad& b : cases) {
    INFO(b.text);
    const Status s = Parse(b.text);
    REQUIRE_FALSE(s.ok());
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK_THAT(s.message(), Catch::Contains(b.expect));
    CHECK_THAT(s.message(), Catch::Contains("in.ply"));
  }
}

TEST_CASE("ply: ascii data errors name the file and the line", "[ply]") {
  struct Bad {
    std::string body, expect;
  };
  const std::string v = kAsciiVertices;
  const std::vector<Bad> cases = {
      {"0 0 0\n1 0 0\n", "in.ply:11: the file ends after 2 of 3 vertex elements"},
      {"", "in.ply:9: the file ends after 0 of 3 vertex elements"},
      {v, "in.ply:12: the file ends after 0 of 1 face elements"},
      {v + "\n\n", "in.ply:14: the file ends after 0 of 1 face elements"},
      {"0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n", "in.ply:11: 'abc' is not a number"},
      {"0 0 0\n1 0 0\n0 1 0x1\n3 0 1 2\n", "in.ply:12: '0x1' is not a number"},
      {"0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n", "in.ply:10: vertex coordinate 'nan' is not finite"},
      {"0 0 0\n-inf 0 0\n0 1 0\n3 0 1 2\n", "in.ply:11: vertex coordinate '-inf' is not finite"},
      {"0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n", "in.ply:12: vertex coordinate '1e999' is not finite"},
      {"0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "in.ply:10: the line ends before vertex property 'z'"},
      {"0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", "in.ply:10: unexpected value '7'"},
      {v + "3 0 1 3\n", "in.ply:13: vertex index 3 is out of range (the file has 3 vertices)"},
      {v + "3 0 -1 2\n", "in.ply:13: vertex index -1 is out of range"},
      {v + "2 0 1\n", "in.ply:13: a face needs at least 3 vertices, this one has 2"},
      {v + "0\n", "in.ply:13: a face needs at least 3 vertices, this one has 0"},
      {v + "-1 0 1 2\n", "in.ply:13: negative list count -1"},
      {v + "4 0 1 2\n", "in.ply:13: list count 4 is larger than the number of values left"},
      {v + "99999999999999999999 0 1 2\n", "in.ply:13: '99999999999999999999' is not a list"},
      {v + "three 0 1 2\n", "in.ply:13: 'three' is not a list count"},
      {v + "3 0 x 2\n", "in.ply:13: 'x' is not a vertex index"},
      {v + "3 0 1.5 2\n", "in.ply:13: '1.5' is not a vertex index"},
      {v + "3 0 1 2 0\n", "in.ply:13: unexpected value '0'"},
  };
  for (const Bad& b : cases) {
    const std::string text = kAsciiHeader + b.body;
    INFO(text);
    const Status s = Parse(text);
    REQUIRE_FALSE(s.ok());
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK_THAT(s.message(), Catch::Contains(b.expect));
  }
  // Skipped properties and elements are still checked.
  const Status s = Parse(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nelement edge 1\nproperty list uchar int ends\nend_header\n"
      "0 0 0\n3 1 2\n");
  REQUIRE_FALSE(s.ok());
  CHECK_THAT(s.message(), Catch::Contains("in.ply:11: list count 3 is larger"));
}

TEST_CASE("ply: binary data errors name the file and the element", "[ply]") {
  struct Bad {
    std::string bytes, expect;
  };
  std::vector<Bad> cases;
  {  // Fewer vertices than declared.
    Bytes b(false);
    b.Text(BinaryHeader("3", "0")).Point(0, 0, 0).Point(1, 0, 0).Put(0.5f);
    cases.push_back({b.str(), "in.ply: vertex 2: truncated data"});
  }
  {  // A lying vertex count is refused before anything is reserved.
    Bytes b(false);
    b.Text(BinaryHeader("2000000000", "0")).Point(0, 0, 0);
    cases.push_back({b.str(), "in.ply: vertex 1: truncated data"});
  }
  {  // Fewer faces than declared.
    Bytes d(false);
    d.Text(BinaryHeader("3", "2")).Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0);
    d.Put(std::uint8_t{3}).Put(0).Put(1).Put(2);
    cases.push_back({d.str(), "in.ply: face 1: truncated data"});
  }
  {  // A face cut short inside its index list.
    Bytes b = BinaryTriangleVertices();
    b.Put(std::uint8_t{3}).Put(0).Put(1).Put(std::int16_t{2});
    cases.push_back({b.str(), "in.ply: face 0: list count 3 is larger than the 10 bytes left"});
  }
  {  // A lying face count.
    Bytes b(false);
    b.Text(BinaryHeader("3", "2000000000")).Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0);
    b.Put(std::uint8_t{3}).Put(0).Put(1).Put(2);
    cases.push_back({b.str(), "in.ply: face 1: truncated data"});
  }
  {
    Bytes b(false);
    b.Text(BinaryHeader("3", "4294967295"));
    cases.push_back({b.str(), "in.ply:7: face count 4294967295 is too large"});
  }
  {  // Non-finite coordinates.
    Bytes b(false);
    b.Text(BinaryHeader("3", "0")).Point(0, 0, 0).Point(1, std::nanf(""), 0).Point(0, 1, 0);
    cases.push_back({b.str(), "in.ply: vertex 1: vertex coordinate y = "});
    Bytes c(true);
    c.Text(Replace(BinaryHeader("3", "0"), "little", "big"));
    c.Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, -HUGE_VALF);
    cases.push_back({c.str(), "in.ply: vertex 2: vertex coordinate z = -inf is not finite"});
  }
  {  // Index out of range, signed and unsigned.
    Bytes b = BinaryTriangleVertices();
    b.Put(std::uint8_t{3}).Put(0).Put(1).Put(3);
    cases.push_back({b.str(), "in.ply: face 0: vertex index 3 is out of range"});
    Bytes c = BinaryTriangleVertices();
    c.Put(std::uint8_t{3}).Put(0).Put(-1).Put(2);
    cases.push_back({c.str(), "in.ply: face 0: vertex index -1 is out of range"});
    Bytes d(false);
    d.Text(BinaryHeader("3", "1", "uchar", "uint")).Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0);
    d.Put(std::uint8_t{3}).Put(0u).Put(4294967295u).Put(2u);
    cases.push_back({d.str(), "in.ply: face 0: vertex index 4294967295 is out of range"});
  }
  {  // Too few vertices in a face.
    Bytes b = BinaryTriangleVertices();
    b.Put(std::uint8_t{2}).Put(0).Put(1);
    cases.push_back({b.str(), "in.ply: face 0: a face needs at least 3 vertices, this one has 2"});
  }
  {  // Negative list count.
    Bytes b(false);
    b.Text(BinaryHeader("3", "1", "char", "int")).Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0);
    b.Put(std::int8_t{-1}).Put(0).Put(1).Put(2);
    cases.push_back({b.str(), "in.ply: face 0: negative list count -1"});
    Bytes c(true);
    c.Text(Replace(BinaryHeader("3", "1", "int", "int"), "little", "big"));
    c.Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0).Put(-2000000000).Put(0).Put(1).Put(2);
    cases.push_back({c.str(), "in.ply: face 0: negative list count -2000000000"});
  }
  {  // Counts larger than the remaining bytes, in the face list and in a skipped list.
    Bytes b = BinaryTriangleVertices();
    b.Put(std::uint8_t{200}).Put(0).Put(1).Put(2);
    cases.push_back({b.str(), "in.ply: face 0: list count 200 is larger than the 12 bytes left"});
    Bytes c(false);
    c.Text(Replace(BinaryHeader("3", "1", "uint", "int"), "element face 1",
                   "element edge 1\nproperty list uint double ends\nelement face 1"));
    c.Point(0, 0, 0).Point(1, 0, 0).Point(0, 1, 0).Put(4000000000u).Put(0.0);
    c.Put(3u).Put(0).Put(1).Put(2);
    cases.push_back({c.str(), "in.ply: edge 0: list count 4000000000 is larger"});
  }
  for (const Bad& b : cases) {
    INFO(b.expect);
    const Status s = Parse(b.bytes);
    REQUIRE_FALSE(s.ok());
    CHECK(s.code() == StatusCode::kInvalidInput);
    CHECK_THAT(s.message(), Catch::Contains(b.expect));
  }
}

TEST_CASE("ply: truncated and corrupted files never crash", "[ply]") {
  std::vector<std::string> files = {
      kAsciiSquareRoof,
      BinaryMesh<std::uint8_t, std::int32_t>(false, "uchar", "int"),
      BinaryMesh<std::uint16_t, std::uint32_t>(true, "ushort", "uint"),
  };
  int parsed = 0;
  for (const std::string& file : files) {
    // Every prefix.
    for (size_t n = 0; n < file.size(); ++n) {
      PolygonMesh m;
      if (ParsePly(std::string_view(file).substr(0, n), "cut.ply", &m).ok()) {
        ++parsed;
        CheckConsistent(m);
      }
    }
    // Every byte replaced by a few interesting values.
    for (size_t i = 0; i < file.size(); ++i) {
      for (const char c : {'\0', '\xff', '\x80', '\x7f', '\n', ' ', '9', '-'}) {
        std::string bad = file;
        bad[i] = c;
        PolygonMesh m;
        const Status s = ParsePly(bad, "bad.ply", &m);
        if (s.ok()) {
          ++parsed;
          CheckConsistent(m);
        } else {
          CHECK_THAT(s.message(), Catch::Contains("bad.ply"));
        }
      }
    }
  }
  CHECK(parsed > 0);
}

TEST_CASE("ply: reading files", "[ply]") {
  PolygonMesh m;
  Status s = ReadPly("/nonexistent/dir/mesh.ply", &m);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("/nonexistent/dir/mesh.ply"));
  const fs::path dir = TempDir();
  s = ReadPly(dir.string(), &m);
  CHECK(s.code() == StatusCode::kIoError);
  CHECK_THAT(s.message(), Catch::Contains("directory"));
  const fs::path file = dir / "mesh.ply";
  {
    std::ofstream f(file, std::ios::binary);
    const std::string bytes = BinaryMesh<std::uint8_t, std::int32_t>(true, "uchar", "int");
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  s = ReadPly(file.string(), &m);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(m.source_name == file.string());
  CHECK(m.num_vertices() == 4);
  CHECK(m.num_faces() == 2);
  fs::remove_all(dir);
}

TEST_CASE("ply: the Stanford bunny", "[ply]") {
  const std::string path = "../shared/data/scans/bun_zipper.ply";
  if (!fs::exists(path)) {
    WARN("skipping: " << path
                      << " not found (run from the repository root with the shared "
                         "data checked out)");
    return;
  }
  PolygonMesh m;
  const Status s = ReadPly(path, &m);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(m.num_vertices() == 35947);
  CHECK(m.num_faces() == 69451);
  CHECK(static_cast<float>(m.positions[0].x) == -0.0378297f);
  CHECK(static_cast<float>(m.positions[0].y) == 0.12794f);
  CHECK(static_cast<float>(m.positions[0].z) == 0.00447467f);
  for (Index f = 0; f < m.num_faces(); ++f) REQUIRE(m.face_size(f) == 3);
  REQUIRE(m.vertex_lines.size() == 35947);
  CHECK(m.vertex_lines.front() == 14);  // after a 13-line header
  CHECK(m.face_lines.back() == 13 + 35947 + 69451);
}
