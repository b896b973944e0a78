// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/runtime_frames.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <vector>

#include "dermis/runtime/runtime.h"

namespace dermis::test {
namespace {

struct Loaded {
  std::unique_ptr<RuntimeCharacter> character;
  std::vector<std::unique_ptr<RuntimeOutput>> outputs;
  std::unique_ptr<RuntimeInstance> instance;
};

Loaded Load(const std::string& bytes, const std::string& name, int level, DeformerKind deformer) {
  Loaded l;
  Status s = RuntimeCharacter::FromBytes(bytes, name, &l.character);
  INFO(s.message());
  REQUIRE(s.ok());
  for (std::size_t p = 0; p < l.character->num_parts(); ++p) {
    OutputSpec spec;
    spec.kind = level == 0 ? OutputKind::kBound : OutputKind::kLevel;
    spec.level = std::max(level, 1);
    spec.threads = 2;
    std::unique_ptr<RuntimeOutput> o;
    s = RuntimeOutput::Build(*l.character, p, spec, &o);
    INFO(s.message());
    REQUIRE(s.ok());
    l.outputs.push_back(std::move(o));
  }
  s = RuntimeInstance::Create(*l.character, deformer, &l.instance);
  INFO(s.message());
  REQUIRE(s.ok());
  return l;
}

// Skin matrices of frame f for part p: joint j turned by 25 f degrees about an axis of its
// own, through its bind position.
std::vector<float> SkinMatrices(const SkinRig& rig, int f) {
  std::vector<float> m(16 * rig.parents.size());
  for (std::size_t j = 0; j < rig.parents.size(); ++j) {
    const glm::dmat4& bind = rig.bind[j];
    const glm::dvec3 origin(bind[3]);
    const glm::dvec3 axis = glm::normalize(
        glm::dvec3(1.0 + 0.3 * static_cast<double>(j % 3), 0.5, 0.2 * static_cast<double>(j % 5)));
    const double angle = glm::radians(25.0 * f);
    glm::dmat4 world = glm::translate(glm::dmat4(1.0), origin) *
                       glm::rotate(glm::dmat4(1.0), angle, axis) *
                       glm::translate(glm::dmat4(1.0), -origin);
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r)
        m[16 * j + 4 * static_cast<std::size_t>(c) + static_cast<std::size_t>(r)] =
            static_cast<float>(world[c][r]);
    }
  }
  return m;
}

std::vector<float> Frame(Loaded* l, std::size_t p, int f) {
  if (const SkinRig* rig = l->character->rig(p)) {
    const std::vector<float> m = SkinMatrices(*rig, f);
    PoseJob pose;
    pose.instance = l->instance.get();
    pose.part = p;
    pose.skin_matrices = m.data();
    pose.num_skin_matrices = rig->parents.size();
    REQUIRE(pose.Run());
  }
  std::vector<float> x(3 * l->outputs[p]->num_vertices());
  EvaluateJob job;
  job.output = l->outputs[p].get();
  job.instance = l->instance.get();
  job.buffers.positions = x.data();
  REQUIRE(job.Run());
  return x;
}

}  // namespace

FrameDeviation CompareRuntimeFrames(const std::string& a, const std::string& b, int level,
                                    DeformerKind deformer, int frames) {
  Loaded la = Load(a, "a.dsurf", level, deformer), lb = Load(b, "b.dsurf", level, deformer);
  REQUIRE(la.character->num_parts() == lb.character->num_parts());
  FrameDeviation d;
  glm::dvec3 lo(1e300), hi(-1e300);
  double sum = 0.0;
  for (int f = 0; f < frames; ++f) {
    for (std::size_t p = 0; p < la.character->num_parts(); ++p) {
      REQUIRE(la.character->num_joints(p) == lb.character->num_joints(p));
      const std::vector<float> xa = Frame(&la, p, f), xb = Frame(&lb, p, f);
      REQUIRE(xa.size() == xb.size());
      for (std::size_t i = 0; i < xa.size(); i += 3) {
        const glm::dvec3 pa(xa[i], xa[i + 1], xa[i + 2]), pb(xb[i], xb[i + 1], xb[i + 2]);
        if (f == 0) {
          lo = glm::min(lo, pa);
          hi = glm::max(hi, pa);
        }
        const double e = glm::length(pb - pa);
        d.max = std::max(d.max, e);
        sum += e;
        ++d.vertices;
      }
    }
  }
  d.diagonal = glm::length(hi - lo);
  d.mean = d.vertices > 0 ? sum / static_cast<double>(d.vertices) : 0.0;
  return d;
}

}  // namespace dermis::test
