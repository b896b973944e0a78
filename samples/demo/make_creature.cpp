// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The built-in demo creature: a procedurally generated limb with fine bumps, skinned to a
// 3-joint chain, with a 2-second clip that bends the middle joint by 90 degrees and twists the
// last one by 120 degrees and back: exactly the motion where linear blend skinning collapses
// and the sweep keeps the volume (paper section 5, docs/deformation.md). Written as a skinned
// glTF binary, the input of samples/demo/run_demo.sh.
//
//   sample_make_creature OUT.glb [--small]
//
// --small makes a coarser mesh (for the test run). Deterministic: same bytes every run.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <string>

#include "dermis/asset/asset.h"
#include "dermis/plugins/gltf.h"

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kLength = 4.0;  // the limb runs along +y from 0 to kLength
constexpr double kJoint1 = 1.4;  // elbow-like joint
constexpr double kJoint2 = 2.8;  // wrist-like joint

double Smoothstep(double e0, double e1, double x) {
  const double t = std::fmin(1.0, std::fmax(0.0, (x - e0) / (e1 - e0)));
  return t * t * (3.0 - 2.0 * t);
}

// Radius of the limb at height y and angle a: a taper, a bulge (muscle) below the elbow, and
// fine bumps: a lattice of small round scales, the detail the displacement must carry.
double Radius(double y, double a) {
  const double base = 0.42 - 0.035 * y + 0.06 * std::exp(-std::pow((y - 0.7) / 0.45, 2.0));
  const double bumps =
      0.018 * std::pow(std::fabs(std::sin(9.0 * a) * std::sin(7.0 * kPi * y / 2.0)), 3.0);
  const double ridge = 0.008 * std::sin(23.0 * a + 3.0 * y);
  return base + bumps + ridge;
}

// Skin weights of a point at height y over joints 0, 1, 2 (blend zones 0.5 wide).
glm::vec4 Weights(double y) {
  const double w12 = Smoothstep(kJoint1 - 0.25, kJoint1 + 0.25, y);
  const double w23 = Smoothstep(kJoint2 - 0.25, kJoint2 + 0.25, y);
  return glm::vec4(static_cast<float>(1.0 - w12), static_cast<float>(w12 * (1.0 - w23)),
                   static_cast<float>(w23), 0.0f);
}

void AddVertex(dermis::AssetPrimitive* prim, glm::dvec3 p, glm::vec2 uv) {
  prim->positions.emplace_back(p);
  prim->texcoords[0].push_back(uv);
  prim->joints[0].emplace_back(0, 1, 2, 0);
  prim->weights[0].push_back(Weights(p.y));
}

// A closed tube: `seg` columns (plus a duplicated seam column for the texture coordinates),
// `rings` rings, and hemispherical caps closing both ends.
dermis::AssetPrimitive Limb(int seg, int rings) {
  dermis::AssetPrimitive prim;
  prim.texcoords.resize(1);
  prim.joints.resize(1);
  prim.weights.resize(1);
  const double cap = 0.35;  // cap height
  for (int r = 0; r < rings; ++r) {
    const double y = kLength * r / (rings - 1);
    for (int s = 0; s <= seg; ++s) {
      const double a = 2.0 * kPi * s / seg;
      const double rad = Radius(y, a);
      AddVertex(&prim, glm::dvec3(rad * std::cos(a), y, -rad * std::sin(a)),
                glm::vec2(static_cast<float>(s) / static_cast<float>(seg),
                          static_cast<float>(y / kLength)));
    }
  }
  const int cols = seg + 1;
  for (int r = 0; r + 1 < rings; ++r) {
    for (int s = 0; s < seg; ++s) {
      const auto a = static_cast<std::uint32_t>(r * cols + s);
      const auto b = a + 1, c = a + static_cast<std::uint32_t>(cols), d = c + 1;
      prim.indices.insert(prim.indices.end(), {a, b, c, b, d, c});
    }
  }
  // Caps: latitude rings shrinking to a pole; they reuse the end ring's positions.
  const int lat = 6;
  for (int end = 0; end < 2; ++end) {
    const double y0 = end == 0 ? 0.0 : kLength, dir = end == 0 ? -1.0 : 1.0;
    const auto ring0 = static_cast<std::uint32_t>(end == 0 ? 0 : (rings - 1) * cols);
    std::uint32_t prev = ring0;
    for (int i = 1; i <= lat; ++i) {
      const double phi = 0.5 * kPi * i / lat;
      const auto first = static_cast<std::uint32_t>(prim.positions.size());
      if (i == lat) {
        AddVertex(&prim, glm::dvec3(0.0, y0 + dir * cap, 0.0), glm::vec2(0.5f, end ? 1.0f : 0.0f));
        for (int s = 0; s < seg; ++s) {
          const std::uint32_t a = prev + static_cast<std::uint32_t>(s), b = a + 1;
          if (end == 0) {
            prim.indices.insert(prim.indices.end(), {b, a, first});
          } else {
            prim.indices.insert(prim.indices.end(), {a, b, first});
          }
        }
        break;
      }
      for (int s = 0; s <= seg; ++s) {
        const double a = 2.0 * kPi * s / seg;
        const double rad = Radius(y0, a) * std::cos(phi);
        AddVertex(&prim,
                  glm::dvec3(rad * std::cos(a), y0 + dir * cap * std::sin(phi), -rad * std::sin(a)),
                  glm::vec2(static_cast<float>(s) / static_cast<float>(seg), end ? 1.0f : 0.0f));
      }
      for (int s = 0; s < seg; ++s) {
        const std::uint32_t a = prev + static_cast<std::uint32_t>(s), b = a + 1;
        const std::uint32_t c = first + static_cast<std::uint32_t>(s), d = c + 1;
        if (end == 0) {
          prim.indices.insert(prim.indices.end(), {b, a, c, b, c, d});
        } else {
          prim.indices.insert(prim.indices.end(), {a, b, c, c, b, d});
        }
      }
      prev = first;
    }
  }
  return prim;
}

