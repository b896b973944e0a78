// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Posing fitted characters (CharacterPoser): the rig from a skin, the bind pose against the bound
// export, rigid motions of the whole skeleton, a bend of the two-cylinder character, clips
// played through steps, and the morph-target bake replayed by our own glTF-style posing.
#include "dermis/offline/character/character_pose.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

#include "dermis/asset/asset_pose.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/offline/character/character_fit.h"
#include "test_meshes.h"

namespace dermis {
namespace {

/// Builds a poser (REQUIREs success; always true).
bool BuildPoser(const Character& ch, const CharacterPoseOptions& options, CharacterPoser* out) {
  const Status s = CharacterPoser::Build(ch, options, out);
  INFO(s.message());
  REQUIRE(s.ok());
  return true;
}

std::vector<PosedPrimitive> Pose(CharacterPoser* poser, const AssetPose& pose) {
  std::vector<PosedPrimitive> out;
  Status s = poser->SetPose(pose);
  INFO(s.message());
  REQUIRE(s.ok());
  s = poser->Evaluate(&out);
  INFO(s.message());
  REQUIRE(s.ok());
  return out;
}

std::vector<PosedPrimitive> Rest(CharacterPoser* poser) {
  AssetPose pose;
  RestPose(poser->asset(), &pose);
  poser->ResetHistory();
  return Pose(poser, pose);
}

/// The joint that alone moves every control vertex the surface over `face` depends on (the
/// face's corners and their one-rings: the local patches' support), or -1.
int RigidJoint(const CharacterPart& part, Index face) {
  const MeshTopology& topo = part.surface.domain->topology();
  int joint = -1;
  for (int c = 0; c < topo.face_size(face); ++c) {
    const Index corner = topo.face_vertex(face, c);
    for (int i = 0; i < topo.valence(corner); ++i) {
      const Index f = topo.ring(corner, i).face;
      for (int k = 0; k < topo.face_size(f); ++k) {
        const auto v = static_cast<std::size_t>(topo.face_vertex(f, k));
        if (part.control_weights[v].x != 1.0f) return -1;
        const int j = part.control_joints[v].x;
        if (joint >= 0 && j != joint) return -1;
        joint = j;
      }
    }
  }
  return joint;
}

constexpr DeformerKind kAllDeformers[] = {DeformerKind::kLbs, DeformerKind::kDqs,
                                          DeformerKind::kSweep};

/// The asset with a clip that bends j1 by 90 degrees about z over one second.
Asset BendingCylinders() {
  Asset a = test::TwoCylinders();
  AssetAnimation clip;
  clip.name = "bend";
  AssetAnimationSampler sampler;
  sampler.times = {0.0f, 1.0f};
  const glm::dquat q = glm::angleAxis(0.5 * M_PI, glm::dvec3(0, 0, 1));
  sampler.values = {0,
                    0,
                    0,
                    1,
                    static_cast<float>(q.x),
                    static_cast<float>(q.y),
                    static_cast<float>(q.z),
                    static_cast<float>(q.w)};
  sampler.components = 4;
  clip.samplers.push_back(sampler);
  clip.channels.push_back({0, 2, AnimationPath::kRotation});
  a.animations.push_back(clip);
  return a;
}

}  // namespace

TEST_CASE("character pose: the rig of a skin") {
  Asset a = test::TwoCylinders();
  SkinRig rig;
  REQUIRE(MakeSkinRig(a, 0, &rig).ok());
  CHECK(rig.parents == std::vector<Index>{-1, 0});
  CHECK(rig.names == std::vector<std::string>{"j0", "j1"});
  CHECK(rig.bind[0] == glm::dmat4(1.0));
  CHECK(rig.bind[1][3] == glm::dvec4(0, 1, 0, 1));
  // A node between two joints that is not a joint: the parent is the nearest joint above.
  AssetNode mid;
  mid.name = "mid";
  mid.parent = 1;
  mid.children = {2};
  a.nodes.push_back(mid);
  a.nodes[1].children = {4};
  a.nodes[2].parent = 4;
  REQUIRE(ValidateAsset(a).ok());
  REQUIRE(MakeSkinRig(a, 0, &rig).ok());
  CHECK(rig.parents == std::vector<Index>{-1, 0});
  // The bind matrices come from the inverse bind matrices, not from the nodes.
  a.nodes[2].translation = glm::dvec3(5, 5, 5);
  REQUIRE(MakeSkinRig(a, 0, &rig).ok());
  CHECK(rig.bind[1][3] == glm::dvec4(0, 1, 0, 1));
  const Status s = MakeSkinRig(a, 3, &rig);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("two_cylinders") != std::string::npos);
}

