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

PolygonMesh BumpySphereMesh(int n_theta, int n_phi, double a) {
  const double pi = 3.14159265358979323846;
  auto bumpy = [a](double theta, double phi) {
    const double r = 1.0 + a * std::sin(3.0 * theta) * std::sin(2.0 * phi);
    return r *
           Vec3(std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta), std::cos(phi));
  };
  PolygonMesh m;
  m.source_name = "bumpy sphere";
  m.positions.push_back(bumpy(0.0, 0.0));
  for (int j = 1; j < n_phi; ++j) {
    for (int i = 0; i < n_theta; ++i)
      m.positions.push_back(bumpy(2 * pi * i / n_theta, pi * j / n_phi));
  }
  m.positions.push_back(bumpy(0.0, pi));
  const Index south = m.num_vertices() - 1;
  auto at = [&](int j, int i) { return 1 + (j - 1) * n_theta + (i % n_theta); };
  for (int i = 0; i < n_theta; ++i) m.AddFace({0, at(1, i), at(1, i + 1)});
  for (int j = 1; j + 1 < n_phi; ++j) {
    for (int i = 0; i < n_theta; ++i) {
      m.AddFace({at(j, i), at(j + 1, i), at(j + 1, i + 1)});
      m.AddFace({at(j, i), at(j + 1, i + 1), at(j, i + 1)});
    }
  }
  for (int i = 0; i < n_theta; ++i) m.AddFace({south, at(n_phi - 1, i + 1), at(n_phi - 1, i)});
  return m;
}

}  // namespace dermis::test
