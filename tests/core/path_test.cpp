// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/core/path.h"

#include <catch2/catch.hpp>

using namespace dermis;

TEST_CASE("path: the lower-cased extension of the file name") {
  CHECK(LowerExtension("Fox.GLB") == ".glb");
  CHECK(LowerExtension("dir/mesh.Obj") == ".obj");
  CHECK(LowerExtension("a.b/c.tar.GZ") == ".gz");
  CHECK(LowerExtension("dir.d/name") == "");
  CHECK(LowerExtension("dir.d\\name") == "");
  CHECK(LowerExtension("C:\\data\\scan.PLY") == ".ply");
  CHECK(LowerExtension("noext") == "");
  CHECK(LowerExtension("") == "");
  CHECK(LowerExtension("trailing.") == ".");
  CHECK(LowerExtension("dir/.obj") == ".obj");
  CHECK(LowerExtension("x.\xc3\x89T") == ".\xc3\x89t");  // non-ASCII bytes kept
}

TEST_CASE("path: ASCII lower case touches letters only") {
  CHECK(AsciiLower("ABC xyz 019 _-.") == "abc xyz 019 _-.");
  CHECK(AsciiLower("\xc3\x89") == "\xc3\x89");
  CHECK(AsciiLower("") == "");
}