TEST_CASE("character pose: clip step times") {
  const std::vector<double> t = ClipStepTimes(0.5, 30.0);
  REQUIRE(t.size() == 16);
  CHECK(t.front() == 0.0);
  CHECK(t[1] == 1.0 / 30.0);
  CHECK(t[14] == 14.0 / 30.0);
  CHECK(t.back() == 0.5);
  CHECK(ClipStepTimes(0.0, 30.0) == std::vector<double>{0.0});
  // A time just past a step replaces it; one a third of a step past keeps it.
  CHECK(ClipStepTimes(0.5 + 1e-9, 30.0).size() == 16);
  CHECK(ClipStepTimes(0.5 + 0.01, 30.0).size() == 17);
  // Every step is distinct in float32 (glTF keyframe times).
  const std::vector<double> long_clip = ClipStepTimes(100.0 + 1e-6, 30.0);
  for (std::size_t k = 1; k < long_clip.size(); ++k) {
    CHECK(static_cast<float>(long_clip[k - 1]) < static_cast<float>(long_clip[k]));
  }
}

TEST_CASE("character pose: the bind pose reproduces the bound export") {
  const Character& ch = test::FittedCylinders();
  Asset bound;
  REQUIRE(BuildBoundAsset(ch, CharacterExportOptions{}, &bound).ok());
  for (const DeformerKind kind : kAllDeformers) {
    INFO(DeformerName(kind));
    CharacterPoseOptions options;
    options.deformer = kind;
    CharacterPoser poser;
    if (!BuildPoser(ch, options, &poser)) continue;
    // The rest pose of this rig is its bind pose: every skin matrix is the identity.
    const std::vector<PosedPrimitive> posed = Rest(&poser);
    REQUIRE(poser.drawn().size() == 2);
    for (std::size_t d = 0; d < 2; ++d) {
      const DrawnPrimitive& dp = poser.drawn()[d];
      CHECK(dp.node == 3);
      CHECK(dp.primitive == static_cast<Index>(d));
      const AssetPrimitive& b = bound.meshes[0].primitives[d];
      REQUIRE(posed[d].positions.size() == b.positions.size());
      // The lone triangle has no normals in the source: the poser makes them from its triangle.
      REQUIRE(posed[d].normals.size() == b.positions.size());
      REQUIRE(b.normals.size() == (d == 0 ? b.positions.size() : 0));
      double worst = 0.0, worst_normal = 0.0;
      for (std::size_t v = 0; v < b.positions.size(); ++v) {
        worst = std::max(worst, glm::length(posed[d].positions[v] - Vec3(b.positions[v])));
        const Vec3 n = d == 0 ? Vec3(b.normals[v]) : Vec3(0, 0, 1);
        worst_normal = std::max(worst_normal, glm::length(posed[d].normals[v] - n));
      }
      // The export is float32 of the same evaluation (positions up to 3.5 from the origin).
      CHECK(worst < 5e-7);
      CHECK(worst_normal < 1e-6);
    }
  }
}