// Rotation keys (x, y, z, w) of `q(t)` at `times`.
dermis::AssetAnimationSampler RotationSampler(const std::vector<float>& times,
                                              glm::dquat (*q)(double)) {
  dermis::AssetAnimationSampler s;
  s.times = times;
  s.components = 4;
  for (float t : times) {
    const glm::dquat r = q(t);
    s.values.insert(s.values.end(), {static_cast<float>(r.x), static_cast<float>(r.y),
                                     static_cast<float>(r.z), static_cast<float>(r.w)});
  }
  return s;
}

// Bend of joint 1 about z: 0 -> 90 degrees at t = 1 s -> 0 at 2 s.
glm::dquat Bend(double t) {
  const double angle = 0.5 * kPi * std::sin(0.5 * kPi * t) * (t <= 2.0 ? 1.0 : 0.0);
  return glm::angleAxis(angle, glm::dvec3(0.0, 0.0, 1.0));
}

// Twist of joint 2 about its bone (y): 0 -> 120 degrees at t = 1.5 s -> 0 at 2 s.
glm::dquat Twist(double t) {
  const double u = t <= 1.5 ? t / 1.5 : (2.0 - t) / 0.5;
  const double angle = (2.0 * kPi / 3.0) * Smoothstep(0.0, 1.0, u);
  return glm::angleAxis(angle, glm::dvec3(0.0, 1.0, 0.0));
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  bool small = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--small")) {
      small = true;
    } else if (argv[i][0] != '-' && out.empty()) {
      out = argv[i];
    } else {
      std::fprintf(stderr, "usage: sample_make_creature OUT.glb [--small]\n");
      return 2;
    }
  }
  if (out.empty()) {
    std::fprintf(stderr, "usage: sample_make_creature OUT.glb [--small]\n");
    return 2;
  }
  dermis::Asset a;
  a.source = "demo_creature";
  dermis::AssetMesh mesh;
  mesh.name = "limb";
  mesh.primitives.push_back(small ? Limb(48, 49) : Limb(120, 121));
  mesh.primitives[0].material = 0;
  a.meshes.push_back(mesh);
  dermis::AssetMaterial skin_material;
  skin_material.name = "skin";
  skin_material.json =
      R"({"pbrMetallicRoughness":{"baseColorFactor":[0.86,0.66,0.56,1.0],"metallicFactor":0.0,)"
      R"("roughnessFactor":0.6}})";
  a.materials.push_back(skin_material);
  // Nodes: 0 root, 1 j0 (y = 0), 2 j1 (y = kJoint1), 3 j2 (y = kJoint2), 4 the skinned limb.
  dermis::AssetNode root, j0, j1, j2, limb;
  root.name = "creature";
  root.children = {1, 4};
  j0.name = "shoulder";
  j0.parent = 0;
  j0.children = {2};
  j1.name = "elbow";
  j1.parent = 1;
  j1.children = {3};
  j1.translation = glm::dvec3(0.0, kJoint1, 0.0);
  j2.name = "wrist";
  j2.parent = 2;
  j2.translation = glm::dvec3(0.0, kJoint2 - kJoint1, 0.0);
  limb.name = "limb";
  limb.parent = 0;
  limb.mesh = 0;
  limb.skin = 0;
  a.nodes = {root, j0, j1, j2, limb};
  dermis::AssetSkin skin;
  skin.name = "limb_skin";
  skin.joints = {1, 2, 3};
  skin.skeleton = 1;
  for (double y : {0.0, kJoint1, kJoint2}) {
    glm::mat4 ibm(1.0f);
    ibm[3] = glm::vec4(0.0f, static_cast<float>(-y), 0.0f, 1.0f);
    skin.inverse_bind_matrices.push_back(ibm);
  }
  a.skins.push_back(skin);
  dermis::AssetAnimation clip;
  clip.name = "bend_and_twist";
  std::vector<float> times;
  for (int k = 0; k <= 16; ++k) times.push_back(0.125f * static_cast<float>(k));
  clip.samplers.push_back(RotationSampler(times, Bend));
  clip.samplers.push_back(RotationSampler(times, Twist));
  clip.channels.push_back({0, 2, dermis::AnimationPath::kRotation});
  clip.channels.push_back({1, 3, dermis::AnimationPath::kRotation});
  a.animations.push_back(clip);
  dermis::AssetScene scene;
  scene.name = "demo";
  scene.nodes = {0};
  a.scenes.push_back(scene);
  a.default_scene = 0;

  dermis::GltfExportOptions options;
  options.generator = "Dermis demo creature";
  const dermis::Status s = dermis::ExportGltf(a, options, out);
  if (!s.ok()) {
    std::fprintf(stderr, "sample_make_creature: %s\n", s.message().c_str());
    return 1;
  }
  std::printf("wrote %s: %zu vertices, %zu triangles, 3 joints, clip 'bend_and_twist' (2 s)\n",
              out.c_str(), a.meshes[0].primitives[0].positions.size(),
              a.meshes[0].primitives[0].indices.size() / 3);
  return 0;
}
