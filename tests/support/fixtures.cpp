// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/fixtures.h"

#include <catch2/catch.hpp>

#include "dermis/core/file_io.h"

namespace dermis::test {

std::string FixturePath(const std::string& name) {
  return std::string(DERMIS_TEST_FIXTURE_DIR) + "/" + name;
}

std::string FixtureBytes(const std::string& name) {
  std::string bytes;
  const Status s = ReadFileBytes(FixturePath(name), "a test fixture", &bytes);
  INFO(s.message());
  REQUIRE(s.ok());
  return bytes;
}

const Character& CylindersFixture() {
  static const Character ch = [] {
    Character c;
    const Status s = ParseCharacter(FixtureBytes("cylinders.dsurf"), "cylinders.dsurf", &c);
    INFO(s.message());
    REQUIRE(s.ok());
    return c;
  }();
  return ch;
}

DisplacedSurface SurfaceFixture(const std::string& builtin) {
  DisplacedSurface surface;
  const Status s = ParseDsurf(FixtureBytes(builtin + ".dsurf"), builtin + ".dsurf", &surface);
  INFO(s.message());
  REQUIRE(s.ok());
  return surface;
}

}  // namespace dermis::test
