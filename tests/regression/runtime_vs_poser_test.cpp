// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Cross-check between layers: the engine runtime's jobs (PoseJob, EvaluateJob, single
// precision, SIMD) against the offline character poser (double precision) on the same fitted
// character, for every deformer. Links the runtime and the offline character stage.
#include <catch2/catch.hpp>
#include <glm/gtc/quaternion.hpp>
#include <memory>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/runtime/runtime.h"
#include "support/fixtures.h"

namespace dermis {

TEST_CASE("runtime: character jobs match the offline poser") {
  const Character& ch = test::CylindersFixture();
  std::unique_ptr<RuntimeCharacter> rc;
  // Through the file format, as an engine loads it.
  REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "cylinders.dsurf", &rc).ok());
  REQUIRE(rc->num_parts() == ch.parts.size());
  REQUIRE(rc->num_parts() == 2);
  for (DeformerKind kind : {DeformerKind::kLbs, DeformerKind::kDqs, DeformerKind::kSweep}) {
    CharacterPoseOptions po;
    po.deformer = kind;
    CharacterPoser poser;
    REQUIRE(CharacterPoser::Build(ch, po, &poser).ok());
    std::unique_ptr<RuntimeInstance> inst;
    REQUIRE(RuntimeInstance::Create(*rc, kind, &inst).ok());
    AssetPose pose;
    RestPose(poser.asset(), &pose);
    for (int step = 0; step <= 6; ++step) {
      // j1 (node 2) bends about z and twists about its bone, step by step (sweep history).
      pose.local[2].rotation = glm::angleAxis(0.25 * step, glm::dvec3(0, 0, 1)) *
                               glm::angleAxis(0.2 * step, glm::dvec3(0, 1, 0));
      REQUIRE(poser.SetPose(pose).ok());
      std::vector<glm::dmat4> world, joints;
      ComputeWorldMatrices(poser.asset(), pose, &world);
      ComputeJointMatrices(poser.asset().skins[0], world, &joints);
      std::vector<float> palette(16 * joints.size());
      for (std::size_t j = 0; j < joints.size(); ++j) {
        for (int c = 0; c < 4; ++c) {
          for (int r = 0; r < 4; ++r)
            palette[16 * j + 4 * c + r] = static_cast<float>(joints[j][c][r]);
        }
      }
      for (std::size_t p = 0; p < rc->num_parts(); ++p) {
        PoseJob job;
        job.instance = inst.get();
        job.part = p;
        job.skin_matrices = palette.data();
        job.num_skin_matrices = joints.size();
        REQUIRE(job.Run());
      }
    }
    std::vector<PosedPrimitive> posed;
    REQUIRE(poser.Evaluate(&posed).ok());
    for (std::size_t p = 0; p < rc->num_parts(); ++p) {
      OutputSpec spec;
      spec.kind = OutputKind::kBound;
      std::unique_ptr<RuntimeOutput> out;
      REQUIRE(RuntimeOutput::Build(*rc, p, spec, &out).ok());
      const std::vector<BoundVertexRef>& refs = rc->bound_vertices(p);
      REQUIRE(out->num_vertices() == refs.size());
      REQUIRE(!refs.empty());
      std::vector<float> pos(3 * refs.size()), nrm(3 * refs.size());
      EvaluateJob ej;
      ej.output = out.get();
      ej.instance = inst.get();
      ej.buffers.positions = pos.data();
      ej.buffers.normals = nrm.data();
      REQUIRE(ej.Run());
      double worst = 0.0, worst_n = 0.0;
      for (std::size_t i = 0; i < refs.size(); ++i) {
        // The mesh is drawn by one node (the poser's drawn primitive of the same mesh).
        std::size_t d = 0;
        while (poser.drawn()[d].mesh != refs[i].mesh ||
               poser.drawn()[d].primitive != refs[i].primitive)
          ++d;
        const Vec3 want = posed[d].positions[static_cast<std::size_t>(refs[i].vertex)];
        const Vec3 want_n = posed[d].normals[static_cast<std::size_t>(refs[i].vertex)];
        worst =
            std::max(worst, glm::length(Vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]) - want));
        worst_n = std::max(worst_n,
                           glm::length(Vec3(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]) - want_n));
      }
      INFO(DeformerName(kind) << " part " << p << ": position " << worst << " normal " << worst_n);
      // Model units: the capsules are 3 long; float palettes and float evaluation.
      CHECK(worst < 3e-5);
      CHECK(worst_n < 1e-4);
    }
  }
}

}  // namespace dermis