TEST_CASE("character pose: a rigid motion of the skeleton moves the surface rigidly") {
  const Character& ch = test::FittedCylinders();
  // A static version: the same mesh without skin, drawn by a node under the moving root.
  Asset static_asset = test::TwoCylinders();
  static_asset.nodes[3].skin = kInvalidIndex;
  static_asset.nodes[3].translation = glm::dvec3(0.5, 0.0, -1.0);
  for (AssetPrimitive& p : static_asset.meshes[0].primitives) p.joints.clear(), p.weights.clear();
  Character static_ch;
  REQUIRE(FitCharacter(static_asset, CharacterFitOptions{}, &static_ch, nullptr).ok());
  REQUIRE(static_ch.parts.size() == 2);
  CHECK(static_ch.parts[0].skin == kInvalidIndex);

  const glm::dquat r = glm::angleAxis(0.7, glm::normalize(glm::dvec3(1, 2, 3)));
  const glm::dvec3 t(0.3, -2.0, 5.0);
  glm::dmat4 g = glm::mat4_cast(r);
  g[3] = glm::dvec4(t, 1.0);
  const Character* const characters[] = {&ch, &static_ch};
  for (const Character* c : characters) {
    for (const CharacterPoseMode mode : {CharacterPoseMode::kBound, CharacterPoseMode::kLod}) {
      for (const DeformerKind kind : kAllDeformers) {
        INFO(DeformerName(kind) << (mode == CharacterPoseMode::kLod ? " lod" : " bound")
                                << (c == &ch ? " skinned" : " static"));
        CharacterPoseOptions options;
        options.deformer = kind;
        options.mode = mode;
        options.level = 3;
        CharacterPoser poser;
        if (!BuildPoser(*c, options, &poser)) continue;
        const std::vector<PosedPrimitive> rest = Rest(&poser);
        AssetPose pose;
        RestPose(poser.asset(), &pose);
        pose.local[0].rotation = r;
        pose.local[0].translation = t;
        const std::vector<PosedPrimitive> moved = Pose(&poser, pose);
        REQUIRE(moved.size() == rest.size());
        double worst = 0.0, worst_normal = 0.0;
        for (std::size_t d = 0; d < moved.size(); ++d) {
          REQUIRE(moved[d].positions.size() == rest[d].positions.size());
          REQUIRE(moved[d].normals.size() == rest[d].normals.size());
          for (std::size_t v = 0; v < moved[d].positions.size(); ++v) {
            const Vec3 expect = Vec3(g * glm::dvec4(rest[d].positions[v], 1.0));
            worst = std::max(worst, glm::length(moved[d].positions[v] - expect));
            worst_normal =
                std::max(worst_normal, glm::length(moved[d].normals[v] - r * rest[d].normals[v]));
          }
        }
        // Relative to the character's size (about 11 across).
        CHECK(worst < 1e-9 * 11.0);
        CHECK(worst_normal < 1e-9);
      }
    }
  }
}

