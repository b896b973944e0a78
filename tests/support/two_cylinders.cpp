// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/two_cylinders.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace dermis::test {

/// A closed capsule: a cylinder along y in [0, 2] with hemispherical caps, radius 0.5, as one
/// glTF-like primitive whose side and caps have their own vertices (split at the junctions, as UV
/// seams do), skinned to two joints with weights blending around y = 1. Placed at x0 along x.
void AddCylinder(double x0, AssetPrimitive* prim) {
  const int seg = 24, rings = 17;
  const auto base = static_cast<std::uint32_t>(prim->positions.size());
  auto add = [&](double x, double y, double z, glm::vec2 uv) {
    prim->positions.emplace_back(static_cast<float>(x0 + x), static_cast<float>(y),
                                 static_cast<float>(z));
    const double t = std::min(1.0, std::max(0.0, (y - 0.7) / 0.6));
    const float w1 = static_cast<float>(t * t * (3.0 - 2.0 * t));
    prim->joints[0].emplace_back(0, 1, 0, 0);
    prim->weights[0].emplace_back(1.0f - w1, w1, 0.0f, 0.0f);
    prim->texcoords[0].push_back(uv);
  };
  for (int r = 0; r < rings; ++r) {
    for (int s = 0; s < seg; ++s) {
      const double a = 2.0 * M_PI * s / seg, y = 2.0 * r / (rings - 1);
      add(0.5 * std::cos(a), y, 0.5 * std::sin(a), glm::vec2(float(s) / seg, float(r) / rings));
    }
  }
  for (int r = 0; r + 1 < rings; ++r) {
    for (int s = 0; s < seg; ++s) {
      const std::uint32_t a = base + static_cast<std::uint32_t>(r * seg + s),
                          b = base + static_cast<std::uint32_t>(r * seg + (s + 1) % seg);
      const std::uint32_t c = a + seg, d = b + seg;
      prim->indices.insert(prim->indices.end(), {a, c, b, b, c, d});
    }
  }
  // Hemispherical caps with their own copy of the end rings (welded back by position in the
  // fit): latitude rings at 0, 22.5, 45, 67.5 degrees and the pole.
  for (int cap = 0; cap < 2; ++cap) {
    const double y0 = cap == 0 ? 0.0 : 2.0, sign = cap == 0 ? -1.0 : 1.0;
    const auto first = static_cast<std::uint32_t>(prim->positions.size());
    for (int i = 0; i < 4; ++i) {
      const double phi = 0.5 * M_PI * i / 4;
      for (int s = 0; s < seg; ++s) {
        const double a = 2.0 * M_PI * s / seg;
        add(0.5 * std::cos(phi) * std::cos(a), y0 + sign * 0.5 * std::sin(phi),
            0.5 * std::cos(phi) * std::sin(a), glm::vec2(0.0f));
      }
    }
    const auto pole = static_cast<std::uint32_t>(prim->positions.size());
    add(0.0, y0 + sign * 0.5, 0.0, glm::vec2(0.5f, 0.5f));
    auto tri = [&](std::uint32_t p, std::uint32_t q, std::uint32_t r) {
      if (cap == 0) {
        prim->indices.insert(prim->indices.end(), {p, q, r});
      } else {
        prim->indices.insert(prim->indices.end(), {p, r, q});
      }
    };
    for (int i = 0; i < 4; ++i) {
      for (int s = 0; s < seg; ++s) {
        const std::uint32_t a = first + static_cast<std::uint32_t>(i * seg + s),
                            b = first + static_cast<std::uint32_t>(i * seg + (s + 1) % seg);
        if (i == 3) {
          tri(a, b, pole);
        } else {
          tri(a, b, a + seg);
          tri(b, b + seg, a + seg);
        }
      }
    }
  }
}

/// Two capsules (two components) and a lone triangle (too small), two joints.
Asset TwoCylinders() {
  Asset a;
  a.source = "two_cylinders";
  AssetPrimitive prim;
  prim.joints.resize(1);
  prim.weights.resize(1);
  prim.texcoords.resize(1);
  AddCylinder(0.0, &prim);
  AddCylinder(3.0, &prim);
  AssetPrimitive tiny;
  tiny.positions = {{10, 0, 0}, {11, 0, 0}, {10, 1, 0}};
  tiny.joints = {{glm::u16vec4(0), glm::u16vec4(0), glm::u16vec4(0)}};
  tiny.weights = {{glm::vec4(1, 0, 0, 0), glm::vec4(1, 0, 0, 0), glm::vec4(1, 0, 0, 0)}};
  tiny.indices = {0, 1, 2};
  AssetMesh mesh;
  mesh.name = "body";
  mesh.primitives = {prim, tiny};
  a.meshes.push_back(mesh);
  AssetNode root, j0, j1, body;
  root.name = "root";
  root.children = {1, 3};
  j0.name = "j0";
  j0.parent = 0;
  j0.children = {2};
  j1.name = "j1";
  j1.parent = 1;
  j1.translation = glm::dvec3(0, 1, 0);
  body.name = "body";
  body.parent = 0;
  body.mesh = 0;
  body.skin = 0;
  a.nodes = {root, j0, j1, body};
  AssetSkin skin;
  skin.joints = {1, 2};
  glm::mat4 ibm1(1.0f);
  ibm1[3] = glm::vec4(0, -1, 0, 1);
  skin.inverse_bind_matrices = {glm::mat4(1.0f), ibm1};
  a.skins.push_back(skin);
  AssetScene scene;
  scene.nodes = {0};
  a.scenes.push_back(scene);
  a.default_scene = 0;
  return a;
}

}  // namespace dermis::test
