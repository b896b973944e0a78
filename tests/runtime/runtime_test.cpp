// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The engine runtime: the precomputed fast path against the scalar reference evaluator
// (EvaluateSurface, double precision), independence of block splits, threads and instruction
// sets, the jobs' refusal of bad input. Runtime only: the domains and the fitted character are
// fixtures (support/fixtures.h); the jobs against the offline poser are in
// tests/regression/runtime_vs_poser_test.cpp.
#include "dermis/runtime/runtime.h"

#include <catch2/catch.hpp>
#include <cstring>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <thread>

#include "dermis/runtime/evaluation_plan.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"
#include "support/fixtures.h"
#include "support/random.h"
#include "support/wavy_displacement.h"

namespace dermis {
namespace {

std::vector<SimdPath> AvailablePaths() {
  std::vector<SimdPath> paths;
  for (SimdPath p : {SimdPath::kScalar, SimdPath::kGeneric, SimdPath::kAvx2}) {
    if (SimdPathAvailable(p)) paths.push_back(p);
  }
  return paths;
}

double Diagonal(const std::vector<Vec3>& x) {
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

// Samples with every special case: the tessellation grid (corners, edges, the one-chart
// squares [0, lb]^2 at level 64 near corners) and random interior points.
std::vector<SampleLocation> TestSamples(const ManifoldDomain& domain) {
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(domain.topology(), 7, &pattern).ok());
  std::vector<SampleLocation> s = pattern.samples;
  test::Lcg rng(7);
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int k = 0; k < 9; ++k) s.push_back({f, rng.Next(), rng.Next()});
    s.push_back({f, 0.004, 0.003});  // one-chart square of corner 0
    s.push_back({f, 0.998, 0.0});    // near corner 1, on an edge
    s.push_back({f, 1.0, 1.0});      // corner 2 itself
  }
  return s;
}

struct Compared {
  double position = 0.0;  // max |fast - scalar| / diagonal
  double normal = 0.0;    // max |fast - scalar|
};

Compared CompareWithScalar(const ManifoldDomain& domain, const std::vector<LocalPatch>& patches,
                           const Displacement* disp, const std::vector<SampleLocation>& samples,
                           SimdPath path) {
  EvaluationPlan plan;
  REQUIRE(EvaluationPlan::Build(domain, disp, samples.data(), samples.size(), {}, &plan).ok());
  std::vector<float> packed(patches.size() * kPackedPatchStride);
  PackPatches(patches.data(), patches.size(), packed.data());
  std::vector<float> pos(3 * samples.size(), NAN), nrm(3 * samples.size(), NAN);
  PlanOutputBuffers out;
  out.positions = pos.data();
  out.normals = nrm.data();
  REQUIRE(EvaluatePlan(plan, packed.data(), 0, plan.num_blocks(), out, path));
  std::vector<Vec3> ref(samples.size()), ref_n(samples.size());
  REQUIRE(EvaluateSamples(domain, patches.data(), disp, samples.data(), samples.size(), ref.data(),
                          ref_n.data()));
  const double diag = Diagonal(ref);
  Compared c;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3 p(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    const Vec3 n(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    c.position = std::max(c.position, glm::length(p - ref[i]) / diag);
    c.normal = std::max(c.normal, glm::length(n - ref_n[i]));
  }
  return c;
}

}  // namespace

TEST_CASE("runtime: the fast path equals the scalar reference") {
  // Extraordinary vertices (valence 3, 5, 7), boundaries, a moved control mesh, a smooth
  // displacement that differs per chart, and the domain surface without displacement.
  for (const char* name : {"house", "prism7", "torus"}) {
    const DisplacedSurface cs = test::SurfaceFixture(name);
    std::vector<Vec3> moved = cs.rest_positions;
    test::Lcg rng(3);
    for (Vec3& p : moved) p += Vec3(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), 0.0);
    std::vector<LocalPatch> patches(moved.size());
    cs.domain->FitPatches(moved.data(), patches.data());
    const test::WavyDisplacement wavy(0.04);
    const std::vector<SampleLocation> samples = TestSamples(*cs.domain);
    for (const Displacement* disp :
         {static_cast<const Displacement*>(&wavy), static_cast<const Displacement*>(nullptr)}) {
      for (SimdPath path : AvailablePaths()) {
        const Compared c = CompareWithScalar(*cs.domain, patches, disp, samples, path);
        INFO(name << " " << SimdPathName(path) << (disp ? " displaced" : " domain") << ": position "
                  << c.position << " normal " << c.normal);
        CHECK(c.position < 1e-5);
        CHECK(c.normal < 1e-5);
      }
    }
  }
}