TEST_CASE("character pose: the two cylinders bent at the joint") {
  const Character& ch = test::FittedCylinders();
  const Asset source = test::TwoCylinders();
  const glm::dquat q = glm::angleAxis(0.5 * M_PI, glm::dvec3(0, 0, 1));
  // Skin matrix of j1: T(0, 1, 0) R T(0, -1, 0).
  glm::dmat4 m1 = glm::mat4_cast(q);
  m1[3] = glm::dvec4(glm::dvec3(0, 1, 0) - q * glm::dvec3(0, 1, 0), 1.0);
  double thickness[3] = {0.0, 0.0, 0.0};
  for (const DeformerKind kind : kAllDeformers) {
    INFO(DeformerName(kind));
    CharacterPoseOptions options;
    options.deformer = kind;
    CharacterPoser poser;
    if (!BuildPoser(ch, options, &poser)) continue;
    const std::vector<PosedPrimitive> rest = Rest(&poser);
    AssetPose pose;
    RestPose(poser.asset(), &pose);
    pose.local[2].rotation = q;
    const std::vector<PosedPrimitive> bent = Pose(&poser, pose);
    // The dense mesh skinned by LBS, for comparison.
    std::vector<glm::dmat4> world;
    ComputeWorldMatrices(source, pose, &world);
    std::vector<glm::dvec3> lbs;
    PosePrimitive(source, pose, world, 3, source.meshes[0].primitives[0], &lbs, nullptr);
    const AssetPrimitive& prim = source.meshes[0].primitives[0];
    double rigid_worst = 0.0, lbs_worst = 0.0;
    std::size_t rigid[2] = {0, 0};
    Vec3 inner(0.0), outer(0.0);
    for (std::size_t v = 0; v < prim.positions.size(); ++v) {
      const Vec3 x0 = rest[0].positions[v], x = bent[0].positions[v];
      REQUIRE(std::isfinite(x.x + x.y + x.z));
      CHECK(glm::length(bent[0].normals[v]) == Approx(1.0).margin(1e-9));
      // Where every control vertex the surface depends on follows one joint alone, the surface
      // moves rigidly with it (the bottom stays, the top turns); where the dense mesh's LBS is
      // rigid too, the two stay as far apart as at rest (the vertex's E1).
      const VertexBinding& b = ch.bindings[0][0][v];
      const CharacterPart& part = ch.parts[static_cast<std::size_t>(b.part)];
      const int joint = RigidJoint(part, b.face);
      if (joint >= 0) {
        const Vec3 expect = joint == 0 ? x0 : Vec3(m1 * glm::dvec4(x0, 1.0));
        rigid_worst = std::max(rigid_worst, glm::length(x - expect));
        if (prim.weights[0][v][joint] == 1.0f) {  // rigid in the dense mesh too
          const double e1 = glm::length(x0 - Vec3(prim.positions[v]));
          lbs_worst = std::max(lbs_worst, std::abs(glm::length(x - lbs[v]) - e1));
        }
        ++rigid[joint];
      }
      // The ring at the joint (y = 1) of the first cylinder, both sides in the bend's plane.
      const float y = prim.positions[v].y;
      if (y == 1.0f && prim.positions[v].x > 0.49f && prim.positions[v].x < 0.51f) inner = x;
      if (y == 1.0f && prim.positions[v].x < -0.49f && prim.positions[v].x > -0.51f) outer = x;
    }
    INFO("rigid vertices " << rigid[0] << " + " << rigid[1] << " of " << prim.positions.size());
    CHECK(rigid[0] > 20);
    CHECK(rigid[1] > 20);
    if (kind != DeformerKind::kSweep) {
      CHECK(rigid_worst < 1e-9);
      CHECK(lbs_worst < 1e-9);
    } else {
      // The sweep moves rigidly only outside its blend and volume zones (deformer_test.cpp);
      // on these short capsules (bones of 1, radius 0.5) the leaf j1's virtual bone gives the
      // joint an arc and a volume bump that span them whole: near-rigid, not rigid.
      CHECK(rigid_worst < 0.02);
    }
    // Joint-ring thickness in the bend's plane: LBS collapses it by cos 45 degrees.
    const double thick = glm::length(inner - outer);
    thickness[static_cast<int>(kind)] = thick;
    INFO("thickness " << thick);
    CHECK(thick > 0.6);
  }
  // LBS: 0.707 of the unit diameter where the weights are 1/2; the control mesh spreads the
  // blend over its coarse faces, so less here.
  CHECK(thickness[0] < 0.9);
  CHECK(thickness[1] > thickness[0]);
  if (thickness[2] > 0.0) CHECK(thickness[2] > thickness[0]);
}

TEST_CASE("character pose: a clip is played through its steps") {
  const Asset asset = BendingCylinders();
  Character ch;
  REQUIRE(FitCharacter(asset, CharacterFitOptions{}, &ch, nullptr).ok());
  for (const DeformerKind kind : kAllDeformers) {
    INFO(DeformerName(kind));
    CharacterPoseOptions options;
    options.deformer = kind;
    CharacterPoser poser;
    if (!BuildPoser(ch, options, &poser)) continue;
    std::vector<PosedPrimitive> stepped;
    REQUIRE(poser.PoseClip(0, 0.5, 30.0, &stepped).ok());
    // The same steps by hand.
    poser.ResetHistory();
    AssetPose pose;
    for (const double t : ClipStepTimes(0.5, 30.0)) {
      SamplePose(poser.asset(), 0, t, &pose);
      REQUIRE(poser.SetPose(pose).ok());
    }
    std::vector<PosedPrimitive> by_hand;
    REQUIRE(poser.Evaluate(&by_hand).ok());
    REQUIRE(by_hand.size() == stepped.size());
    for (std::size_t d = 0; d < by_hand.size(); ++d)
      CHECK(by_hand[d].positions == stepped[d].positions);
    if (kind != DeformerKind::kSweep) {
      // LBS and DQS keep no history: one jump gives the same.
      poser.ResetHistory();
      SamplePose(poser.asset(), 0, 0.5, &pose);
      const std::vector<PosedPrimitive> jump = Pose(&poser, pose);
      for (std::size_t d = 0; d < jump.size(); ++d)
        CHECK(jump[d].positions == stepped[d].positions);
    }
    // Past the end: the last keyframe.
    std::vector<PosedPrimitive> end, past;
    REQUIRE(poser.PoseClip(0, 1.0, 30.0, &end).ok());
    REQUIRE(poser.PoseClip(0, 7.0, 30.0, &past).ok());
    for (std::size_t d = 0; d < end.size(); ++d) {
      for (std::size_t v = 0; v < end[d].positions.size(); ++v) {
        CHECK(glm::length(end[d].positions[v] - past[d].positions[v]) < 1e-9);
      }
    }
    // Bad requests name the asset.
    std::vector<PosedPrimitive> out;
    Status s = poser.PoseClip(1, 0.0, 30.0, &out);
    CHECK_FALSE(s.ok());
    CHECK(s.message().find("two_cylinders") != std::string::npos);
    CHECK_FALSE(poser.PoseClip(0, -1.0, 30.0, &out).ok());
    CHECK_FALSE(poser.PoseClip(0, 0.5, 0.0, &out).ok());
  }
  // Evaluate() needs a pose first.
  CharacterPoser fresh;
  CharacterPoseOptions options;
  options.deformer = DeformerKind::kLbs;
  REQUIRE(CharacterPoser::Build(ch, options, &fresh).ok());
  std::vector<PosedPrimitive> out;
  CHECK_FALSE(fresh.Evaluate(&out).ok());
}

