// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Small procedural control meshes so that demos and tests need no external data.
#include "dermis/offline/geometry/builtin_meshes.h"

#include <algorithm>
#include <cmath>

namespace dermis {
namespace {
constexpr double kPi = 3.14159265358979323846;

// Reverses faces whose Newell normal points towards the centroid (convex shapes only).
void OrientOutward(PolygonMesh* m) {
  Vec3 centroid(0.0);
  for (const Vec3& p : m->positions) centroid += p;
  centroid /= static_cast<double>(m->positions.size());
  for (Index f = 0; f < m->num_faces(); ++f) {
    const Index b = m->face_offsets[f], e = m->face_offsets[f + 1];
    Vec3 normal(0.0), center(0.0);
    for (Index h = b; h < e; ++h) {
      const Vec3 p = m->positions[m->face_vertices[h]];
      const Vec3 q = m->positions[m->face_vertices[h + 1 < e ? h + 1 : b]];
      normal += glm::cross(p, q);
      center += p;
    }
    center /= static_cast<double>(e - b);
    if (glm::dot(normal, center - centroid) < 0.0) {
      std::reverse(m->face_vertices.begin() + b, m->face_vertices.begin() + e);
    }
  }
}

void Cube(PolygonMesh* m, bool with_top) {
  m->positions = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  m->AddFace({0, 3, 2, 1});
  m->AddFace({0, 1, 5, 4});
  m->AddFace({1, 2, 6, 5});
  m->AddFace({2, 3, 7, 6});
  m->AddFace({3, 0, 4, 7});
  if (with_top) m->AddFace({4, 5, 6, 7});
}

}  // namespace

std::vector<std::string> BuiltinMeshNames() {
  return {"cube", "tetrahedron", "octahedron", "torus", "prismN (N = 3..64)", "grid", "house"};
}

Status MakeBuiltinMesh(const std::string& name, PolygonMesh* mesh) {
  PolygonMesh m;
  m.source_name = "builtin:" + name;
  if (name == "cube") {
    Cube(&m, true);
  } else if (name == "tetrahedron") {
    m.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    m.AddFace({0, 1, 2});
    m.AddFace({0, 3, 1});
    m.AddFace({0, 2, 3});
    m.AddFace({1, 3, 2});
    OrientOutward(&m);
  } else if (name == "octahedron") {
    m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const Index ring[4] = {0, 2, 1, 3};
    for (int i = 0; i < 4; ++i) {
      m.AddFace({ring[i], ring[(i + 1) % 4], 4});
      m.AddFace({ring[(i + 1) % 4], ring[i], 5});
    }
    OrientOutward(&m);
  } else if (name == "torus") {
    const int nu = 8, nv = 6;
    const double big = 1.0, small = 0.4;
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        const double u = 2.0 * kPi * i / nu, v = 2.0 * kPi * j / nv;
        m.positions.push_back({(big + small * std::cos(v)) * std::cos(u),
                               (big + small * std::cos(v)) * std::sin(u), small * std::sin(v)});
      }
    }
    auto id = [&](int i, int j) { return static_cast<Index>((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j)
        m.AddFace({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  } else if (name.rfind("prism", 0) == 0 && name.size() > 5) {
    const std::string digits = name.substr(5);
    if (digits.size() > 2 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) {
      return Status::InvalidInput("unknown built-in mesh '" + name + "'");
    }
    const int n = std::stoi(digits);
    if (n < 3 || n > 64) {
      return Status::InvalidInput("built-in prism needs 3..64 sides, got " + digits);
    }
    for (int z = 0; z < 2; ++z)
      for (int i = 0; i < n; ++i) {
        const double a = 2.0 * kPi * i / n;
        m.positions.push_back({std::cos(a), std::sin(a), z == 0 ? -0.5 : 0.5});
      }
    std::vector<Index> bottom, top;
    for (int i = 0; i < n; ++i) {
      bottom.push_back(static_cast<Index>(n - 1 - i));
      top.push_back(static_cast<Index>(n + i));
      m.AddFace({static_cast<Index>(i), static_cast<Index>((i + 1) % n),
                 static_cast<Index>(n + (i + 1) % n), static_cast<Index>(n + i)});
    }
    m.AddFace(bottom);
    m.AddFace(top);
    OrientOutward(&m);
  } else if (name == "grid") {
    const int nx = 4, ny = 3;
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const double x = i - 0.5 * nx, y = j - 0.5 * ny;
        m.positions.push_back({x, y, 0.15 * x * x - 0.1 * y * y});
      }
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Index a = static_cast<Index>(j * (nx + 1) + i);
        m.AddFace({a, a + 1, a + 1 + nx + 1, a + nx + 1});
      }
  } else if (name == "house") {
    Cube(&m, false);
    m.positions.push_back({0, 0, 2.2});
    for (Index i = 0; i < 4; ++i) m.AddFace({4 + i, 4 + (i + 1) % 4, 8});
    OrientOutward(&m);
  } else {
    return Status::InvalidInput("unknown built-in mesh '" + name + "'");
  }
  *mesh = std::move(m);
  return Status::Ok();
}

}  // namespace dermis