TEST_CASE("runtime: sparse displacement levels, whole and truncated, on the fast path") {
  // The plan precomputes d(z) per sample through the Displacement interface: the additive
  // sparse levels of .dsurf version 3 and their truncation give the scalar evaluator's surface.
  const DisplacedSurface cs = test::SurfaceFixture("torus");
  const ManifoldDomain& domain = *cs.domain;
  std::vector<LocalPatch> patches(cs.rest_positions.size());
  domain.FitPatches(cs.rest_positions.data(), patches.data());
  test::Lcg rng(12);
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  d.offsets.push_back(0);
  for (Index v = 0; v < domain.num_vertices(); ++v) {
    d.half_extent.push_back(1.6);
    d.num_levels.push_back(3);
    for (int k = 0; k < 3; ++k) {
      std::int32_t count = 0;
      for (std::int64_t n = 0; n < BsplineLatticeSize(k); ++n) {
        if (k > 0 && rng.Next() < 0.5) continue;  // levels 1 and 2 sparse
        if (k > 0) d.nodes.push_back(static_cast<std::uint32_t>(n));
        d.values.push_back(static_cast<float>(rng.Uniform(-0.03, 0.03) / (1 << k)));
        ++count;
      }
      d.level_counts.push_back(count);
    }
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  }
  Status s;
  auto disp = BsplineDisplacement::Create(d, domain.num_vertices(), &s);
  REQUIRE(disp);
  const TruncatedDisplacement two(disp.get(), 2);
  const std::vector<SampleLocation> samples = TestSamples(domain);
  for (const Displacement* dp :
       {static_cast<const Displacement*>(disp.get()), static_cast<const Displacement*>(&two)}) {
    for (SimdPath path : AvailablePaths()) {
      const Compared c = CompareWithScalar(domain, patches, dp, samples, path);
      INFO(SimdPathName(path) << (dp == &two ? " two levels" : " all levels") << ": position "
                              << c.position << " normal " << c.normal);
      CHECK(c.position < 1e-5);
      CHECK(c.normal < 1e-5);
    }
  }
}

TEST_CASE("runtime: results do not depend on threads, block splits or the plan's threads") {
  const DisplacedSurface cs = test::SurfaceFixture("house");
  std::vector<LocalPatch> rest_patches(cs.rest_positions.size());
  cs.domain->FitPatches(cs.rest_positions.data(), rest_patches.data());
  const test::WavyDisplacement wavy(0.04);
  const std::vector<SampleLocation> samples = TestSamples(*cs.domain);
  EvaluationPlan plans[2];
  for (int t = 0; t < 2; ++t) {
    EvaluationPlanOptions o;
    o.threads = t + 1;
    REQUIRE(EvaluationPlan::Build(*cs.domain, &wavy, samples.data(), samples.size(), o, &plans[t])
                .ok());
  }
  REQUIRE(plans[0].num_blocks() == plans[1].num_blocks());
  CHECK(std::memcmp(plans[0].block_data(), plans[1].block_data(),
                    plans[0].num_blocks() * kPlanBlockFloats * sizeof(float)) == 0);
  CHECK(plans[0].num_samples() == samples.size());
  std::vector<float> packed(rest_patches.size() * kPackedPatchStride);
  PackPatches(rest_patches.data(), rest_patches.size(), packed.data());
  // Interleaved output (position, normal, 2 floats of something else: stride 32 bytes).
  const std::size_t n = samples.size();
  std::vector<float> whole(8 * n, -7.0f), split(8 * n, -7.0f);
  auto buffers = [](std::vector<float>& v) {
    PlanOutputBuffers o;
    o.positions = v.data();
    o.normals = v.data() + 3;
    o.position_stride = o.normal_stride = 8 * sizeof(float);
    return o;
  };
  REQUIRE(EvaluatePlan(plans[0], packed.data(), 0, plans[0].num_blocks(), buffers(whole)));
  const std::size_t half = plans[0].num_blocks() / 3;
  bool other_ok = false;  // Catch2 assertions are not thread-safe: checked after the join
  std::thread other([&] {
    other_ok = EvaluatePlan(plans[1], packed.data(), half, plans[1].num_blocks(), buffers(split));
  });
  REQUIRE(EvaluatePlan(plans[1], packed.data(), 0, half, buffers(split)));
  other.join();
  REQUIRE(other_ok);
  CHECK(std::memcmp(whole.data(), split.data(), whole.size() * sizeof(float)) == 0);
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(whole[8 * i + 6] == -7.0f);  // the caller's other attributes are left alone
    CHECK(whole[8 * i + 7] == -7.0f);
  }
  // Bad calls write nothing.
  PlanOutputBuffers bad = buffers(split);
  CHECK_FALSE(EvaluatePlan(plans[0], packed.data(), 2, 1, bad));
  CHECK_FALSE(EvaluatePlan(plans[0], packed.data(), 0, plans[0].num_blocks() + 1, bad));
  bad.position_stride = 4;
  CHECK_FALSE(EvaluatePlan(plans[0], packed.data(), 0, 1, bad));
  CHECK_FALSE(EvaluatePlan(plans[0], nullptr, 0, 1, buffers(split)));
  // The kernel backends: the portable one always runs; kAuto is the fastest this CPU runs;
  // every available backend writes the same bytes as the one kAuto picks, up to float
  // contraction (checked against the reference in the test above).
  CHECK(SimdPathAvailable(SimdPath::kGeneric));
  CHECK(SimdPathAvailable(SimdPath::kScalar));
  CHECK(BestSimdPath() != SimdPath::kScalar);
  CHECK(SimdPathAvailable(SimdPath::kAuto));
  CHECK(SimdPathAvailable(BestSimdPath()));
  CHECK(BestSimdPath() != SimdPath::kAuto);
  CHECK(std::string(SimdPathName(SimdPath::kGeneric)) == "generic");
  CHECK(std::string(SimdPathName(SimdPath::kAvx2)) == "avx2");
  CHECK(std::string(SimdPathName(SimdPath::kScalar)) == "scalar");
  CHECK(std::string(SimdPathName(SimdPath::kAuto)) == SimdPathName(BestSimdPath()));
  CHECK(SimdPathAvailable(static_cast<SimdPath>(9)) == false);
  CHECK_FALSE(
      EvaluatePlan(plans[0], packed.data(), 0, 1, buffers(split), static_cast<SimdPath>(9)));
  for (SimdPath path : AvailablePaths()) {
    std::vector<float> again(8 * n, -7.0f);
    REQUIRE(EvaluatePlan(plans[0], packed.data(), 0, plans[0].num_blocks(), buffers(again), path));
    if (path == BestSimdPath()) {
      CHECK(std::memcmp(whole.data(), again.data(), whole.size() * sizeof(float)) == 0);
    }
  }
  // Invalid sample locations are refused, naming the sample.
  std::vector<SampleLocation> wrong = samples;
  wrong[5].u = 1.5;
  EvaluationPlan p;
  const Status s = EvaluationPlan::Build(*cs.domain, &wavy, wrong.data(), wrong.size(), {}, &p);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("sample 5") != std::string::npos);
  wrong[5] = {cs.domain->num_faces(), 0.5, 0.5};
  CHECK_FALSE(EvaluationPlan::Build(*cs.domain, &wavy, wrong.data(), wrong.size(), {}, &p).ok());
}

