// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Tangents of bound outputs (issue 17, docs/engine-integration.md "Tangents"): at the rest pose
// the source's tangent made orthogonal to the surface normal (from TANGENT, or from the
// texture coordinates: the capsule's u runs around its axis), under a rigid motion rotated
// with it, under a bending pose the direction of the surface curve the frame coefficients
// name (central differences of positions), and the C API's buffer checks. On the fitted
// two-capsule character (tests/support/fixtures.h).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "dermis/dermis.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/runtime.h"
#include "support/fixtures.h"

namespace dermis {
namespace {

glm::dvec3 Vec(const float* p) { return glm::dvec3(p[0], p[1], p[2]); }

struct Frame {
  std::vector<float> pos, nrm, tan;
};

// Evaluates every vertex of `out` with tangents (interleaved buffers of their own strides).
Frame EvaluateAll(const RuntimeInstance& inst, const RuntimeOutput& out) {
  const std::size_t n = out.num_vertices();
  Frame f;
  f.pos.assign(3 * n, 0.0f);
  f.nrm.assign(3 * n, 0.0f);
  f.tan.assign(4 * n, 0.0f);
  EvaluateJob job;
  job.output = &out;
  job.instance = &inst;
  job.buffers.positions = f.pos.data();
  job.buffers.normals = f.nrm.data();
  job.buffers.tangents = f.tan.data();
  REQUIRE(job.Run());
  return f;
}

// A character with the fixture's asset, optionally given explicit tangents.
std::unique_ptr<RuntimeCharacter> Load(bool explicit_tangents) {
  Character c;
  REQUIRE(ParseCharacter(test::FixtureBytes("cylinders.dsurf"), "cylinders.dsurf", &c).ok());
  if (explicit_tangents) {
    for (AssetMesh& m : c.asset.meshes) {
      for (AssetPrimitive& p : m.primitives) {
        p.tangents.resize(p.positions.size());
        for (std::size_t i = 0; i < p.tangents.size(); ++i) {
          const glm::vec3 t = glm::normalize(glm::vec3(0.3f, 1.0f, 0.2f + 0.01f * float(i % 7)));
          p.tangents[i] = glm::vec4(t, i % 2 ? -1.0f : 1.0f);
        }
      }
    }
  }
  std::unique_ptr<RuntimeCharacter> rc;
  REQUIRE(RuntimeCharacter::FromCharacter(std::move(c), &rc).ok());
  return rc;
}

std::unique_ptr<RuntimeOutput> BoundWithTangents(const RuntimeCharacter& rc) {
  OutputSpec spec;
  spec.kind = OutputKind::kBound;
  spec.tangents = true;
  std::unique_ptr<RuntimeOutput> out;
  const Status s = RuntimeOutput::Build(rc, 0, spec, &out);
  INFO(s.message());
  REQUIRE(s.ok());
  return out;
}

TEST_CASE("tangents: from TANGENT, the source's tangent at the rest pose") {
  const std::unique_ptr<RuntimeCharacter> rc = Load(true);
  const std::unique_ptr<RuntimeOutput> out = BoundWithTangents(*rc);
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kLbs, &inst).ok());
  const Frame f = EvaluateAll(*inst, *out);
  const Asset& a = rc->character().asset;
  double worst = 0.0;
  for (std::size_t i = 0; i < out->num_vertices(); ++i) {
    const BoundVertexRef& r = rc->bound_vertices(0)[i];
    const glm::vec4 src = a.meshes[static_cast<std::size_t>(r.mesh)]
                              .primitives[static_cast<std::size_t>(r.primitive)]
                              .tangents[static_cast<std::size_t>(r.vertex)];
    const glm::dvec3 n = Vec(&f.nrm[3 * i]);
    const glm::dvec3 t = Vec(&f.tan[4 * i]);
    glm::dvec3 expected = glm::dvec3(src) - n * glm::dot(n, glm::dvec3(src));
    if (glm::length(expected) < 0.1) continue;  // the tangent nearly along the normal
    expected = glm::normalize(expected);
    worst = std::max(worst, glm::length(t - expected));
    CHECK(f.tan[4 * i + 3] == src.w);
    CHECK(std::fabs(glm::dot(t, n)) < 1e-5);
  }
  INFO("largest difference " << worst);
  CHECK(worst < 1e-4);
}

