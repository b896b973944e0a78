// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Smoothing of control-vertex skin weights (sdk/src/offline/character/skin_smoothing.h):
// one umbrella step against hand-computed values, a crease cut open keeps its two sides equal
// and gives what the uncut mesh gives, the four largest influences kept, nothing from zero
// steps, a vertex without weights left alone.
#include "offline/character/skin_smoothing.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

namespace dermis {
namespace {

struct Weights {
  std::vector<glm::u16vec4> joints;
  std::vector<glm::vec4> weights;
};

// The weight of `joint` in vertex v's influences (0 if absent).
double WeightOf(const Weights& w, std::size_t v, int joint) {
  double s = 0.0;
  for (int k = 0; k < 4; ++k) {
    if (w.joints[v][k] == joint) s += static_cast<double>(w.weights[v][k]);
  }
  return s;
}

void Set(Weights* w, std::size_t v, std::uint16_t joint) {
  w->joints[v] = glm::u16vec4(joint, 0, 0, 0);
  w->weights[v] = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
}

// An nx by ny grid of unit quads in z = 0 with columns [x0, x0 + nx]; vertex (i, j) is
// j * (nx + 1) + i + first.
void AddGrid(int x0, int nx, int ny, std::vector<Vec3>* rest, std::vector<Index>* quads) {
  const Index first = static_cast<Index>(rest->size());
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) rest->push_back(Vec3(x0 + i, j, 0));
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Index a = first + j * (nx + 1) + i;
      quads->insert(quads->end(), {a, a + 1, a + 1 + nx + 1, a + nx + 1});
    }
  }
}

}  // namespace

TEST_CASE("skin smoothing: one umbrella step spreads a step of the weights by hand") {
  // Columns 0..3 on joint 3, columns 4..8 on joint 5.
  std::vector<Vec3> rest;
  std::vector<Index> quads;
  AddGrid(0, 8, 6, &rest, &quads);
  MeshTopology topo;
  REQUIRE(MeshTopology::BuildQuads(static_cast<Index>(rest.size()), quads, &topo).ok());
  Weights w{std::vector<glm::u16vec4>(rest.size()), std::vector<glm::vec4>(rest.size())};
  for (std::size_t v = 0; v < rest.size(); ++v) Set(&w, v, rest[v].x < 4.0 ? 3 : 5);
  Weights none = w;
  character::SmoothSkinWeights(topo, rest, 0, 0.5, &none.joints, &none.weights);
  CHECK(none.joints == w.joints);
  CHECK(none.weights == w.weights);
  character::SmoothSkinWeights(topo, rest, 1, 0.5, &w.joints, &w.weights);
  auto at = [](int i, int j) { return static_cast<std::size_t>(j * 9 + i); };
  // Interior: four neighbours, one across the step: half of a quarter moves over.
  CHECK(WeightOf(w, at(3, 3), 5) == Approx(0.125).epsilon(1e-6));
  CHECK(WeightOf(w, at(3, 3), 3) == Approx(0.875).epsilon(1e-6));
  CHECK(WeightOf(w, at(4, 3), 3) == Approx(0.125).epsilon(1e-6));
  // On the boundary: three neighbours.
  CHECK(WeightOf(w, at(3, 0), 5) == Approx(1.0 / 6.0).epsilon(1e-6));
  // Two columns away: untouched.
  CHECK(WeightOf(w, at(2, 3), 3) == 1.0);
  CHECK(WeightOf(w, at(6, 3), 5) == 1.0);
  // The strongest influence comes first; every vertex sums to 1.
  CHECK(w.joints[at(3, 3)][0] == 3);
  for (std::size_t v = 0; v < rest.size(); ++v) {
    const glm::vec4& x = w.weights[v];
    CHECK(x[0] + x[1] + x[2] + x[3] == Approx(1.0).epsilon(1e-6));
  }
}