TEST_CASE("character pose: the bake replays the poses as morph targets") {
  const Asset asset = BendingCylinders();
  Character ch;
  REQUIRE(FitCharacter(asset, CharacterFitOptions{}, &ch, nullptr).ok());
  for (const CharacterPoseMode mode : {CharacterPoseMode::kBound, CharacterPoseMode::kLod}) {
    for (const DeformerKind kind : kAllDeformers) {
      INFO(DeformerName(kind) << (mode == CharacterPoseMode::kLod ? " lod" : " bound"));
      CharacterPoseOptions options;
      options.deformer = kind;
      options.mode = mode;
      options.level = 2;
      CharacterPoser poser;
      if (!BuildPoser(ch, options, &poser)) continue;
      Asset baked;
      CharacterBakeReport report;
      const double fps = 10.0;
      Status s = BuildBakedAsset(&poser, fps, &baked, &report);
      INFO(s.message());
      REQUIRE(s.ok());
      s = ValidateAsset(baked);
      INFO(s.message());
      REQUIRE(s.ok());
      const std::vector<double> frames = ClipStepTimes(1.0, fps);
      CHECK(frames.size() == 11);
      CHECK(report.frames == std::vector<std::size_t>{11});
      CHECK(report.targets == 11);
      CHECK(baked.skins.empty());
      REQUIRE(baked.nodes.size() == 1);  // one drawing node
      CHECK(baked.nodes[0].skin == kInvalidIndex);
      CHECK(baked.nodes[0].translation == glm::dvec3(0.0));
      REQUIRE(baked.meshes.size() == 1);
      REQUIRE(baked.meshes[0].primitives.size() == poser.drawn().size());
      std::size_t vertices = 0;
      for (const AssetPrimitive& p : baked.meshes[0].primitives) {
        CHECK(p.targets.size() == 11);
        CHECK(p.joints.empty());
        vertices += p.positions.size();
      }
      CHECK(report.vertices == vertices);
      CHECK(report.vertex_frames == vertices * 11);
      REQUIRE(baked.animations.size() == 1);
      CHECK(baked.animations[0].name == "bend");
      REQUIRE(baked.animations[0].channels.size() == 1);
      CHECK(baked.animations[0].channels[0].path == AnimationPath::kWeights);
      // Posing the baked asset as a glTF viewer does gives the poser's pose at every frame (and
      // the rest pose without animation), to float32 rounding.
      for (int k = -1; k < static_cast<int>(frames.size()); ++k) {
        const double t = k < 0 ? 0.0 : frames[static_cast<std::size_t>(k)];
        INFO("frame " << k << " t = " << t);
        std::vector<PosedPrimitive> expect;
        REQUIRE(poser.PoseClip(k < 0 ? -1 : 0, t, fps, &expect).ok());
        AssetPose pose;
        if (k < 0) {
          RestPose(baked, &pose);
        } else {
          SamplePose(baked, 0, t, &pose);
        }
        std::vector<glm::dmat4> world;
        ComputeWorldMatrices(baked, pose, &world);
        double worst = 0.0, worst_normal = 0.0;
        for (std::size_t p = 0; p < baked.meshes[0].primitives.size(); ++p) {
          std::vector<glm::dvec3> x, n;
          PosePrimitive(baked, pose, world, 0, baked.meshes[0].primitives[p], &x, &n);
          REQUIRE(x.size() == expect[p].positions.size());
          REQUIRE(n.size() == expect[p].normals.size());
          for (std::size_t v = 0; v < x.size(); ++v) {
            worst = std::max(worst, glm::length(x[v] - expect[p].positions[v]));
            worst_normal = std::max(worst_normal, glm::length(n[v] - expect[p].normals[v]));
          }
        }
        CHECK(worst < 2e-6);
        CHECK(worst_normal < 1e-5);
      }
    }
  }
  // Nothing to bake without clips.
  CharacterPoser poser;
  CharacterPoseOptions options;
  options.deformer = DeformerKind::kLbs;
  REQUIRE(CharacterPoser::Build(test::FittedCylinders(), options, &poser).ok());
  Asset baked;
  const Status s = BuildBakedAsset(&poser, 30.0, &baked, nullptr);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("no clips") != std::string::npos);
}