TEST_CASE("tangents: from texture coordinates, around the capsule's axis, glTF handedness") {
  const std::unique_ptr<RuntimeCharacter> rc = Load(false);
  const std::unique_ptr<RuntimeOutput> out = BoundWithTangents(*rc);
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kLbs, &inst).ok());
  const Frame f = EvaluateAll(*inst, *out);
  std::size_t checked = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < out->num_vertices(); ++i) {
    const glm::dvec3 p = Vec(&f.pos[3 * i]), n = Vec(&f.nrm[3 * i]), t = Vec(&f.tan[4 * i]);
    CHECK(std::fabs(glm::length(t) - 1.0) < 1e-5);
    CHECK(std::fabs(glm::dot(t, n)) < 1e-5);
    // The capsules' sides (x0 = 0 or 3, u = angle / 2 pi around y, v up), away from the u
    // seam at angle 0 (the fixture does not split it) and from the caps (no uv).
    const double x0 = p.x > 1.5 ? 3.0 : 0.0;
    const double angle = std::atan2(p.z, p.x - x0);
    if (p.y < 0.3 || p.y > 1.7 || std::fabs(angle) < 0.5) continue;
    // Around the axis, on the fitted surface's tangent plane (its normal is a few degrees off
    // the exact capsule's).
    glm::dvec3 around(-std::sin(angle), 0.0, std::cos(angle));
    around = glm::normalize(around - n * glm::dot(n, around));
    worst = std::max(worst, glm::length(t - around));
    // The bitangent cross(n, t) w points towards decreasing v (down the capsule).
    CHECK(glm::dot(glm::cross(n, t) * static_cast<double>(f.tan[4 * i + 3]), glm::dvec3(0, 1, 0)) <
          -0.9);
    ++checked;
  }
  INFO("largest difference " << worst << " over " << checked << " side vertices");
  CHECK(checked > 100);
  CHECK(worst < 1e-3);  // the triangle mesh's u direction against the exact one
}

TEST_CASE("tangents: a rigid motion rotates them; a bend keeps them along the surface curve") {
  const std::unique_ptr<RuntimeCharacter> rc = Load(true);
  const std::unique_ptr<RuntimeOutput> out = BoundWithTangents(*rc);
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kDqs, &inst).ok());
  const Frame rest = EvaluateAll(*inst, *out);
  const std::size_t joints = rc->num_joints(0);
  REQUIRE(joints >= 2);
  // Rigid: every joint by the same rotation (0.7 rad about (1, 2, 3)) and shift.
  const glm::dmat3 rot = glm::dmat3(glm::rotate(glm::dmat4(1.0), 0.7, glm::dvec3(1, 2, 3)));
  std::vector<float> pal(16 * joints);
  for (std::size_t j = 0; j < joints; ++j) {
    glm::mat4 m = glm::mat4(glm::dmat4(rot));
    m[3] = glm::vec4(0.4f, -0.2f, 1.5f, 1.0f);
    std::copy(&m[0][0], &m[0][0] + 16, &pal[16 * j]);
  }
  PoseJob pose;
  pose.instance = inst.get();
  pose.part = 0;
  pose.skin_matrices = pal.data();
  pose.num_skin_matrices = joints;
  REQUIRE(pose.Run());
  const Frame moved = EvaluateAll(*inst, *out);
  double worst = 0.0;
  for (std::size_t i = 0; i < out->num_vertices(); ++i) {
    worst = std::max(worst, glm::length(Vec(&moved.tan[4 * i]) - rot * Vec(&rest.tan[4 * i])));
    CHECK(moved.tan[4 * i + 3] == rest.tan[4 * i + 3]);
  }
  INFO("rigid: largest difference " << worst);
  CHECK(worst < 1e-4);

  // A bend: joint 1 rotated by 0.8 rad about z, joint 0 at rest. The tangent must be the
  // direction (on the tangent plane) of the surface curve s -> S(u + s a, v + s b) that the
  // vertex's frame coefficients name, by central differences of the posed surface.
  for (std::size_t j = 0; j < joints; ++j) {
    glm::mat4 m(1.0f);
    if (j == 1) m = glm::rotate(glm::mat4(1.0f), 0.8f, glm::vec3(0, 0, 1));
    std::copy(&m[0][0], &m[0][0] + 16, &pal[16 * j]);
  }
  REQUIRE(pose.Run());
  const Frame bent = EvaluateAll(*inst, *out);
  const std::vector<SampleLocation>& loc = rc->bound_locations(0);
  const std::vector<float>& frames = out->tangent_frames();
  std::vector<SampleLocation> fd;
  std::vector<std::size_t> which;
  const double h = 1e-3;
  for (std::size_t i = 0; i < loc.size() && which.size() < 400; i += 3) {
    const double a = frames[4 * i], b = frames[4 * i + 1];
    const double l = std::sqrt(a * a + b * b);
    if (!(l > 0.0)) continue;
    const double du = h * a / l, dv = h * b / l;
    const SampleLocation& s = loc[i];
    if (s.u - std::fabs(du) < 0.0 || s.u + std::fabs(du) > 1.0 || s.v - std::fabs(dv) < 0.0 ||
        s.v + std::fabs(dv) > 1.0) {
      continue;
    }
    fd.push_back({s.face, s.u + du, s.v + dv});
    fd.push_back({s.face, s.u - du, s.v - dv});
    which.push_back(i);
  }
  REQUIRE(which.size() > 100);
  const DisplacedSurface& surf = rc->character().parts[0].surface;
  EvaluationPlan plan;
  REQUIRE(
      EvaluationPlan::Build(*surf.domain, surf.displacement.get(), fd.data(), fd.size(), {}, &plan)
          .ok());
  std::vector<float> fp(3 * fd.size());
  PlanOutputBuffers ob;
  ob.positions = fp.data();
  REQUIRE(EvaluatePlan(plan, inst->packed_patches(0), 0, plan.num_blocks(), ob));
  double worst_fd = 0.0;
  for (std::size_t k = 0; k < which.size(); ++k) {
    const std::size_t i = which[k];
    const glm::dvec3 n = Vec(&bent.nrm[3 * i]);
    glm::dvec3 d = Vec(&fp[6 * k]) - Vec(&fp[6 * k + 3]);
    d = glm::normalize(d - n * glm::dot(n, d));
    worst_fd = std::max(worst_fd, glm::length(Vec(&bent.tan[4 * i]) - d));
  }
  INFO("bend: largest difference from central differences " << worst_fd);
  CHECK(worst_fd < 2e-3);
}