TEST_CASE("runtime: jobs refuse bad input and loading names the file") {
  const Character& ch = test::CylindersFixture();
  std::unique_ptr<RuntimeCharacter> rc, other;
  REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "a.dsurf", &rc).ok());
  REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "b.dsurf", &other).ok());
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kSweep, &inst).ok());
  std::vector<float> palette(16 * 2, 0.0f);
  for (int j = 0; j < 2; ++j)
    for (int k = 0; k < 4; ++k) palette[16 * j + 5 * k] = 1.0f;
  PoseJob job;
  CHECK_FALSE(job.Validate());  // no instance
  job.instance = inst.get();
  job.skin_matrices = palette.data();
  job.num_skin_matrices = 1;  // the skin has 2 joints
  CHECK_FALSE(job.Run());
  job.num_skin_matrices = 2;
  CHECK(job.Run());
  job.part = 9;
  CHECK_FALSE(job.Validate());
  job.part = 0;
  palette[3] = NAN;
  CHECK_FALSE(job.Run());
  std::unique_ptr<RuntimeOutput> out;
  OutputSpec spec;
  spec.level = 0;
  CHECK_FALSE(RuntimeOutput::Build(*rc, 0, spec, &out).ok());
  spec.level = 3;
  CHECK_FALSE(RuntimeOutput::Build(*rc, 5, spec, &out).ok());
  REQUIRE(RuntimeOutput::Build(*other, 0, spec, &out).ok());
  std::vector<float> pos(3 * out->num_vertices());
  EvaluateJob ej;
  ej.output = out.get();
  ej.instance = inst.get();  // an instance of another character
  ej.buffers.positions = pos.data();
  CHECK_FALSE(ej.Validate());
  CHECK(out->triangles().size() % 3 == 0);
  // Files: garbage, truncation, missing.
  std::unique_ptr<RuntimeCharacter> bad;
  Status s = RuntimeCharacter::FromBytes("garbage", "g.dsurf", &bad);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("g.dsurf") != std::string::npos);
  const std::string bytes = SerializeCharacter(ch);
  s = RuntimeCharacter::FromBytes(bytes.substr(0, bytes.size() / 2), "half.dsurf", &bad);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("half.dsurf") != std::string::npos);
  s = RuntimeCharacter::Load("/nonexistent/x.dsurf", &bad);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("/nonexistent/x.dsurf") != std::string::npos);
}

}  // namespace dermis
