// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Tests of the neutral asset module: validation, pose sampling / skinning, binary round trip.
#include "dermis/asset/asset.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "dermis/asset/asset_io.h"
#include "dermis/asset/asset_pose.h"
#include "dermis/asset/asset_validate.h"

namespace dermis {
namespace {

constexpr double kPi = 3.14159265358979323846;

glm::mat4 Translation(float x, float y, float z) {
  glm::mat4 m(1.0f);
  m[3] = glm::vec4(x, y, z, 1.0f);
  return m;
}

glm::dquat AxisAngleZ(double angle) {
  return glm::dquat(std::cos(angle / 2), 0.0, 0.0, std::sin(angle / 2));
}

/// A small asset using every field: a 2-joint skin, a skinned mesh with 2 primitives and a morph
/// target, an instanced textured mesh, and an animation with T/R/S/weights channels in LINEAR,
/// STEP and CUBICSPLINE.
Asset RichAsset() {
  Asset a;
  a.source = "rich.glb";
  a.generator = "dermis test";
  a.copyright = "(c) nobody";

  a.nodes.resize(5);
  a.nodes[0].name = "root";
  a.nodes[0].children = {1, 3};
  a.nodes[0].translation = glm::dvec3(1.0, 0.0, 0.0);
  a.nodes[1].name = "joint0";
  a.nodes[1].parent = 0;
  a.nodes[1].children = {2};
  a.nodes[1].rotation = AxisAngleZ(kPi / 2);
  a.nodes[2].name = "joint1";
  a.nodes[2].parent = 1;
  a.nodes[2].translation = glm::dvec3(0.0, 2.0, 0.0);
  a.nodes[3].name = "skinned";
  a.nodes[3].parent = 0;
  a.nodes[3].mesh = 0;
  a.nodes[3].skin = 0;
  a.nodes[3].weights = {0.25};
  a.nodes[4].name = "instance";
  a.nodes[4].mesh = 1;
  a.nodes[4].has_matrix = true;
  a.nodes[4].matrix = glm::dmat4(2.0);
  a.nodes[4].matrix[3] = glm::dvec4(0.0, 0.0, 5.0, 1.0);
  a.nodes[4].translation = glm::dvec3(0.1, 0.2, 0.3);  // Unused but kept losslessly.

  a.meshes.resize(2);
  a.meshes[0].name = "body";
  a.meshes[0].weights = {0.5f};
  a.meshes[0].primitives.resize(2);
  {
    AssetPrimitive& p = a.meshes[0].primitives[0];
    p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    p.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    p.joints = {{{0, 1, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}}};
    p.weights = {{{0.25f, 0.75f, 0, 0}, {0.5f, 0.5f, 0, 0}, {1, 0, 0, 0}}};
    p.indices = {0, 1, 2};
    p.targets.resize(1);
    p.targets[0].positions = {{0, 0, 1}, {0, 0, 2}, {0, 0, 3}};
    p.targets[0].normals = {{0, 0.1f, 0}, {0, 0, 0}, {0, 0, 0}};
    p.material = 0;
  }
  {
    AssetPrimitive& p = a.meshes[0].primitives[1];
    p.mode = PrimitiveMode::kTriangleStrip;
    p.positions = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    p.joints = {std::vector<glm::u16vec4>(4, glm::u16vec4(1, 0, 0, 0))};
    p.weights = {std::vector<glm::vec4>(4, glm::vec4(1, 0, 0, 0))};
    p.targets.resize(1);
    p.targets[0].positions = {{1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  }
  a.meshes[1].name = "prop";
  a.meshes[1].primitives.resize(1);
  {
    AssetPrimitive& p = a.meshes[1].primitives[0];
    p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    p.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
    p.tangents = {{1, 0, 0, 1}, {1, 0, 0, 1}, {1, 0, 0, -1}};
    p.texcoords = {{{0, 0}, {1, 0}, {0, 1}}, {{0.5f, 0.5f}, {0.25f, 0}, {0, 0.125f}}};
    p.colors = {{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 0.5f}}};
    p.indices = {0, 2, 1};
    p.material = 0;
  }

  a.materials.push_back({"skin", R"({"name":"skin","pbrMetallicRoughness":{}})"});
  a.textures.push_back({"tex", 0, 0});
  a.images.push_back({"img", "image/png", std::string("\x89PNG\0\x01\xff", 7)});
  a.samplers.push_back({"smp", 9729, 9987, 33071, 10497});

  a.skins.resize(1);
  a.skins[0].name = "skin";
  a.skins[0].joints = {1, 2};
  a.skins[0].inverse_bind_matrices = {glm::mat4(1.0f), Translation(0, -2, 0)};
  a.skins[0].skeleton = 0;

  const float s45 = static_cast<float>(std::sin(kPi / 4));
  a.animations.resize(1);
  AssetAnimation& anim = a.animations[0];
  anim.name = "walk";
  anim.samplers.resize(5);
  anim.samplers[0] = {{0, 1}, {0, 0, 0, 4, 8, -4}, 3, Interpolation::kLinear};
  // Second key stored as -q (q = 90 degrees about Z): slerp must take the short arc.
  anim.samplers[1] = {{0, 1}, {0, 0, 0, 1, 0, 0, -s45, -s45}, 4, Interpolation::kLinear};
  anim.samplers[2] = {{0, 1, 2}, {1, 1, 1, 2, 2, 2, 3, 3, 3}, 3, Interpolation::kStep};
  // Per key: in-tangent, value, out-tangent.
  anim.samplers[3] = {
      {0, 2}, {0.3f, 0.0f, 1.5f, -0.7f, 1.0f, 0.2f}, 1, Interpolation::kCubicSpline};
  anim.samplers[4] = {{0, 1},
                      {0, 0, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0, 3, 0, 0, 0, 0},
                      3,
                      Interpolation::kCubicSpline};
  anim.channels = {{0, 0, AnimationPath::kTranslation},
                   {1, 1, AnimationPath::kRotation},
                   {2, 2, AnimationPath::kScale},
                   {3, 3, AnimationPath::kWeights},
                   {4, 2, AnimationPath::kTranslation}};

  a.scenes.push_back({"main", {0, 4}});
  a.default_scene = 0;
  return a;
}

// ---------------------------------------------------------------------------------------------
// Validation.

TEST_CASE("ValidateAsset accepts the rich asset and an empty one", "[asset][validate]") {
  const Status status = ValidateAsset(RichAsset());
  INFO(status.message());
  CHECK(status.ok());
  CHECK(ValidateAsset(Asset{}).ok());
}

struct Mutation {
  const char* rule;
  std::function<void(Asset*)> apply;
  const char* pointer;  ///< Expected JSON pointer (followed by ": ").
  const char* what;     ///< Expected words of the message.
};

TEST_CASE("ValidateAsset rejects each broken rule with a pointer to it", "[asset][validate]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Mutation> mutations = {
      {"cycle",
       [](Asset* a) {
         a->nodes[0].children = {3};
         a->nodes[1].parent = 2;
         a->nodes[2].children = {1};
       },
       "/nodes/1", "cycle"},
      {"two parents", [](Asset* a) { a->nodes[4].children = {2}; }, "/nodes/4/children/0",
       "node 2 has two parents (1 and 4)"},
      {"own child", [](Asset* a) { a->nodes[4].children = {4}; }, "/nodes/4/children/0",
       "own child"},
      {"parent disagrees", [](Asset* a) { a->nodes[2].parent = 0; }, "/nodes/2/parent",
       "disagrees"},
      {"child out of range", [](Asset* a) { a->nodes[2].children = {5}; }, "/nodes/2/children/0",
       "out of range"},
      {"joint index >= joint count",
       [](Asset* a) { a->meshes[0].primitives[1].joints[0][2] = glm::u16vec4(0, 2, 0, 0); },
       "/meshes/0/primitives/1/joints/0/2", "joint index 2 >= joint count 2 of skin 0"},
      {"NaN in node matrix", [nan](Asset* a) { a->nodes[4].matrix[2][1] = nan; }, "/nodes/4/matrix",
       "not finite"},
      {"NaN in inverse bind matrix",
       [nan](Asset* a) { a->skins[0].inverse_bind_matrices[1][0][0] = nan; },
       "/skins/0/inverse_bind_matrices/1", "not finite"},
      {"IBM last row", [](Asset* a) { a->skins[0].inverse_bind_matrices[1][0][3] = 0.5f; },
       "/skins/0/inverse_bind_matrices/1", "last row"},
      {"IBM last row [3][3]", [](Asset* a) { a->skins[0].inverse_bind_matrices[0][3][3] = 2.0f; },
       "/skins/0/inverse_bind_matrices/0", "last row"},
      {"equal keyframe times",
       [](Asset* a) {
         a->animations[0].samplers[2].times = {0, 1, 1};
       },
       "/animations/0/samplers/2/times/2", "strictly increasing"},
      {"decreasing keyframe times",
       [](Asset* a) {
         a->animations[0].samplers[0].times = {1, 0};
       },
       "/animations/0/samplers/0/times/1", "strictly increasing"},
      {"NaN keyframe time", [nan](Asset* a) { a->animations[0].samplers[3].times[1] = nan; },
       "/animations/0/samplers/3/times/1", "not finite"},
      {"no keyframes",
       [](Asset* a) {
         a->animations[0].samplers[0].times.clear();
         a->animations[0].samplers[0].values.clear();
       },
       "/animations/0/samplers/0/times", "no keyframes"},
      {"wrong value count", [](Asset* a) { a->animations[0].samplers[0].values.pop_back(); },
       "/animations/0/samplers/0/values", "expected 2 keyframes"},
      {"cubic value count without tangents",
       [](Asset* a) {
         a->animations[0].samplers[3].values = {0.0f, 1.0f};
       },
       "/animations/0/samplers/3/values", "expected 2 keyframes * 3"},
      {"rotation channel with 3 components",
       [](Asset* a) { a->animations[0].channels[1].sampler = 0; },
       "/animations/0/channels/1/sampler", "needs 4"},
      {"weights channel with the wrong target count",
       [](Asset* a) { a->animations[0].channels[3].sampler = 0; },
       "/animations/0/channels/3/sampler", "needs 1"},
      {"channel node out of range", [](Asset* a) { a->animations[0].channels[2].node = 9; },
       "/animations/0/channels/2/node", "out of range"},
      {"bad material index", [](Asset* a) { a->meshes[1].primitives[0].material = 1; },
       "/meshes/1/primitives/0/material", "out of range"},
      {"bad texture image", [](Asset* a) { a->textures[0].image = 3; }, "/textures/0/image",
       "out of range"},
      {"index >= vertex count", [](Asset* a) { a->meshes[1].primitives[0].indices[1] = 3; },
       "/meshes/1/primitives/0/indices/1", "index 3 >= vertex count 3"},
      {"triangles not a multiple of 3",
       [](Asset* a) {
         a->meshes[1].primitives[0].indices = {0, 1, 2, 0};
       },
       "/meshes/1/primitives/0/indices", "do not fit mode triangles"},
      {"non-indexed lines of odd count",
       [](Asset* a) {
         a->meshes[1].primitives[0].mode = PrimitiveMode::kLines;
         a->meshes[1].primitives[0].indices.clear();
       },
       "/meshes/1/primitives/0/positions", "3 vertices do not fit mode lines"},
      {"strip of 2",
       [](Asset* a) {
         a->meshes[1].primitives[0].mode = PrimitiveMode::kTriangleStrip;
         a->meshes[1].primitives[0].indices = {0, 1};
       },
       "/meshes/1/primitives/0/indices", "2 indices do not fit mode triangle strip"},
      {"normal count", [](Asset* a) { a->meshes[1].primitives[0].normals.pop_back(); },
       "/meshes/1/primitives/0/normals", "expected 3"},
      {"NaN position", [nan](Asset* a) { a->meshes[0].primitives[1].positions[3].y = nan; },
       "/meshes/0/primitives/1/positions/3", "not finite"},
      {"negative weight",
       [](Asset* a) { a->meshes[0].primitives[0].weights[0][1] = glm::vec4(0, -0.5f, 0, 0); },
       "/meshes/0/primitives/0/weights/0/1/1", "negative"},
      {"NaN weight", [nan](Asset* a) { a->meshes[0].primitives[0].weights[0][2].x = nan; },
       "/meshes/0/primitives/0/weights/0/2", "not finite"},
      {"zero rotation", [](Asset* a) { a->nodes[1].rotation = glm::dquat(0, 0, 0, 0); },
       "/nodes/1/rotation", "zero"},
      {"morph target count differs", [](Asset* a) { a->meshes[0].primitives[1].targets.clear(); },
       "/meshes/0/primitives/1/targets", "morph targets"},
      {"node weights count",
       [](Asset* a) {
         a->nodes[3].weights = {1, 2};
       },
       "/nodes/3/weights", "2 weights"},
      {"scene root with a parent", [](Asset* a) { a->scenes[0].nodes = {2}; }, "/scenes/0/nodes/0",
       "not a root"},
      {"default scene", [](Asset* a) { a->default_scene = 1; }, "/default_scene", "out of range"},
  };
  for (const Mutation& m : mutations) {
    Asset asset = RichAsset();
    m.apply(&asset);
    const Status status = ValidateAsset(asset);
    INFO(m.rule << ": " << status.message());
    CHECK(status.code() == StatusCode::kInvalidInput);
    CHECK_THAT(status.message(), Catch::StartsWith("rich.glb: " + std::string(m.pointer) + ": "));
    CHECK_THAT(status.message(), Catch::Contains(m.what));
  }
}

TEST_CASE("ValidateAsset walks a deep chain without recursion", "[asset][validate]") {
  Asset a;
  a.source = "chain.glb";
  const int n = 100000;
  a.nodes.resize(n);
  for (int i = 0; i + 1 < n; ++i) {
    a.nodes[i].children = {i + 1};
    a.nodes[i + 1].parent = i;
  }
  CHECK(ValidateAsset(a).ok());
  std::vector<glm::dmat4> world;
  AssetPose pose;
  a.nodes[0].translation = glm::dvec3(0.5, 0, 0);
  RestPose(a, &pose);
  ComputeWorldMatrices(a, pose, &world);
  CHECK(world[n - 1][3].x == 0.5);
  // Close the chain into a loop through the root: every node now lies on a cycle.
  a.nodes[n - 1].children = {0};
  a.nodes[0].parent = n - 1;
  const Status status = ValidateAsset(a);
  CHECK_THAT(status.message(), Catch::Contains("chain.glb: /nodes/0: node is part of a cycle"));
}

// ---------------------------------------------------------------------------------------------
// Pose.

void CheckVec(const glm::dvec3& got, const glm::dvec3& want, double eps = 1e-6) {
  INFO("got (" << got.x << ", " << got.y << ", " << got.z << ") want (" << want.x << ", " << want.y
               << ", " << want.z << ")");
  CHECK(std::fabs(got.x - want.x) <= eps);
  CHECK(std::fabs(got.y - want.y) <= eps);
  CHECK(std::fabs(got.z - want.z) <= eps);
}

void CheckQuat(const glm::dquat& got, const glm::dquat& want, double eps = 1e-6) {
  INFO("got (w " << got.w << ", " << got.x << ", " << got.y << ", " << got.z << ") want (w "
                 << want.w << ", " << want.x << ", " << want.y << ", " << want.z << ")");
  CHECK(std::fabs(got.w - want.w) <= eps);
  CHECK(std::fabs(got.x - want.x) <= eps);
  CHECK(std::fabs(got.y - want.y) <= eps);
  CHECK(std::fabs(got.z - want.z) <= eps);
}

TEST_CASE("SamplePose LINEAR translation and short-arc slerp", "[asset][pose]") {
  const Asset a = RichAsset();
  AssetPose pose;
  SamplePose(a, 0, 0.25, &pose);
  CheckVec(pose.local[0].translation, {1.0, 2.0, -1.0});  // 0.25 * (4, 8, -4).
  // Keys: identity and -(90 degrees about Z); the short arc passes through 22.5 degrees.
  CheckQuat(pose.local[1].rotation, AxisAngleZ(kPi / 8));
  SamplePose(a, 0, 0.5, &pose);
  CheckQuat(pose.local[1].rotation,
            glm::dquat(std::cos(kPi / 8), 0.0, 0.0, std::sin(kPi / 8)));  // 45 degrees.
  // Untouched nodes keep their rest transform; the rest pose keeps node weights.
  CheckVec(pose.local[3].translation, {0, 0, 0});
  CHECK(pose.local[4].has_matrix);
  CHECK(pose.local[4].matrix[3][2] == 5.0);
}

TEST_CASE("SamplePose near-parallel slerp stays unit and exact", "[asset][pose]") {
  Asset a;
  a.nodes.resize(1);
  AssetAnimation anim;
  const float e = 1e-6f;  // Tiny rotation about X; the dot product rounds to 1.
  anim.samplers.push_back(
      {{0, 1}, {0, 0, 0, 1, e, 0, 0, std::sqrt(1 - e * e)}, 4, Interpolation::kLinear});
  anim.channels.push_back({0, 0, AnimationPath::kRotation});
  a.animations.push_back(anim);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  SamplePose(a, 0, 0.5, &pose);
  const glm::dquat q = pose.local[0].rotation;
  CHECK(std::isfinite(q.w));
  CHECK(std::fabs(q.x - 0.5 * e) < 1e-9);
  CHECK(std::fabs(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z - 1.0) < 1e-12);
}

TEST_CASE("SamplePose STEP holds each key until the next and clamps", "[asset][pose]") {
  const Asset a = RichAsset();
  AssetPose pose;
  const std::vector<std::pair<double, double>> expected = {
      {-1.0, 1.0}, {0.0, 1.0}, {0.99, 1.0}, {1.0, 2.0}, {1.5, 2.0}, {2.0, 3.0}, {7.0, 3.0}};
  for (const auto& [t, scale] : expected) {
    INFO("t = " << t);
    SamplePose(a, 0, t, &pose);
    CheckVec(pose.local[2].scale, glm::dvec3(scale));
  }
}

/// The cubic Hermite segment written as a Bezier curve and evaluated by de Casteljau, an
/// evaluation independent of the Hermite basis used by the library.
double BezierFromHermite(double p0, double m0, double p1, double m1, double s) {
  double c[4] = {p0, p0 + m0 / 3.0, p1 - m1 / 3.0, p1};
  for (int level = 3; level > 0; --level) {
    for (int i = 0; i < level; ++i) c[i] = (1.0 - s) * c[i] + s * c[i + 1];
  }
  return c[0];
}

TEST_CASE("SamplePose CUBICSPLINE follows the glTF Hermite formula", "[asset][pose]") {
  const Asset a = RichAsset();
  AssetPose pose;
  // Weights sampler: keys at t = 0 and 2: (in 0.3, value 0, out 1.5), (in -0.7, value 1, out 0.2).
  // Tangents are scaled by the key spacing dt = 2.
  for (double t : {0.5, 1.0, 1.7}) {
    INFO("t = " << t);
    SamplePose(a, 0, t, &pose);
    REQUIRE(pose.morph_weights[3].size() == 1);
    const double want = BezierFromHermite(0.0, 2.0 * 1.5, 1.0, 2.0 * -0.7, t / 2.0);
    CHECK(std::fabs(pose.morph_weights[3][0] - want) < 1e-6);
  }
  // t = 1: s = 1/2 gives 0.5 v0 + 0.125 dt b0 + 0.5 v1 - 0.125 dt a1 by hand.
  SamplePose(a, 0, 1.0, &pose);
  CHECK(std::fabs(pose.morph_weights[3][0] - (0.5 + 0.125 * 2 * 1.5 + 0.125 * 2 * 0.7)) < 1e-6);
  // Clamping returns the key values, never the tangents.
  SamplePose(a, 0, -3.0, &pose);
  CHECK(pose.morph_weights[3][0] == 0.0);
  SamplePose(a, 0, 9.0, &pose);
  CHECK(pose.morph_weights[3][0] == 1.0);
  // Translation of node 2 (3 components, dt = 1): y from 2 to 3, zero y tangents; x leaves with
  // out-tangent 1, z arrives with in-tangent 1.
  SamplePose(a, 0, 0.25, &pose);
  CheckVec(pose.local[2].translation,
           {BezierFromHermite(0, 1, 0, 0, 0.25), BezierFromHermite(2, 0, 3, 0, 0.25),
            BezierFromHermite(0, 0, 0, 1, 0.25)});
  SamplePose(a, 0, -1.0, &pose);
  CheckVec(pose.local[2].translation, {0, 2, 0});
  SamplePose(a, 0, 1.0, &pose);
  CheckVec(pose.local[2].translation, {0, 3, 0});
}

TEST_CASE("SamplePose CUBICSPLINE rotation is renormalised", "[asset][pose]") {
  Asset a;
  a.nodes.resize(1);
  AssetAnimation anim;
  const float s45 = static_cast<float>(std::sin(kPi / 4));
  // Identity to 90 degrees about Z with zero tangents: at s = 1/2 the Hermite value is the
  // average of the keys, whose normalisation is the 45 degree rotation.
  anim.samplers.push_back(
      {{1, 3},
       {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, s45, s45, 0, 0, 0, 0},
       4,
       Interpolation::kCubicSpline});
  anim.channels.push_back({0, 0, AnimationPath::kRotation});
  a.animations.push_back(anim);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  SamplePose(a, 0, 2.0, &pose);
  CheckQuat(pose.local[0].rotation, AxisAngleZ(kPi / 4));
  SamplePose(a, 0, 0.0, &pose);
  CheckQuat(pose.local[0].rotation, AxisAngleZ(0.0));
  SamplePose(a, 0, 4.0, &pose);
  CheckQuat(pose.local[0].rotation, AxisAngleZ(kPi / 2));
}

TEST_CASE("NodeTransform::Matrix is T * R * S", "[asset][pose]") {
  NodeTransform t;
  t.translation = glm::dvec3(1, 2, 3);
  t.rotation = AxisAngleZ(kPi / 2);
  t.scale = glm::dvec3(2, 3, 4);
  const glm::dmat4 m = t.Matrix();
  // S then R (x -> y, y -> -x) then T, applied to the unit axes.
  CheckVec(glm::dvec3(m * glm::dvec4(1, 0, 0, 1)), {1, 4, 3});
  CheckVec(glm::dvec3(m * glm::dvec4(0, 1, 0, 1)), {-2, 2, 3});
  CheckVec(glm::dvec3(m * glm::dvec4(0, 0, 1, 1)), {1, 2, 7});
  CHECK(m[0][3] == 0.0);
  CHECK(m[3][3] == 1.0);
  t.has_matrix = true;
  t.matrix = glm::dmat4(7.0);
  CHECK(t.Matrix() == glm::dmat4(7.0));
}

TEST_CASE("ComputeWorldMatrices handles parents listed after children", "[asset][pose]") {
  Asset a;
  a.nodes.resize(3);
  a.nodes[2].children = {0};  // Root last.
  a.nodes[2].translation = glm::dvec3(1, 2, 3);
  a.nodes[2].scale = glm::dvec3(2.0);
  a.nodes[0].parent = 2;
  a.nodes[0].children = {1};
  a.nodes[0].translation = glm::dvec3(1, 0, 0);
  a.nodes[0].rotation = AxisAngleZ(kPi / 2);
  a.nodes[1].parent = 0;
  a.nodes[1].translation = glm::dvec3(0, 1, 0);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  RestPose(a, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  REQUIRE(world.size() == 3);
  // world[0] = T(1,2,3) S(2) T(1,0,0) Rz(90), written out by hand (columns).
  const glm::dmat4 want0(0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 3, 2, 3, 1);
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) CHECK(std::fabs(world[0][c][r] - want0[c][r]) < 1e-12);
  }
  CheckVec(glm::dvec3(world[1] * glm::dvec4(0, 0, 0, 1)), {1, 2, 3});
  CheckVec(glm::dvec3(world[1] * glm::dvec4(1, 0, 0, 1)), {1, 4, 3});
  CheckVec(glm::dvec3(world[2] * glm::dvec4(1, 1, 1, 1)), {3, 4, 5});
}

/// Two joints (nodes 0 and 1), a skinned node 2 far away (its transform must be ignored), and
/// a mesh of three vertices with weights spread over two JOINTS/WEIGHTS sets.
Asset SkinnedAsset() {
  Asset a;
  a.source = "skin.glb";
  a.nodes.resize(3);
  a.nodes[0].translation = glm::dvec3(1, 0, 0);
  a.nodes[1].rotation = AxisAngleZ(kPi / 2);
  a.nodes[2].translation = glm::dvec3(100, 0, 0);
  a.nodes[2].mesh = 0;
  a.nodes[2].skin = 0;
  a.skins.resize(1);
  a.skins[0].joints = {0, 1};
  a.skins[0].inverse_bind_matrices = {glm::mat4(1.0f), Translation(0, -1, 0)};
  a.meshes.resize(1);
  AssetPrimitive p;
  p.mode = PrimitiveMode::kPoints;
  p.positions = {{1, 2, 3}, {1, 2, 3}, {0, 0, 0}};
  p.normals = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  // Vertex 0: 0.25 on joint 0 and 0.75 on joint 1 in set 0. Vertex 1: the same weights split
  // over sets 0 and 1. Vertex 2: all weights zero.
  p.joints = {{{0, 1, 0, 0}, {0, 0, 0, 0}, {0, 1, 0, 0}},
              {{0, 0, 0, 0}, {1, 0, 0, 0}, {1, 1, 1, 1}}};
  p.weights = {{{0.25f, 0.75f, 0, 0}, {0.25f, 0, 0, 0}, {0, 0, 0, 0}},
               {{0, 0, 0, 0}, {0.75f, 0, 0, 0}, {0, 0, 0, 0}}};
  a.meshes[0].primitives.push_back(p);
  return a;
}

TEST_CASE("PosePrimitive blends joint matrices (linear blend skinning)", "[asset][pose]") {
  const Asset a = SkinnedAsset();
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  RestPose(a, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  std::vector<glm::dmat4> joints;
  ComputeJointMatrices(a.skins[0], world, &joints);
  REQUIRE(joints.size() == 2);
  // J0 = T(1,0,0); J1 = Rz(90) T(0,-1,0). By hand: J0 (1,2,3) = (2,2,3); J1 (1,2,3) =
  // Rz(90) (1,1,3) = (-1,1,3).
  CheckVec(glm::dvec3(joints[0] * glm::dvec4(1, 2, 3, 1)), {2, 2, 3});
  CheckVec(glm::dvec3(joints[1] * glm::dvec4(1, 2, 3, 1)), {-1, 1, 3});
  std::vector<glm::dvec3> positions, normals;
  PosePrimitive(a, pose, world, 2, a.meshes[0].primitives[0], &positions, &normals);
  REQUIRE(positions.size() == 3);
  REQUIRE(normals.size() == 3);
  // 0.25 (2,2,3) + 0.75 (-1,1,3).
  CheckVec(positions[0], {-0.25, 1.25, 3.0});
  CheckVec(positions[1], {-0.25, 1.25, 3.0});
  // Zero weights: the vertex follows the node's own world matrix.
  CheckVec(positions[2], {100, 0, 0});
  CheckVec(normals[2], {0, 1, 0});
  // The blended 3x3 is 0.25 I + 0.75 Rz(90), a scaled rotation: its inverse transpose turns
  // normals like the matrix itself, so n' = M n / |M n| = (0.25, 0.75, 0) / |.|.
  const double len = std::sqrt(0.25 * 0.25 + 0.75 * 0.75);
  CheckVec(normals[0], {0.25 / len, 0.75 / len, 0});
  CheckVec(normals[1], {0.25 / len, 0.75 / len, 0});

  // Rotate joint 0 by 180 degrees about Z in a pose: J0 (1,2,3) = Rz(180) (1,2,3) + (1,0,0).
  pose.local[0].rotation = AxisAngleZ(kPi);
  ComputeWorldMatrices(a, pose, &world);
  PosePrimitive(a, pose, world, 2, a.meshes[0].primitives[0], &positions, nullptr);
  CheckVec(positions[0], glm::dvec3(0.25 * 0.0 + 0.75 * -1, 0.25 * -2 + 0.75 * 1, 3.0));
}

TEST_CASE("PosePrimitive draws an instanced mesh at each node", "[asset][pose]") {
  Asset a;
  a.nodes.resize(2);
  a.nodes[0].translation = glm::dvec3(1, 0, 0);
  a.nodes[0].children = {1};
  a.nodes[0].mesh = 0;
  a.nodes[1].parent = 0;
  a.nodes[1].scale = glm::dvec3(2, 1, 1);
  a.nodes[1].mesh = 0;
  a.meshes.resize(1);
  AssetPrimitive p;
  p.positions = {{0, 0, 0}, {1, 1, 0}, {0, 1, 1}};
  const float r = static_cast<float>(std::sqrt(0.5));
  p.normals = {{r, r, 0}, {0, 0, 1}, {1, 0, 0}};
  a.meshes[0].primitives.push_back(p);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  RestPose(a, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  std::vector<glm::dvec3> positions, normals;
  PosePrimitive(a, pose, world, 0, a.meshes[0].primitives[0], &positions, &normals);
  CheckVec(positions[1], {2, 1, 0});
  CheckVec(normals[0], {r, r, 0});
  PosePrimitive(a, pose, world, 1, a.meshes[0].primitives[0], &positions, &normals);
  CheckVec(positions[0], {1, 0, 0});
  CheckVec(positions[1], {3, 1, 0});
  CheckVec(positions[2], {1, 1, 1});
  // Inverse transpose of diag(2,1,1) is diag(0.5,1,1): (r, r, 0) -> (0.5, 1, 0) normalised
  // (the plain matrix would give (2, 1, 0)).
  CheckVec(normals[0], glm::dvec3(0.5, 1, 0) / std::sqrt(1.25));
  CheckVec(normals[1], {0, 0, 1});
}

TEST_CASE("PosePrimitive keeps normals outward under a mirroring matrix", "[asset][pose]") {
  Asset a;
  a.nodes.resize(1);
  a.nodes[0].scale = glm::dvec3(-1, 2, 1);  // det < 0.
  a.nodes[0].mesh = 0;
  a.meshes.resize(1);
  AssetPrimitive p;
  p.mode = PrimitiveMode::kPoints;
  p.positions = {{1, 1, 1}};
  p.normals = {{1, 0, 0}};
  a.meshes[0].primitives.push_back(p);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  RestPose(a, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  std::vector<glm::dvec3> positions, normals;
  PosePrimitive(a, pose, world, 0, a.meshes[0].primitives[0], &positions, &normals);
  CheckVec(positions[0], {-1, 2, 1});
  // Inverse transpose of diag(-1, 2, 1) is diag(-1, 0.5, 1).
  CheckVec(normals[0], {-1, 0, 0});
}

TEST_CASE("PosePrimitive applies morph targets before the transform", "[asset][pose]") {
  Asset a;
  a.nodes.resize(2);
  a.nodes[0].translation = glm::dvec3(0, 0, 10);
  a.nodes[0].mesh = 0;
  a.nodes[1].mesh = 0;
  a.nodes[1].weights = {1.0, 0.5};
  a.meshes.resize(1);
  a.meshes[0].weights = {0.5f, 0.0f};
  AssetPrimitive p;
  p.mode = PrimitiveMode::kPoints;
  p.positions = {{1, 0, 0}, {0, 1, 0}};
  p.normals = {{0, 0, 1}, {0, 0, 1}};
  p.targets.resize(2);
  p.targets[0].positions = {{2, 0, 0}, {0, 0, 0}};
  p.targets[0].normals = {{1, 0, -1}, {0, 0, 0}};
  p.targets[1].positions = {{0, 4, 0}, {0, 0, 8}};
  a.meshes[0].primitives.push_back(p);
  REQUIRE(ValidateAsset(a).ok());
  AssetPose pose;
  RestPose(a, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  std::vector<glm::dvec3> positions, normals;
  // Node 0: mesh defaults (0.5, 0), then T(0,0,10).
  PosePrimitive(a, pose, world, 0, a.meshes[0].primitives[0], &positions, &normals);
  CheckVec(positions[0], {2, 0, 10});
  CheckVec(positions[1], {0, 1, 10});
  CheckVec(normals[0], glm::dvec3(0.5, 0, 0.5) / std::sqrt(0.5));
  // Node 1: its own weights (1, 0.5).
  PosePrimitive(a, pose, world, 1, a.meshes[0].primitives[0], &positions, &normals);
  CheckVec(positions[0], {3, 2, 0});
  CheckVec(positions[1], {0, 1, 4});
  CheckVec(normals[0], glm::dvec3(1, 0, 0));
  // Pose weights override both.
  pose.morph_weights[0] = {0.0, 0.25};
  PosePrimitive(a, pose, world, 0, a.meshes[0].primitives[0], &positions, nullptr);
  CheckVec(positions[0], {1, 1, 10});
  CheckVec(positions[1], {0, 1, 12});
}

TEST_CASE("The rich asset skins and morphs in an animated pose", "[asset][pose]") {
  const Asset a = RichAsset();
  AssetPose pose;
  SamplePose(a, 0, 0.0, &pose);  // T(0) = 0, R = identity, S = 1, weights cubic = 0.
  CHECK(pose.morph_weights[3] == std::vector<double>{0.0});
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(a, pose, &world);
  // Joint 1 world = T(0,2,0) (node 2 cubic translation at t=0), IBM1 = T(0,-2,0): identity.
  // Joint 0 world = identity. So every vertex stays at its bind position (weight 0 morph).
  std::vector<glm::dvec3> positions;
  PosePrimitive(a, pose, world, 3, a.meshes[0].primitives[1], &positions, nullptr);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    CheckVec(positions[v], glm::dvec3(a.meshes[0].primitives[1].positions[v]));
  }
  // t = 2: morph weight 1 moves vertex 0 to (1,0,1). Joint 1 = T(4,8,-4) Rz(90) T(0,3,0) S(3)
  // IBM T(0,-2,0), by hand: (1,-2,1) -> (3,-6,3) -> (3,-3,3) -> (3,3,3) -> (7,11,-1).
  SamplePose(a, 0, 2.0, &pose);
  ComputeWorldMatrices(a, pose, &world);
  PosePrimitive(a, pose, world, 3, a.meshes[0].primitives[1], &positions, nullptr);
  CheckVec(positions[0], {7, 11, -1});
}

// ---------------------------------------------------------------------------------------------
// Serialisation.

/// Collects the first difference between two assets; floats compare bit for bit.
class Diff {
 public:
  std::string first;

  void Fail(const std::string& where) {
    if (first.empty()) first = where;
  }
  void Bits(const std::string& where, float x, float y) {
    if (std::memcmp(&x, &y, sizeof x) != 0) Fail(where);
  }
  void Bits(const std::string& where, double x, double y) {
    if (std::memcmp(&x, &y, sizeof x) != 0) Fail(where);
  }
  template <typename T>
  void Same(const std::string& where, const T& x, const T& y) {
    if (!(x == y)) Fail(where);
  }
  template <int N, typename T, glm::qualifier Q>
  void Bits(const std::string& where, const glm::vec<N, T, Q>& x, const glm::vec<N, T, Q>& y) {
    for (int i = 0; i < N; ++i) Bits(where + "." + std::to_string(i), x[i], y[i]);
  }
  template <typename T>
  void BitsArray(const std::string& where, const std::vector<T>& x, const std::vector<T>& y) {
    if (x.size() != y.size()) return Fail(where + " size");
    for (std::size_t i = 0; i < x.size(); ++i)
      Bits(where + "[" + std::to_string(i) + "]", x[i], y[i]);
  }
  template <typename T>
  void BitsSets(const std::string& where, const std::vector<std::vector<T>>& x,
                const std::vector<std::vector<T>>& y) {
    if (x.size() != y.size()) return Fail(where + " size");
    for (std::size_t i = 0; i < x.size(); ++i) {
      BitsArray(where + "[" + std::to_string(i) + "]", x[i], y[i]);
    }
  }
};

void Compare(Diff& d, const Asset& x, const Asset& y) {
  d.Same("source", x.source, y.source);
  d.Same("generator", x.generator, y.generator);
  d.Same("copyright", x.copyright, y.copyright);
  d.Same("default_scene", x.default_scene, y.default_scene);
  d.Same("meshes size", x.meshes.size(), y.meshes.size());
  for (std::size_t m = 0; m < x.meshes.size() && m < y.meshes.size(); ++m) {
    const std::string mw = "meshes[" + std::to_string(m) + "]";
    d.Same(mw + ".name", x.meshes[m].name, y.meshes[m].name);
    d.BitsArray(mw + ".weights", x.meshes[m].weights, y.meshes[m].weights);
    d.Same(mw + ".primitives size", x.meshes[m].primitives.size(), y.meshes[m].primitives.size());
    for (std::size_t p = 0; p < x.meshes[m].primitives.size() && p < y.meshes[m].primitives.size();
         ++p) {
      const AssetPrimitive& a = x.meshes[m].primitives[p];
      const AssetPrimitive& b = y.meshes[m].primitives[p];
      const std::string w = mw + ".primitives[" + std::to_string(p) + "]";
      d.Same(w + ".mode", a.mode, b.mode);
      d.Same(w + ".material", a.material, b.material);
      d.BitsArray(w + ".positions", a.positions, b.positions);
      d.BitsArray(w + ".normals", a.normals, b.normals);
      d.BitsArray(w + ".tangents", a.tangents, b.tangents);
      d.BitsSets(w + ".texcoords", a.texcoords, b.texcoords);
      d.BitsSets(w + ".colors", a.colors, b.colors);
      d.Same(w + ".joints", a.joints, b.joints);
      d.BitsSets(w + ".weights", a.weights, b.weights);
      d.Same(w + ".indices", a.indices, b.indices);
      d.Same(w + ".targets size", a.targets.size(), b.targets.size());
      for (std::size_t t = 0; t < a.targets.size() && t < b.targets.size(); ++t) {
        const std::string tw = w + ".targets[" + std::to_string(t) + "]";
        d.BitsArray(tw + ".positions", a.targets[t].positions, b.targets[t].positions);
        d.BitsArray(tw + ".normals", a.targets[t].normals, b.targets[t].normals);
        d.BitsArray(tw + ".tangents", a.targets[t].tangents, b.targets[t].tangents);
      }
    }
  }
  d.Same("materials size", x.materials.size(), y.materials.size());
  for (std::size_t i = 0; i < x.materials.size() && i < y.materials.size(); ++i) {
    d.Same("material name", x.materials[i].name, y.materials[i].name);
    d.Same("material json", x.materials[i].json, y.materials[i].json);
  }
  d.Same("textures size", x.textures.size(), y.textures.size());
  for (std::size_t i = 0; i < x.textures.size() && i < y.textures.size(); ++i) {
    d.Same("texture name", x.textures[i].name, y.textures[i].name);
    d.Same("texture image", x.textures[i].image, y.textures[i].image);
    d.Same("texture sampler", x.textures[i].sampler, y.textures[i].sampler);
  }
  d.Same("images size", x.images.size(), y.images.size());
  for (std::size_t i = 0; i < x.images.size() && i < y.images.size(); ++i) {
    d.Same("image name", x.images[i].name, y.images[i].name);
    d.Same("image mime", x.images[i].mime_type, y.images[i].mime_type);
    d.Same("image bytes", x.images[i].bytes, y.images[i].bytes);
  }
  d.Same("samplers size", x.samplers.size(), y.samplers.size());
  for (std::size_t i = 0; i < x.samplers.size() && i < y.samplers.size(); ++i) {
    const AssetSampler &a = x.samplers[i], &b = y.samplers[i];
    d.Same("sampler name", a.name, b.name);
    d.Same("sampler mag", a.mag_filter, b.mag_filter);
    d.Same("sampler min", a.min_filter, b.min_filter);
    d.Same("sampler wrap_s", a.wrap_s, b.wrap_s);
    d.Same("sampler wrap_t", a.wrap_t, b.wrap_t);
  }
  d.Same("nodes size", x.nodes.size(), y.nodes.size());
  for (std::size_t i = 0; i < x.nodes.size() && i < y.nodes.size(); ++i) {
    const AssetNode &a = x.nodes[i], &b = y.nodes[i];
    const std::string w = "nodes[" + std::to_string(i) + "]";
    d.Same(w + ".name", a.name, b.name);
    d.Same(w + ".parent", a.parent, b.parent);
    d.Same(w + ".children", a.children, b.children);
    d.Bits(w + ".translation", a.translation, b.translation);
    d.Bits(w + ".rotation.w", a.rotation.w, b.rotation.w);
    d.Bits(w + ".rotation.x", a.rotation.x, b.rotation.x);
    d.Bits(w + ".rotation.y", a.rotation.y, b.rotation.y);
    d.Bits(w + ".rotation.z", a.rotation.z, b.rotation.z);
    d.Bits(w + ".scale", a.scale, b.scale);
    d.Same(w + ".has_matrix", a.has_matrix, b.has_matrix);
    for (int c = 0; c < 4; ++c) d.Bits(w + ".matrix", a.matrix[c], b.matrix[c]);
    d.Same(w + ".mesh", a.mesh, b.mesh);
    d.Same(w + ".skin", a.skin, b.skin);
    d.BitsArray(w + ".weights", a.weights, b.weights);
  }
  d.Same("skins size", x.skins.size(), y.skins.size());
  for (std::size_t i = 0; i < x.skins.size() && i < y.skins.size(); ++i) {
    const AssetSkin &a = x.skins[i], &b = y.skins[i];
    d.Same("skin name", a.name, b.name);
    d.Same("skin joints", a.joints, b.joints);
    d.Same("skin ibm size", a.inverse_bind_matrices.size(), b.inverse_bind_matrices.size());
    for (std::size_t j = 0;
         j < a.inverse_bind_matrices.size() && j < b.inverse_bind_matrices.size(); ++j) {
      for (int c = 0; c < 4; ++c) {
        d.Bits("skin ibm", a.inverse_bind_matrices[j][c], b.inverse_bind_matrices[j][c]);
      }
    }
    d.Same("skin has_ibm", a.has_inverse_bind_matrices, b.has_inverse_bind_matrices);
    d.Same("skin skeleton", a.skeleton, b.skeleton);
  }
  d.Same("animations size", x.animations.size(), y.animations.size());
  for (std::size_t i = 0; i < x.animations.size() && i < y.animations.size(); ++i) {
    const AssetAnimation &a = x.animations[i], &b = y.animations[i];
    d.Same("animation name", a.name, b.name);
    d.Same("animation samplers size", a.samplers.size(), b.samplers.size());
    for (std::size_t k = 0; k < a.samplers.size() && k < b.samplers.size(); ++k) {
      const std::string w = "animation sampler " + std::to_string(k);
      d.BitsArray(w + " times", a.samplers[k].times, b.samplers[k].times);
      d.BitsArray(w + " values", a.samplers[k].values, b.samplers[k].values);
      d.Same(w + " components", a.samplers[k].components, b.samplers[k].components);
      d.Same(w + " interpolation", a.samplers[k].interpolation, b.samplers[k].interpolation);
    }
    d.Same("animation channels size", a.channels.size(), b.channels.size());
    for (std::size_t k = 0; k < a.channels.size() && k < b.channels.size(); ++k) {
      d.Same("channel sampler", a.channels[k].sampler, b.channels[k].sampler);
      d.Same("channel node", a.channels[k].node, b.channels[k].node);
      d.Same("channel path", a.channels[k].path, b.channels[k].path);
    }
  }
  d.Same("scenes size", x.scenes.size(), y.scenes.size());
  for (std::size_t i = 0; i < x.scenes.size() && i < y.scenes.size(); ++i) {
    d.Same("scene name", x.scenes[i].name, y.scenes[i].name);
    d.Same("scene nodes", x.scenes[i].nodes, y.scenes[i].nodes);
  }
}

TEST_CASE("The equality helper sees single-field changes", "[asset][io]") {
  const Asset a = RichAsset();
  Asset b = a;
  Diff same;
  Compare(same, a, b);
  CHECK(same.first.empty());
  b.nodes[4].matrix[1][2] = -0.0;  // 0.0 == -0.0 numerically, but not bit for bit.
  Diff diff;
  Compare(diff, a, b);
  CHECK(diff.first == "nodes[4].matrix.2");
}

TEST_CASE("SerializeAsset / ParseAsset round trip is lossless and deterministic", "[asset][io]") {
  Asset a = RichAsset();
  a.source = "x.dsurf";
  a.meshes[0].primitives[0].positions[1].y = -0.0f;  // Signed zero survives.
  a.skins.push_back({"no ibm", {0}, {}, false, kInvalidIndex});
  const std::string bytes = SerializeAsset(a);
  REQUIRE(bytes.compare(0, 8, std::string("DASSET\0\0", 8)) == 0);
  CHECK(std::uint32_t(static_cast<unsigned char>(bytes[8])) == kAssetStreamVersion);
  Asset b;
  const Status status = ParseAsset(bytes, "x.dsurf", &b);
  INFO(status.message());
  REQUIRE(status.ok());
  CHECK(b.source == "x.dsurf");
  Diff diff;
  Compare(diff, a, b);
  INFO("first difference: " << diff.first);
  CHECK(diff.first.empty());
  CHECK(SerializeAsset(b) == bytes);
  CHECK(SerializeAsset(a) == bytes);  // Same asset, same bytes.
  // The source is not part of the stream.
  b.source = "other";
  CHECK(SerializeAsset(b) == bytes);
}

TEST_CASE("ParseAsset fails cleanly on every truncation", "[asset][io]") {
  const std::string bytes = SerializeAsset(RichAsset());
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    Asset out;
    out.generator = "untouched";
    const Status status = ParseAsset(std::string_view(bytes.data(), n), "t.dsurf", &out);
    if (status.ok() || status.message().rfind("t.dsurf: asset stream: ", 0) != 0 ||
        out.generator != "untouched") {
      FAIL("prefix " << n << ": " << status.message());
    }
  }
  Asset out;
  CHECK(ParseAsset(bytes, "t.dsurf", &out).ok());
  // A trailing byte is an error too.
  const Status status = ParseAsset(bytes + std::string(1, '\0'), "t.dsurf", &out);
  CHECK_THAT(status.message(), Catch::Contains("trailing"));
}

TEST_CASE("ParseAsset survives any single corrupted byte", "[asset][io]") {
  const std::string good = SerializeAsset(RichAsset());
  int rejected = 0;
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (unsigned mask : {0x01u, 0x80u, 0xFFu}) {
      std::string bytes = good;
      bytes[i] = static_cast<char>((static_cast<unsigned char>(bytes[i]) ^ mask) & 0xFFu);
      Asset out;
      const Status status = ParseAsset(bytes, "f.dsurf", &out);
      if (status.ok()) {
        // Whatever was accepted is a valid asset that serialises back to the same bytes.
        CHECK(SerializeAsset(out) == bytes);
      } else {
        ++rejected;
        CHECK(status.message().rfind("f.dsurf: ", 0) == 0);
      }
    }
  }
  CHECK(rejected > 0);
}

void PutU64(std::string* bytes, std::size_t offset, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) (*bytes)[offset + i] = static_cast<char>((v >> (8 * i)) & 0xFF);
}

TEST_CASE("ParseAsset rejects huge counts before allocating", "[asset][io]") {
  Asset a = RichAsset();
  a.generator = "g";
  a.copyright = "";
  a.meshes[0].name = "ab";
  const std::string good = SerializeAsset(a);
  // Header: magic 8, version 4, generator 8 + 1, copyright 8 + 0, default scene 4.
  const std::size_t meshes_count = 8 + 4 + 9 + 8 + 4;
  // meshes count 8, mesh name 8 + 2, primitives count 8, mode 1, material 4.
  const std::size_t positions_count = meshes_count + 8 + 10 + 8 + 1 + 4;
  const std::size_t mode = positions_count - 5;
  struct Case {
    std::size_t offset;
    const char* message;
  };
  for (const Case& c : {Case{meshes_count, "x.dsurf: asset stream: meshes: count exceeds data"},
                        Case{positions_count,
                             "x.dsurf: asset stream: meshes[0].primitives[0].positions: count "
                             "exceeds data"}}) {
    std::string bytes = good;
    PutU64(&bytes, c.offset, std::uint64_t(1) << 60);
    Asset out;
    // Allocating 2^60 elements would throw (or abort under ASan) instead of returning.
    const Status status = ParseAsset(bytes, "x.dsurf", &out);
    CHECK(status.code() == StatusCode::kInvalidInput);
    CHECK(status.message() == c.message);
  }
  // An enum byte out of range.
  std::string bytes = good;
  bytes[mode] = 9;
  Asset out;
  CHECK(ParseAsset(bytes, "x.dsurf", &out).message() ==
        "x.dsurf: asset stream: meshes[0].primitives[0].mode: value 9 out of range");
  // Bad magic and version.
  bytes = good;
  bytes[0] = 'X';
  CHECK_THAT(ParseAsset(bytes, "x.dsurf", &out).message(), Catch::Contains("bad magic"));
  bytes = good;
  bytes[8] = 2;
  CHECK(ParseAsset(bytes, "x.dsurf", &out).code() == StatusCode::kUnsupported);
}

TEST_CASE("ParseAsset validates what it reads", "[asset][io]") {
  Asset a = RichAsset();
  a.meshes[1].primitives[0].material = 4;
  Asset out;
  const Status status = ParseAsset(SerializeAsset(a), "bad.dsurf", &out);
  CHECK(status.message() ==
        "bad.dsurf: /meshes/1/primitives/0/material: material index 4 out of range (count 1)");
}

}  // namespace
}  // namespace dermis