TEST_CASE("tangents: the C API checks the tangent buffer and writes nothing on failure") {
  const std::string bytes = test::FixtureBytes("cylinders.dsurf");
  dermis_character* c = nullptr;
  REQUIRE(dermis_character_load_memory(bytes.data(), bytes.size(), "c.dsurf", &c) == DERMIS_OK);
  dermis_instance* inst = nullptr;
  REQUIRE(dermis_instance_create(c, DERMIS_DEFORMER_LBS, &inst) == DERMIS_OK);
  dermis_output_desc desc;
  dermis_output_desc_init(&desc);
  CHECK(desc.tangents == 0);
  desc.tangents = 1;
  dermis_output* level = nullptr;
  CHECK(dermis_output_create(c, 0, &desc, &level) != DERMIS_OK);
  CHECK(level == nullptr);
  CHECK(std::string(dermis_last_error()).find("bound output") != std::string::npos);
  desc.kind = DERMIS_OUTPUT_BOUND;
  dermis_output* out = nullptr;
  REQUIRE(dermis_output_create(c, 0, &desc, &out) == DERMIS_OK);
  CHECK(dermis_output_has_tangents(out) == 1);
  desc.tangents = 0;
  dermis_output* plain = nullptr;
  REQUIRE(dermis_output_create(c, 0, &desc, &plain) == DERMIS_OK);
  CHECK(dermis_output_has_tangents(plain) == 0);
  const std::size_t n = dermis_output_vertex_count(out);
  // One interleaved vertex: position, normal, tangent (40 bytes).
  const std::size_t stride = 10 * sizeof(float);
  std::vector<float> v(10 * n, -7.0f);
  const std::size_t bytes_needed = dermis_output_required_bytes(out, 0, SIZE_MAX, stride) + 4;
  CHECK(bytes_needed == (n - 1) * stride + 16);
  CHECK(dermis_evaluate_with_tangents(inst, out, 0, SIZE_MAX, v.data(), stride, v.size() * 4,
                                      v.data() + 3, stride, v.size() * 4, v.data() + 6, stride,
                                      bytes_needed - 7) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(std::string(dermis_last_error()).find("tangent buffer") != std::string::npos);
  CHECK(std::all_of(v.begin(), v.end(), [](float x) { return x == -7.0f; }));
  CHECK(dermis_evaluate_with_tangents(inst, plain, 0, SIZE_MAX, v.data(), stride, v.size() * 4,
                                      v.data() + 3, stride, v.size() * 4, v.data() + 6, stride,
                                      v.size() * 4) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(dermis_evaluate_with_tangents(inst, out, 0, SIZE_MAX, v.data(), stride, v.size() * 4,
                                      v.data() + 3, stride, v.size() * 4, v.data() + 6, 12,
                                      v.size() * 4) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(std::all_of(v.begin(), v.end(), [](float x) { return x == -7.0f; }));
  REQUIRE(dermis_evaluate_with_tangents(inst, out, 0, SIZE_MAX, v.data(), stride, v.size() * 4,
                                        v.data() + 3, stride, v.size() * 4, v.data() + 6, stride,
                                        bytes_needed) == DERMIS_OK);
  // The same positions and normals as dermis_evaluate(); unit tangents orthogonal to them.
  std::vector<float> p(6 * n);
  REQUIRE(dermis_evaluate(inst, out, 0, SIZE_MAX, p.data(), 24, p.size() * 4, p.data() + 3, 24,
                          p.size() * 4) == DERMIS_OK);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 6; ++k)
      CHECK(v[10 * i + static_cast<std::size_t>(k)] == p[6 * i + static_cast<std::size_t>(k)]);
    const glm::dvec3 t = Vec(&v[10 * i + 6]), nn = Vec(&v[10 * i + 3]);
    CHECK(std::fabs(glm::length(t) - 1.0) < 1e-5);
    CHECK(std::fabs(glm::dot(t, nn)) < 1e-5);
    CHECK(std::fabs(v[10 * i + 9]) == 1.0f);
  }
  dermis_output_destroy(plain);
  dermis_output_destroy(out);
  dermis_instance_destroy(inst);
  dermis_character_destroy(c);
}

}  // namespace
}  // namespace dermis