TEST_CASE("skin smoothing: a crease cut open keeps its two sides equal, as the uncut mesh") {
  // Uncut: one grid, the middle column half on each joint. Cut: two grids whose columns at
  // x = 4 lie on the same points, the left copies on joint 3, the right ones on joint 5.
  std::vector<Vec3> rest_u, rest_c;
  std::vector<Index> quads_u, quads_c;
  AddGrid(0, 8, 4, &rest_u, &quads_u);
  AddGrid(0, 4, 4, &rest_c, &quads_c);
  AddGrid(4, 4, 4, &rest_c, &quads_c);
  MeshTopology tu, tc;
  REQUIRE(MeshTopology::BuildQuads(static_cast<Index>(rest_u.size()), quads_u, &tu).ok());
  REQUIRE(MeshTopology::BuildQuads(static_cast<Index>(rest_c.size()), quads_c, &tc).ok());
  Weights u{std::vector<glm::u16vec4>(rest_u.size()), std::vector<glm::vec4>(rest_u.size())};
  for (std::size_t v = 0; v < rest_u.size(); ++v) {
    if (rest_u[v].x == 4.0) {
      u.joints[v] = glm::u16vec4(3, 5, 0, 0);
      u.weights[v] = glm::vec4(0.5f, 0.5f, 0.0f, 0.0f);
    } else {
      Set(&u, v, rest_u[v].x < 4.0 ? 3 : 5);
    }
  }
  Weights c{std::vector<glm::u16vec4>(rest_c.size()), std::vector<glm::vec4>(rest_c.size())};
  const std::size_t left = 5 * 5;  // the left grid's vertices come first
  for (std::size_t v = 0; v < rest_c.size(); ++v) Set(&c, v, v < left ? 3 : 5);
  character::SmoothSkinWeights(tu, rest_u, 2, 0.5, &u.joints, &u.weights);
  character::SmoothSkinWeights(tc, rest_c, 2, 0.5, &c.joints, &c.weights);
  for (std::size_t v = 0; v < rest_c.size(); ++v) {
    // The same point of the uncut grid.
    const std::size_t vu =
        static_cast<std::size_t>(rest_c[v].y) * 9 + static_cast<std::size_t>(rest_c[v].x);
    INFO("vertex " << v << " at x " << rest_c[v].x << ", y " << rest_c[v].y);
    for (int joint : {3, 5}) {
      CHECK(WeightOf(c, v, joint) == Approx(WeightOf(u, vu, joint)).margin(1e-6));
    }
  }
}

TEST_CASE("skin smoothing: the four largest influences are kept, ties to the smaller joint") {
  // A fan: centre 0 on joint 0, five rim vertices on joints 1..5.
  std::vector<Vec3> rest = {Vec3(0, 0, 0)};
  std::vector<Index> offsets = {0}, verts;
  for (int k = 0; k < 5; ++k) {
    const double a = 2.0 * 3.14159265358979 * k / 5.0;
    rest.push_back(Vec3(std::cos(a), std::sin(a), 0));
  }
  for (Index k = 0; k < 5; ++k) {
    verts.insert(verts.end(), {0, 1 + k, 1 + (k + 1) % 5});
    offsets.push_back(static_cast<Index>(verts.size()));
  }
  MeshTopology topo;
  REQUIRE(MeshTopology::Build(6, offsets, verts, &topo).ok());
  Weights w{std::vector<glm::u16vec4>(6), std::vector<glm::vec4>(6)};
  for (std::uint16_t v = 0; v < 6; ++v) Set(&w, v, v);
  character::SmoothSkinWeights(topo, rest, 1, 0.5, &w.joints, &w.weights);
  // Centre: 0.5 on joint 0 and 0.1 on each of 1..5; joints 1, 2, 3 kept, normalised by 0.8.
  CHECK(w.joints[0] == glm::u16vec4(0, 1, 2, 3));
  CHECK(w.weights[0][0] == Approx(0.625).epsilon(1e-6));
  CHECK(w.weights[0][3] == Approx(0.125).epsilon(1e-6));
}

TEST_CASE("skin smoothing: a vertex without weights stays so and dilutes no neighbour") {
  std::vector<Vec3> rest;
  std::vector<Index> quads;
  AddGrid(0, 4, 4, &rest, &quads);
  MeshTopology topo;
  REQUIRE(MeshTopology::BuildQuads(static_cast<Index>(rest.size()), quads, &topo).ok());
  Weights w{std::vector<glm::u16vec4>(rest.size()), std::vector<glm::vec4>(rest.size())};
  for (std::size_t v = 0; v < rest.size(); ++v) Set(&w, v, 7);
  const std::size_t hole = 2 * 5 + 2;  // the middle vertex
  w.weights[hole] = glm::vec4(0.0f);
  // Weights not summing to 1 are normalised first.
  w.weights[0] = glm::vec4(0.25f, 0.0f, 0.0f, 0.0f);
  character::SmoothSkinWeights(topo, rest, 3, 0.5, &w.joints, &w.weights);
  CHECK(w.weights[hole] == glm::vec4(0.0f));
  for (std::size_t v = 0; v < rest.size(); ++v) {
    if (v == hole) continue;
    CHECK(w.joints[v][0] == 7);
    CHECK(w.weights[v][0] == 1.0f);
  }
}

}  // namespace dermis
