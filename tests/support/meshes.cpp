// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/meshes.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "dermis/offline/geometry/builtin_meshes.h"

namespace dermis::test {

PolygonMesh FanMesh(int k, double sector, double height) {
  PolygonMesh m;
  m.source_name = "fan";
  const bool closed = std::abs(sector - 2.0 * M_PI) < 1e-12;
  const int edges = closed ? k : k + 1;
  m.positions.push_back(Vec3(0.0, 0.0, height));
  for (int i = 0; i < edges; ++i) {  // edge neighbours at radius 1
    const double a = sector * i / k;
    m.positions.push_back(Vec3(std::cos(a), std::sin(a), 0.0));
  }
  for (int i = 0; i < k; ++i) {  // diagonal neighbours at radius ~1.4
    const double a = sector * (i + 0.5) / k;
    m.positions.push_back(Vec3(1.4 * std::cos(a), 1.4 * std::sin(a), 0.0));
  }
  for (int i = 0; i < k; ++i) {
    const Index e0 = 1 + i, e1 = 1 + (i + 1) % edges, d = 1 + edges + i;
    m.AddFace({0, e0, d, e1});
  }
  return m;
}

void Perturb(PolygonMesh* mesh, double amount, std::uint32_t seed) {
  Lcg rng(seed);
  for (Vec3& p : mesh->positions) {
    for (int c = 0; c < 3; ++c) p[c] += amount * (2.0 * rng.Next() - 1.0);
  }
}

PolygonMesh Builtin(const std::string& name) {
  PolygonMesh m;
  const Status s = MakeBuiltinMesh(name, &m);
  INFO(s.message());
  REQUIRE(s.ok());
  return m;
}

}  // namespace dermis::test
