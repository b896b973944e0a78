// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The source points a character part's fit adds where its surface leaves the source
// (sdk/src/offline/character/surface_gap_points.h), against planes whose distances are known.
#include "offline/character/surface_gap_points.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <vector>

#include "dermis/surface/surface_evaluator.h"
#include "support/domains.h"
#include "support/meshes.h"

namespace dermis {
namespace {

/// Two triangles covering [-10, 10]^2 at height z = a x + b.
PolygonMesh Plane(double a, double b) {
  PolygonMesh m;
  for (const double y : {-10.0, 10.0}) {
    for (const double x : {-10.0, 10.0}) m.positions.push_back(Vec3(x, y, a * x + b));
  }
  m.face_offsets = {0};
  m.AddFace({0, 1, 3});
  m.AddFace({0, 3, 2});
  return m;
}

/// The fitted surface of a flat closed fan of 4 quads (its domain surface is the plane z = 0,
/// no displacement), and the points of it SurfaceGapPoints evaluates (4 x 4 per face).
struct FlatFan {
  FittedSurface fitted;
  std::vector<Vec3> evaluated;
  FlatFan() {
    fitted.control_mesh = test::FanMesh(4, 2.0 * M_PI);
    fitted.surface = test::Build(fitted.control_mesh);
    const ManifoldDomain& domain = *fitted.surface.domain;
    for (Index f = 0; f < domain.num_faces(); ++f) {
      for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 4; ++j) {
          SurfacePoint sp;
          REQUIRE(EvaluateSurface(domain, fitted.surface.patches.data(), nullptr, f,
                                  Vec2((i + 0.5) / 4, (j + 0.5) / 4), &sp));
          evaluated.push_back(sp.position);
        }
      }
    }
  }
};

/// SurfaceGapPoints against `source`, its shading surface flat, or (`dome` > 0) Phong's at
/// shape 1 over corner normals leaning out by dome x their distance from the z axis.
std::vector<Vec3> Gaps(const FlatFan& fan, const PolygonMesh& source, double max_distance,
                       int per_edge = 4, double dome = 0.0) {
  TriangleDistanceTree tree;
  const std::vector<std::uint32_t> triangles(source.face_vertices.begin(),
                                             source.face_vertices.end());
  REQUIRE(tree.Build(source.positions, triangles));
  std::vector<Vec3> normals;
  if (dome > 0.0) {
    for (const Index v : source.face_vertices) {
      const Vec3& x = source.positions[v];
      normals.push_back(glm::normalize(Vec3(dome * x.x, dome * x.y, 1.0)));
    }
  }
  ShadingSurface shading;
  shading.Build(source, normals, dome > 0.0 ? 1.0 : 0.0, 0.0);
  return character::SurfaceGapPoints(fan.fitted, tree, shading, max_distance, per_edge);
}

}  // namespace

TEST_CASE("character surface gaps: a source 0.01 off gives the point over each sample") {
  const FlatFan fan;
  REQUIRE(fan.evaluated.size() == 64);
  for (const Vec3& p : fan.evaluated) REQUIRE(std::abs(p.z) < 1e-12);
  const PolygonMesh source = Plane(0.0, 0.01);
  // Every evaluated point is 0.01 from the source: all of them beyond 0.005, in order, each
  // with the source's point straight above it; none beyond 0.02.
  const std::vector<Vec3> gaps = Gaps(fan, source, 0.005);
  REQUIRE(gaps.size() == fan.evaluated.size());
  for (std::size_t k = 0; k < gaps.size(); ++k) {
    CHECK(gaps[k].x == Approx(fan.evaluated[k].x).margin(1e-12));
    CHECK(gaps[k].y == Approx(fan.evaluated[k].y).margin(1e-12));
    CHECK(gaps[k].z == Approx(0.01).margin(1e-12));
  }
  CHECK(Gaps(fan, source, 0.02).empty());
  CHECK(Gaps(fan, source, 0.0).empty());
  CHECK(Gaps(fan, source, 0.005, 0).empty());
  // 2 x 2 per face: 16 points.
  CHECK(Gaps(fan, source, 0.005, 2).size() == 16);
  // On a curved shading surface (the plane's Phong surface under normals leaning out, which
  // rises above the plane inside its triangles) the points are the shading surface's, not the
  // plane's: every one above it.
  const std::vector<Vec3> domed = Gaps(fan, source, 0.005, 4, 1e-3);
  REQUIRE(domed.size() == fan.evaluated.size());
  for (const Vec3& q : domed) CHECK(q.z > 0.0101);
}

TEST_CASE("character surface gaps: on a tilted source, the points farther than the bound") {
  // z = 0.02 x: a point (x, y, 0) is |0.02 x| / sqrt(1 + 0.02^2) from it.
  const FlatFan fan;
  const PolygonMesh source = Plane(0.02, 0.0);
  const double bound = 0.01;
  int expected = 0;
  for (const Vec3& p : fan.evaluated) {
    expected += std::abs(0.02 * p.x) / std::sqrt(1.0 + 0.02 * 0.02) > bound;
  }
  REQUIRE(expected > 0);
  REQUIRE(expected < static_cast<int>(fan.evaluated.size()));
  const std::vector<Vec3> gaps = Gaps(fan, source, bound);
  CHECK(static_cast<int>(gaps.size()) == expected);
  for (const Vec3& q : gaps) {
    CHECK(q.z == Approx(0.02 * q.x).margin(1e-12));  // on the source
    CHECK(std::abs(q.x) > 0.45);                     // where the surface is far from it
  }
}

}  // namespace dermis
