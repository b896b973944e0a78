// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The OBJ and the ASCII PLY reader share one number parser: the same token is the same value
// in both, and out-of-range magnitudes round as IEEE (and strtod) round them.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"

using namespace dermis;

namespace {

// The first coordinate of a one-point cloud read from OBJ and from ASCII PLY text, with the
// other two coordinates 0; the status of each read.
struct Both {
  Status obj, ply;
  double obj_x = std::nan(""), ply_x = std::nan("");
};

Both ReadToken(const std::string& token) {
  Both r;
  PolygonMesh m;
  r.obj = ParseObj("v " + token + " 0 0\n", "in.obj", &m, /*require_faces=*/false);
  if (r.obj.ok()) r.obj_x = m.positions.at(0).x;
  PolygonMesh p;
  r.ply = ParsePly(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n" +
          token + " 0 0\n",
      "in.ply", &p);
  if (r.ply.ok()) r.ply_x = p.positions.at(0).x;
  return r;
}

}  // namespace

TEST_CASE("text numbers: OBJ and PLY read every token alike") {
  const double denorm_min = std::numeric_limits<double>::denorm_min();
  const struct {
    const char* token;
    double value;  // expected, checked bit for bit (and against strtod)
  } cases[] = {
      {"1", 1.0},
      {"+2.5", 2.5},
      {"-0.125e1", -1.25},
      {"1e-400", 0.0},                 // underflow: 0 (the OBJ reader once read +infinity)
      {"-1e-400", -0.0},               // keeps its sign
      {"0.000001e-320", 0.0},          // the leading digit's exponent decides
      {"1e-310", 1e-310},              // subnormal, exact
      {"3e-324", denorm_min},          // rounds up to the smallest subnormal
      {"2.4703282292062327e-324", 0},  // just below half of it: 0
      {"123456789e-330", 1.23456789e-322},
      {"0.1", 0.1},
      {"1.7976931348623157e308", std::numeric_limits<double>::max()},
  };
  for (const auto& c : cases) {
    INFO(c.token);
    const Both r = ReadToken(c.token);
    REQUIRE(r.obj.ok());
    REQUIRE(r.ply.ok());
    CHECK(std::signbit(r.obj_x) == std::signbit(c.value));
    CHECK(r.obj_x == c.value);
    CHECK(r.ply_x == c.value);
    CHECK(std::signbit(r.ply_x) == std::signbit(c.value));
    const std::string unsigned_token = c.token[0] == '+' ? c.token + 1 : c.token;
    CHECK(std::strtod(unsigned_token.c_str(), nullptr) == c.value);
  }
}

TEST_CASE("text numbers: overflow and non-numbers are errors in both readers") {
  for (const char* token : {"1e400", "-1e400", "12345678901234567890e300", "inf", "-nan"}) {
    INFO(token);
    const Both r = ReadToken(token);
    REQUIRE_FALSE(r.obj.ok());
    REQUIRE_FALSE(r.ply.ok());
    CHECK_THAT(r.obj.message(), Catch::Contains("is not finite"));
    CHECK_THAT(r.ply.message(), Catch::Contains("is not finite"));
  }
  for (const char* token : {"1.0.0", "0x10", "1e", "--1", "1,5", "e5"}) {
    INFO(token);
    const Both r = ReadToken(token);
    REQUIRE_FALSE(r.obj.ok());
    REQUIRE_FALSE(r.ply.ok());
    CHECK_THAT(r.obj.message(), Catch::Contains("is not a number"));
    CHECK_THAT(r.ply.message(), Catch::Contains("is not a number"));
  }
}
