// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The per-frame runtime calls do not allocate: this executable replaces the global operator
// new (every non-aligned form, so that new and delete stay paired under AddressSanitizer) and
// counts every call while PoseJob::Run(), EvaluateJob::Run() and the C API's
// dermis_instance_pose() / dermis_evaluate() (and dermis_evaluate_with_tangents()) run, for
// every deformer.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <glm/gtc/matrix_transform.hpp>
#include <new>

#include "dermis/deform/deformer.h"
#include "dermis/dermis.h"
#include "dermis/runtime/runtime.h"
#include "support/fixtures.h"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size ? size : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace dermis {

TEST_CASE("runtime: per-frame calls do not allocate") {
  const std::string bytes = test::FixtureBytes("cylinders.dsurf");
  std::unique_ptr<RuntimeCharacter> rc;
  REQUIRE(RuntimeCharacter::FromBytes(bytes, "cylinders.dsurf", &rc).ok());
  std::vector<float> palette(32, 0.0f);
  for (int j = 0; j < 2; ++j)
    for (int k = 0; k < 4; ++k) palette[16 * j + 5 * k] = 1.0f;
  for (DeformerKind kind : {DeformerKind::kLbs, DeformerKind::kDqs, DeformerKind::kSweep}) {
    std::unique_ptr<RuntimeInstance> inst;
    REQUIRE(RuntimeInstance::Create(*rc, kind, &inst).ok());
    std::vector<std::unique_ptr<RuntimeOutput>> outputs;
    std::vector<std::vector<float>> buffers;
    for (std::size_t p = 0; p < rc->num_parts(); ++p) {
      for (OutputKind ok : {OutputKind::kBound, OutputKind::kLevel}) {
        OutputSpec spec;
        spec.kind = ok;
        spec.level = 5;
        std::unique_ptr<RuntimeOutput> o;
        REQUIRE(RuntimeOutput::Build(*rc, p, spec, &o).ok());
        buffers.emplace_back(6 * o->num_vertices());
        outputs.push_back(std::move(o));
      }
    }
    long during = 0;
    bool all_ok = true;  // checked after the counted windows (Catch's macros may allocate)
    for (int frame = 0; frame < 5; ++frame) {
      // A bend of joint 1 about z at its bind position (y = 1), growing frame by frame.
      const float a = 0.3f * static_cast<float>(frame);
      const float c = std::cos(a), s = std::sin(a);
      // T(0,1,0) R T(0,-1,0), column-major.
      const float m[16] = {c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, s, 1.0f - c, 0, 1};
      std::copy(m, m + 16, palette.begin() + 16);
      const long before = g_allocations.load();
      for (std::size_t p = 0; p < rc->num_parts(); ++p) {
        PoseJob job;
        job.instance = inst.get();
        job.part = p;
        job.skin_matrices = palette.data();
        job.num_skin_matrices = 2;
        all_ok = job.Run() && all_ok;
      }
      for (std::size_t k = 0; k < outputs.size(); ++k) {
        EvaluateJob job;
        job.output = outputs[k].get();
        job.instance = inst.get();
        job.buffers.positions = buffers[k].data();
        job.buffers.normals = buffers[k].data() + 3;
        job.buffers.position_stride = job.buffers.normal_stride = 6 * sizeof(float);
        all_ok = job.Run() && all_ok;
      }
      during += g_allocations.load() - before;
    }
    INFO(DeformerName(kind));
    CHECK(all_ok);
    CHECK(during == 0);
  }
  // The same through the C API.
  dermis_character* c = nullptr;
  REQUIRE(dermis_character_load_memory(bytes.data(), bytes.size(), "c.dsurf", &c) == DERMIS_OK);
  dermis_instance* inst = nullptr;
  // A value that names no deformer is refused (the deformer table decides, not a list here).
  for (const int bogus : {3}) {  // (in C any int may come; 3 is the one C++ may pass here)
    CHECK(dermis_instance_create(c, static_cast<dermis_deformer>(bogus), &inst) ==
          DERMIS_ERROR_INVALID_ARGUMENT);
    CHECK(inst == nullptr);
    CHECK(std::string(dermis_last_error()) == "dermis_instance_create: unknown deformer");
  }
  REQUIRE(dermis_instance_create(c, DERMIS_DEFORMER_SWEEP, &inst) == DERMIS_OK);
  dermis_output_desc desc;
  dermis_output_desc_init(&desc);
  dermis_output* out = nullptr;
  REQUIRE(dermis_output_create(c, 0, &desc, &out) == DERMIS_OK);
  std::vector<float> buf(3 * dermis_output_vertex_count(out));
  // A bound output with tangents (issue 17), evaluated with them each frame.
  desc.kind = DERMIS_OUTPUT_BOUND;
  desc.tangents = 1;
  dermis_output* bound = nullptr;
  REQUIRE(dermis_output_create(c, 0, &desc, &bound) == DERMIS_OK);
  const std::size_t nb = dermis_output_vertex_count(bound);
  std::vector<float> bbuf(10 * nb);
  const long before = g_allocations.load();
  bool c_ok = true;
  for (int frame = 0; frame < 3; ++frame) {
    c_ok = dermis_instance_pose(inst, 0, palette.data(), 2) == DERMIS_OK && c_ok;
    const int32_t remap[2] = {1, 0};  // the engine's order: the skin's reversed
    c_ok = dermis_instance_pose_remapped(inst, 0, palette.data(), 2, remap, 2) == DERMIS_OK && c_ok;
    c_ok = dermis_evaluate(inst, out, 0, SIZE_MAX, buf.data(), 12, buf.size() * 4, nullptr, 12,
                           0) == DERMIS_OK &&
           c_ok;
    c_ok = dermis_evaluate_with_tangents(inst, bound, 0, SIZE_MAX, bbuf.data(), 40, bbuf.size() * 4,
                                         bbuf.data() + 3, 40, bbuf.size() * 4, bbuf.data() + 6, 40,
                                         bbuf.size() * 4) == DERMIS_OK &&
           c_ok;
  }
  const long c_allocations = g_allocations.load() - before;
  CHECK(c_ok);
  CHECK(c_allocations == 0);
  // An error records a message (the one case that may allocate) and says what is wrong.
  CHECK(dermis_instance_pose(inst, 0, palette.data(), 1) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(std::string(dermis_last_error()).find("needs 2 skin matrices, got 1") != std::string::npos);
  CHECK(dermis_evaluate(inst, out, 5, 2, buf.data(), 12, buf.size() * 4, nullptr, 0, 0) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  dermis_output_destroy(bound);
  dermis_output_destroy(out);
  dermis_instance_destroy(inst);
  dermis_character_destroy(c);
  dermis_character_destroy(nullptr);
}

TEST_CASE("sweep: SetPose and Deform do not allocate, blended and leaf vertices included") {
  // A branching rig: a root with two chains (0 -> 1 -> 2 and 0 -> 3 -> 4), the leaves 2 and 4
  // carrying skin (virtual end bones), vertices shared by the two chains (dual-quaternion blend
  // of their frames) and a stretched pose (the DQS share).
  SkinRig rig;
  rig.parents = {-1, 0, 1, 0, 3};
  for (const Vec3& p :
       {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(8, 0, 0), Vec3(0, 4, 0), Vec3(0, 8, 0)}) {
    rig.bind.push_back(glm::translate(glm::dmat4(1.0), p));
  }
  std::vector<Vec3> x, n;
  std::vector<VertexWeights> w;
  for (int i = 0; i <= 40; ++i) {
    for (int k = 0; k < 8; ++k) {
      const double a = 0.785398163397 * k;
      const double t = 0.25 * i;
      for (int arm = 0; arm < 2; ++arm) {
        const Vec3 along = arm == 0 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Vec3 side = arm == 0 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
        x.push_back(t * along + 0.8 * (std::cos(a) * side + std::sin(a) * Vec3(0, 0, 1)));
        n.push_back(std::cos(a) * side + std::sin(a) * Vec3(0, 0, 1));
        VertexWeights vw;
        const std::uint16_t j1 = arm == 0 ? 1 : 3, j2 = arm == 0 ? 2 : 4;
        const float u = static_cast<float>(std::clamp((t - 3.0) / 2.0, 0.0, 1.0));
        const float v = static_cast<float>(std::clamp((t - 7.0) / 2.0, 0.0, 1.0));
        vw.joints = glm::u16vec4(0, j1, j2, arm == 0 ? 3 : 1);
        const float near_root = t < 1.0 ? 0.3f : 0.0f;  // shared with the other chain
        vw.weights = glm::vec4(1.0f - u, u - v, v, near_root);
        w.push_back(vw);
      }
    }
  }
  std::unique_ptr<Deformer> d;
  REQUIRE(MakeSweepDeformer(rig, x.data(), n.data(), w.data(), x.size(), SweepOptions{}, &d).ok());
  std::vector<Vec3> out(x.size()), nout(x.size());
  std::vector<glm::dmat4> palette(5, glm::dmat4(1.0));
  long during = 0;
  bool ok = true;
  for (int frame = 0; frame < 6; ++frame) {
    const double a = 0.4 * frame;
    palette[1] = glm::translate(glm::dmat4(1.0), {4, 0, 0}) *
                 glm::rotate(glm::dmat4(1.0), a, {0, 0, 1}) *
                 glm::translate(glm::dmat4(1.0), {-4, 0, 0});
    palette[2] = palette[1] * glm::translate(glm::dmat4(1.0), {8, 0, 0}) *
                 glm::rotate(glm::dmat4(1.0), 1.5 * a, {1, 0, 0}) *
                 glm::translate(glm::dmat4(1.0), {-8, 0, 0});
    palette[3] = glm::translate(glm::dmat4(1.0), {0, 4, 0}) *
                 glm::rotate(glm::dmat4(1.0), -a, {0, 0, 1}) *
                 glm::scale(glm::dmat4(1.0), {1.0, 1.0 + 0.01 * frame, 1.0}) *
                 glm::translate(glm::dmat4(1.0), {0, -4, 0});
    palette[4] = palette[3];
    const long before = g_allocations.load();
    ok = d->SetPose(palette.data()).ok() && ok;
    d->Deform(0, x.size(), out.data(), nout.data());
    during += g_allocations.load() - before;
  }
  CHECK(ok);
  CHECK(during == 0);
  for (const Vec3& p : out) CHECK(std::isfinite(p.x + p.y + p.z));
}

}  // namespace dermis