TEST_CASE("character pose: the static asset of a pose") {
  const Character& ch = test::FittedCylinders();
  CharacterPoseOptions options;
  options.deformer = DeformerKind::kDqs;
  CharacterPoser poser;
  REQUIRE(CharacterPoser::Build(ch, options, &poser).ok());
  const std::vector<PosedPrimitive> rest = Rest(&poser);
  Asset posed;
  REQUIRE(BuildPosedAsset(poser, rest, &posed).ok());
  REQUIRE(ValidateAsset(posed).ok());
  CHECK(posed.skins.empty());
  CHECK(posed.animations.empty());
  REQUIRE(posed.nodes.size() == 1);
  CHECK(posed.nodes[0].name == "body");
  REQUIRE(posed.scenes.size() == 1);
  CHECK(posed.scenes[0].nodes == std::vector<Index>{0});
  const AssetPrimitive& p = posed.meshes[0].primitives[0];
  CHECK(p.texcoords == ch.asset.meshes[0].primitives[0].texcoords);
  CHECK(p.indices == ch.asset.meshes[0].primitives[0].indices);
  CHECK(p.joints.empty());
  CHECK(p.tangents.empty());
  // A wrong number of posed primitives is refused.
  CHECK_FALSE(BuildPosedAsset(poser, {}, &posed).ok());
}

TEST_CASE("character pose: a deformer the table does not know is refused") {
  CharacterPoseOptions options;
  options.deformer = static_cast<DeformerKind>(9);
  CharacterPoser poser;
  const Status s = CharacterPoser::Build(test::FittedCylinders(), options, &poser);
  CHECK(s.code() == StatusCode::kInvalidInput);
  CHECK_THAT(s.message(), Catch::EndsWith(": unknown deformer 9"));
}

TEST_CASE("character pose: a bake past the vertex-frame budget is refused before posing") {
  // Issue 19, finding 5: a clip of 1e6 s at 30 frames per second asked for 1e7 frames.
  Asset asset = BendingCylinders();
  REQUIRE(asset.animations.size() == 1);
  for (AssetAnimationSampler& s : asset.animations[0].samplers) s.times.back() = 1.0e6f;
  REQUIRE(asset.animations[0].Duration() == Approx(1.0e6));
  Character ch;
  REQUIRE(FitCharacter(asset, CharacterFitOptions{}, &ch, nullptr).ok());
  CharacterPoseOptions options;
  options.deformer = DeformerKind::kSweep;
  CharacterPoser poser;
  REQUIRE(BuildPoser(ch, options, &poser));
  Asset baked;
  const Status s = BuildBakedAsset(&poser, 30.0, &baked, nullptr);
  INFO(s.message());
  REQUIRE_FALSE(s.ok());
  CHECK(s.message().find("10000001 frames") !=
        std::string::npos);  // ClipStepTimes caps a clip at 1e7 steps
  CHECK(s.message().find("vertex-frames") != std::string::npos);
  CHECK(baked.meshes.empty());
  // The same clip at a frame rate inside the budget bakes (1e6 s at 1e-4 fps: 101 frames).
  REQUIRE(BuildBakedAsset(&poser, 1e-4, &baked, nullptr).ok());
  REQUIRE_FALSE(baked.meshes.empty());
  CHECK(baked.meshes[0].primitives[0].targets.size() == 101);
}

}  // namespace dermis
