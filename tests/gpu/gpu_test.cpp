// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The Vulkan compute evaluation (dermis::gpu, docs/gpu.md) against the CPU fast path
// (EvaluatePlan / EvaluateJob) and the double-precision scalar evaluator: built-in control
// meshes with every special case, the fitted Stanford bunny at level 8 through several poses,
// and every shared Khronos character at its bound vertices and at level 8 through frames of its
// first clip. Bounds (issue 18): 1e-5 of the bounding-box diagonal for positions, 1e-4 for unit
// normals. Runs on whatever Vulkan device the machine has (Mesa's lavapipe on the build
// machines), with the Khronos validation layer when it is installed (no message allowed).
// Without a Vulkan device the tests say so and skip; with DERMIS_GPU_REQUIRED=1 (CI) they fail.
#include "dermis/gpu/gpu.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/dermis.h"
#include "dermis/dermis_gpu.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/gpu/shader_interface.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/evaluation_plan.h"
#include "dermis/runtime/runtime.h"
#include "dermis/surface/surface_evaluator.h"
#include "test_meshes.h"

namespace dermis {
namespace {

const std::string kData = "../shared/data";

bool GpuRequired() {
  const char* e = std::getenv("DERMIS_GPU_REQUIRED");
  return e && std::string(e) == "1";
}

// One context for the whole executable (device creation and pipeline compilation are the slow
// part on lavapipe), with the validation layer when it is installed.
struct SharedContext {
  std::unique_ptr<gpu::Context> context;
  Status status;
  SharedContext() {
    gpu::ContextOptions o;
    o.validation = true;
    status = gpu::Context::Create(o, &context);
  }
};

SharedContext& Shared() {
  static SharedContext s;
  return s;
}

// The context, or null after saying why the test is skipped (a failure under
// DERMIS_GPU_REQUIRED=1).
gpu::Context* Gpu() {
  SharedContext& s = Shared();
  if (s.context) return s.context.get();
  if (GpuRequired()) {
    FAIL("DERMIS_GPU_REQUIRED=1 but no Vulkan device: " << s.status.message());
  }
  WARN("SKIPPED: no Vulkan device: " << s.status.message());
  return nullptr;
}

// No validation message so far (when the layer is active; CI installs it and must use it).
void CheckValidation(const gpu::Context& c) {
  if (GpuRequired()) CHECK(c.validation_enabled());
  INFO("validation: " << c.last_validation_message());
  CHECK(c.validation_messages() == 0);
}

double Diagonal(const float* p, std::size_t n, std::size_t stride_floats) {
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[i * stride_floats + k]);
      hi[k] = std::max(hi[k], p[i * stride_floats + k]);
    }
  }
  double d = 0.0;
  for (int k = 0; k < 3; ++k) d += (double(hi[k]) - lo[k]) * (double(hi[k]) - lo[k]);
  return std::sqrt(d);
}

struct Difference {
  double position = 0.0;      // max |gpu - cpu| / bounding-box diagonal
  double normal = 0.0;        // max |gpu - cpu| of unit normals
  std::size_t vertices = 0;   // compared
  std::size_t identical = 0;  // of which all 6 floats have the same bits
  bool finite = true;

  void Merge(const Difference& o) {
    position = std::max(position, o.position);
    normal = std::max(normal, o.normal);
    vertices += o.vertices;
    identical += o.identical;
    finite = finite && o.finite;
  }
  // The bounds of issue 18.
  bool ok() const { return finite && position < 1e-5 && normal < 1e-4; }
};

std::ostream& operator<<(std::ostream& os, const Difference& d) {
  return os << "position " << d.position << " of the diagonal, normal " << d.normal << ", "
            << d.identical << " of " << d.vertices << " vertices bit-identical";
}

// Interleaved position + normal (6 floats per vertex) against the same from the CPU.
Difference Compare(const std::vector<float>& gpu, const std::vector<float>& cpu) {
  REQUIRE(gpu.size() == cpu.size());
  const std::size_t n = cpu.size() / 6;
  const double diag = std::max(Diagonal(cpu.data(), n, 6), 1e-30);
  Difference d;
  for (std::size_t i = 0; i < n; ++i) {
    double dp = 0.0, dn = 0.0;
    for (int k = 0; k < 3; ++k) {
      d.finite = d.finite && std::isfinite(gpu[6 * i + k]) && std::isfinite(gpu[6 * i + 3 + k]);
      dp += std::pow(double(gpu[6 * i + k]) - cpu[6 * i + k], 2);
      dn += std::pow(double(gpu[6 * i + 3 + k]) - cpu[6 * i + 3 + k], 2);
    }
    d.position = std::max(d.position, std::sqrt(dp) / diag);
    d.normal = std::max(d.normal, std::sqrt(dn));
    d.identical += std::memcmp(&gpu[6 * i], &cpu[6 * i], 6 * sizeof(float)) == 0;
  }
  d.vertices = n;
  return d;
}

PlanOutputBuffers Interleaved(std::vector<float>* v) {
  PlanOutputBuffers o;
  o.positions = v->data();
  o.normals = v->data() + 3;
  o.position_stride = o.normal_stride = 6 * sizeof(float);
  return o;
}

// The plan evaluated on the device through Output + Patches + Evaluation into a host-visible
// buffer with an engine-like layout: 40-byte vertices starting 8 bytes into the buffer, the
// position at +0 and the normal at +16 of each vertex (the rest of each vertex is the engine's
// and must stay untouched). Returns position + normal per vertex, and checks the untouched
// bytes.
class PlanOnGpu {
 public:
  PlanOnGpu(gpu::Context& c, const EvaluationPlan& plan, std::size_t max_chunk_blocks = 0)
      : context_(c), n_(plan.num_samples()) {
    gpu::OutputOptions oo;
    oo.max_chunk_blocks = max_chunk_blocks;
    REQUIRE(gpu::Output::Upload(c, plan, oo, &output_).ok());
    REQUIRE(gpu::Patches::Create(c, plan.num_vertices(), 2, &patches_).ok());
    const VkDeviceSize bytes = kBase + std::max<std::size_t>(n_, 1) * kStride;
    REQUIRE(gpu::Buffer::Create(c, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                gpu::MemoryUse::kReadback, &target_)
                .ok());
    gpu::Targets t;
    t.positions = {target_->handle(), kBase, kStride};
    t.normals = {target_->handle(), kBase + 16, kStride};
    const Status s = gpu::Evaluation::Create(c, *output_, *patches_, t, &evaluation_);
    INFO(s.message());
    REQUIRE(s.ok());
  }

  std::vector<float> Run(const float* packed, std::uint32_t slot) {
    REQUIRE(patches_->Write(slot, packed));
    float* f = static_cast<float*>(target_->mapped());
    std::fill(f, f + target_->size() / sizeof(float), kSentinel);
    bool recorded = false;  // (no REQUIRE inside: the library is built without exceptions)
    const Status s = context_.Submit([&](VkCommandBuffer cmd) {
      recorded = evaluation_->Record(cmd, slot);
      VkMemoryBarrier mb{};
      mb.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
      mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
      mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
      vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                           1, &mb, 0, nullptr, 0, nullptr);
    });
    INFO(s.message());
    REQUIRE(s.ok());
    REQUIRE(recorded);
    std::vector<float> out(6 * n_);
    std::size_t untouched_bad = 0;
    for (std::size_t i = 0; i < n_; ++i) {
      const float* v = f + (kBase + i * kStride) / sizeof(float);
      std::copy(v, v + 3, &out[6 * i]);
      std::copy(v + 4, v + 7, &out[6 * i + 3]);
      untouched_bad += v[3] != kSentinel;
      for (std::size_t k = 7; k < kStride / sizeof(float); ++k) untouched_bad += v[k] != kSentinel;
    }
    CHECK(f[0] == kSentinel);
    CHECK(f[1] == kSentinel);
    CHECK(untouched_bad == 0);
    return out;
  }

  const gpu::Output& output() const { return *output_; }
  std::size_t dispatches() const { return evaluation_->dispatch_count(); }

 private:
  static constexpr VkDeviceSize kBase = 8;
  static constexpr std::uint32_t kStride = 40;
  static constexpr float kSentinel = -12345.0f;
  gpu::Context& context_;
  std::size_t n_;
  std::unique_ptr<gpu::Output> output_;
  std::unique_ptr<gpu::Patches> patches_;
  std::unique_ptr<gpu::Buffer> target_;
  std::unique_ptr<gpu::Evaluation> evaluation_;
};

std::vector<float> CpuPlan(const EvaluationPlan& plan, const float* packed, SimdPath path) {
  std::vector<float> out(6 * plan.num_samples(), NAN);
  REQUIRE(EvaluatePlan(plan, packed, 0, plan.num_blocks(), Interleaved(&out), path));
  return out;
}

// GPU against the CPU fast path: against the portable kernel, whose arithmetic the shader
// repeats operation for operation (`precise`), every bound of issue 18 holds; against the
// fastest kernel of this CPU (AVX2 + FMA, which fuses multiply-adds), positions do, and its
// normal differences are reported (docs/gpu.md, section 8).
struct Versus {
  Difference portable, fastest;
  void Merge(const Versus& o) {
    portable.Merge(o.portable);
    fastest.Merge(o.fastest);
  }
  bool ok() const { return portable.ok() && fastest.finite && fastest.position < 1e-5; }
};

std::ostream& operator<<(std::ostream& os, const Versus& v) {
  os << "GPU - CPU (" << SimdPathName(SimdPath::kGeneric) << ") " << v.portable;
  if (BestSimdPath() != SimdPath::kGeneric) {
    os << "; GPU - CPU (" << SimdPathName(BestSimdPath()) << ") " << v.fastest;
  }
  return os;
}

Versus CompareWithCpu(const std::vector<float>& gpu, const EvaluationPlan& plan,
                      const float* packed) {
  Versus v;
  v.portable = Compare(gpu, CpuPlan(plan, packed, SimdPath::kGeneric));
  v.fastest = Compare(gpu, CpuPlan(plan, packed, BestSimdPath()));
  return v;
}

std::vector<float> Pack(const std::vector<LocalPatch>& patches) {
  std::vector<float> packed(patches.size() * kPackedPatchStride);
  PackPatches(patches.data(), patches.size(), packed.data());
  return packed;
}

// Samples with every special case (as tests/runtime/runtime_test.cpp): the level-7 grid,
// random points, the one-chart squares near corners, edges and corners.
std::vector<SampleLocation> TestSamples(const ManifoldDomain& domain) {
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(domain.topology(), 7, &pattern).ok());
  std::vector<SampleLocation> s = pattern.samples;
  test::Lcg rng(11);
  for (Index f = 0; f < domain.num_faces(); ++f) {
    for (int k = 0; k < 9; ++k) s.push_back({f, rng.Next(), rng.Next()});
    s.push_back({f, 0.004, 0.003});
    s.push_back({f, 0.998, 0.0});
    s.push_back({f, 1.0, 1.0});
  }
  return s;
}

// Column-major float palettes of a part's skin at a pose.
std::vector<float> Palette(const Asset& asset, Index skin, const AssetPose& pose) {
  if (skin == kInvalidIndex) return {};
  std::vector<glm::dmat4> world, joints;
  ComputeWorldMatrices(asset, pose, &world);
  ComputeJointMatrices(asset.skins[static_cast<std::size_t>(skin)], world, &joints);
  std::vector<float> pal(16 * joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) {
    for (int c = 0; c < 4; ++c) {
      for (int r = 0; r < 4; ++r) pal[16 * j + 4 * c + r] = static_cast<float>(joints[j][c][r]);
    }
  }
  return pal;
}

}  // namespace

TEST_CASE("gpu: the shader interface is the plan's documented layout") {
  std::size_t words = 0;
  const std::uint32_t* spirv = gpu::EvaluateShaderSpirv(&words);
  REQUIRE(words > 100);
  CHECK(spirv[0] == 0x07230203u);  // SPIR-V magic
  CHECK(spirv[1] == 0x00010000u);  // SPIR-V 1.0 (Vulkan 1.0)
  std::size_t c_words = 0;
  CHECK(dermis_gpu_shader_spirv(&c_words) == spirv);
  CHECK(c_words == words);
  // Binding 0 is read as 32-bit words: chart[4], index[lanes], dominant[lanes], count,
  // displaced (docs/gpu.md).
  CHECK(offsetof(PlanBlock, chart) == 0);
  CHECK(offsetof(PlanBlock, index) == 16);
  CHECK(offsetof(PlanBlock, dominant) == 16 + 4 * kPlanLanes);
  CHECK(offsetof(PlanBlock, count) == 16 + 8 * kPlanLanes);
  CHECK(offsetof(PlanBlock, displaced) == 20 + 8 * kPlanLanes);
  CHECK(gpu::kPlanBlockBytes == 88);
  CHECK(gpu::kPlanBlockDataBytes == 1536);
  CHECK(gpu::kPackedPatchBytes == 128);
  CHECK(gpu::WorkgroupCount(0) == 0);
  CHECK(gpu::WorkgroupCount(8) == 1);
  CHECK(gpu::WorkgroupCount(9) == 2);
}

TEST_CASE("gpu: built-in surfaces with every special case match the CPU and the reference") {
  gpu::Context* c = Gpu();
  if (!c) return;
  INFO("device: " << c->device_name());
  // Valences 3 to 7, boundaries, a perturbed control mesh, a displacement that differs per
  // chart and none at all; split into many small chunks once (the path of plans larger than
  // maxStorageBufferRange) with identical bytes.
  for (const char* name : {"house", "prism7", "torus"}) {
    ControlSurface cs = test::Build(test::Builtin(name));
    std::vector<Vec3> moved = cs.control.positions;
    test::Lcg rng(5);
    for (Vec3& p : moved) p += Vec3(rng.Uniform(-0.05, 0.05), rng.Uniform(-0.05, 0.05), 0.0);
    std::vector<LocalPatch> patches(moved.size());
    cs.domain->FitPatches(moved.data(), patches.data());
    const std::vector<float> packed = Pack(patches);
    const test::WavyDisplacement wavy(0.04);
    const std::vector<SampleLocation> samples = TestSamples(*cs.domain);
    for (const Displacement* disp :
         {static_cast<const Displacement*>(&wavy), static_cast<const Displacement*>(nullptr)}) {
      EvaluationPlan plan;
      REQUIRE(
          EvaluationPlan::Build(*cs.domain, disp, samples.data(), samples.size(), {}, &plan).ok());
      PlanOnGpu whole(*c, plan);
      const std::vector<float> gpu_out = whole.Run(packed.data(), 1);
      const Versus d = CompareWithCpu(gpu_out, plan, packed.data());
      // The double-precision reference.
      std::vector<Vec3> ref(samples.size()), ref_n(samples.size());
      REQUIRE(EvaluateSamples(*cs.domain, patches.data(), disp, samples.data(), samples.size(),
                              ref.data(), ref_n.data()));
      std::vector<float> ref_f(6 * samples.size());
      for (std::size_t i = 0; i < samples.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
          ref_f[6 * i + k] = static_cast<float>(ref[i][k]);
          ref_f[6 * i + 3 + k] = static_cast<float>(ref_n[i][k]);
        }
      }
      const Difference r = Compare(gpu_out, ref_f);
      INFO(name << (disp ? " displaced" : " domain") << ", " << samples.size() << " samples: " << d
                << "; GPU - scalar reference " << r);
      CHECK(d.ok());
      CHECK(d.fastest.normal < 1e-4);  // regular surfaces: every kernel within the bound
      CHECK(r.ok());
      WARN(name << (disp ? " displaced" : " domain") << ", " << samples.size() << " samples: " << d
                << "; GPU - scalar reference " << r);
      // Many chunks of 2 blocks: the same bytes.
      PlanOnGpu chunked(*c, plan, 2);
      CHECK(chunked.output().chunks().size() == (plan.num_blocks() + 1) / 2);
      CHECK(chunked.dispatches() == chunked.output().chunks().size());
      const std::vector<float> chunk_out = chunked.Run(packed.data(), 0);
      CHECK(std::memcmp(chunk_out.data(), gpu_out.data(), gpu_out.size() * sizeof(float)) == 0);
    }
  }
  CheckValidation(*c);
}

TEST_CASE("gpu: the fitted bunny at level 8 through several poses", "[data]") {
  const std::string path = kData + "/scans/bunny-npm-1839v.obj";
  if (!std::filesystem::exists(path)) {
    WARN("SKIPPED: " << path << " not found (the shared data is absent)");
    return;
  }
  gpu::Context* c = Gpu();
  if (!c) return;
  PolygonMesh mesh;
  Index dropped = 0;
  REQUIRE(ReadFitInput(path, &mesh, &dropped).ok());
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  input.points_dropped = dropped;
  FitOptions fo;
  fo.control_vertices = 200;
  fo.threads = 2;
  FittedSurface fitted;
  REQUIRE(FitSurface(input, fo, &fitted, nullptr).ok());
  const ManifoldDomain& domain = *fitted.surface.domain;
  TessellationPattern pattern;
  REQUIRE(TessellationPattern::Build(domain.topology(), 8, &pattern).ok());
  EvaluationPlan plan;
  REQUIRE(EvaluationPlan::Build(domain, fitted.displacement.get(), pattern.samples.data(),
                                pattern.samples.size(), {}, &plan)
              .ok());
  PlanOnGpu gpu_plan(*c, plan);
  // The rest pose, then the control vertices twisted about the vertical axis and squashed
  // (patches refitted each time, as PoseJob does), alternating the two patch slots.
  const std::vector<Vec3>& rest = fitted.surface.control.positions;
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : rest) lo = glm::min(lo, p), hi = glm::max(hi, p);
  for (int frame = 0; frame < 3; ++frame) {
    std::vector<Vec3> posed(rest.size());
    for (std::size_t i = 0; i < rest.size(); ++i) {
      const Vec3 q = rest[i] - 0.5 * (lo + hi);
      const double t = (q.y / (hi.y - lo.y)) * 1.2 * frame;
      posed[i] = Vec3(std::cos(t) * q.x - std::sin(t) * q.z, q.y * (1.0 - 0.1 * frame),
                      std::sin(t) * q.x + std::cos(t) * q.z);
    }
    std::vector<LocalPatch> patches(posed.size());
    domain.FitPatches(posed.data(), patches.data());
    const std::vector<float> packed = Pack(patches);
    const Versus d = CompareWithCpu(
        gpu_plan.Run(packed.data(), static_cast<std::uint32_t>(frame % 2)), plan, packed.data());
    INFO("bunny level 8 (" << plan.num_samples() << " vertices) pose " << frame << ": " << d);
    CHECK(d.ok());
    WARN("bunny level 8 pose " << frame << ": " << d);
  }
  CheckValidation(*c);
}

namespace {

// Fits a shared character, and compares GPU and CPU at every part's bound vertices and level 8
// through frames of its first clip (sweep deformer, the engine's order: pose, then evaluate).
void CompareCharacter(const std::string& file) {
  const std::string path = kData + "/gltf/" + file;
  if (!std::filesystem::exists(path)) {
    WARN("SKIPPED: " << path << " not found (the shared data is absent)");
    return;
  }
  gpu::Context* c = Gpu();
  if (!c) return;
  Asset asset;
  REQUIRE(ImportGltf(path, &asset).ok());
  CharacterFitOptions cfo;
  cfo.fit.threads = 2;
  Character ch;
  REQUIRE(FitCharacter(asset, cfo, &ch, nullptr).ok());
  std::unique_ptr<RuntimeCharacter> rc;
  REQUIRE(RuntimeCharacter::FromCharacter(std::move(ch), &rc).ok());
  REQUIRE(rc->num_parts() > 0);
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kSweep, &inst).ok());
  struct Out {
    std::unique_ptr<RuntimeOutput> cpu;
    std::unique_ptr<gpu::ReadbackEvaluator> gpu;
    Versus worst;
  };
  std::vector<Out> outs;
  for (std::size_t p = 0; p < rc->num_parts(); ++p) {
    for (OutputKind kind : {OutputKind::kBound, OutputKind::kLevel}) {
      OutputSpec spec;
      spec.kind = kind;
      spec.level = 8;
      spec.threads = 2;
      Out o;
      REQUIRE(RuntimeOutput::Build(*rc, p, spec, &o.cpu).ok());
      const Status s = gpu::ReadbackEvaluator::Create(*c, *o.cpu, {}, &o.gpu);
      INFO(s.message());
      REQUIRE(s.ok());
      outs.push_back(std::move(o));
    }
  }
  const Asset& a = rc->character().asset;
  const int clip = a.animations.empty() ? -1 : 0;
  const double duration = clip >= 0 ? a.animations[0].Duration() : 0.0;
  const int frames = 4;
  std::size_t vertices = 0;
  for (int f = 0; f < frames; ++f) {
    AssetPose pose;
    if (clip >= 0) {
      SamplePose(a, clip, duration * f / (frames - 1), &pose);
    } else {
      RestPose(a, &pose);
    }
    for (std::size_t p = 0; p < rc->num_parts(); ++p) {
      const std::vector<float> pal = Palette(a, rc->character().parts[p].skin, pose);
      PoseJob job;
      job.instance = inst.get();
      job.part = p;
      job.skin_matrices = pal.empty() ? nullptr : pal.data();
      job.num_skin_matrices = pal.size() / 16;
      REQUIRE(job.Run());
    }
    vertices = 0;
    for (Out& o : outs) {
      const std::size_t n = o.cpu->num_vertices();
      vertices += n;
      std::vector<float> gpu_out(6 * n, NAN);
      const Status s = o.gpu->Run(*inst, Interleaved(&gpu_out));
      INFO(s.message());
      REQUIRE(s.ok());
      Versus v;
      for (SimdPath kernel : {SimdPath::kGeneric, BestSimdPath()}) {
        std::vector<float> cpu(6 * n, NAN);
        EvaluateJob ej;
        ej.output = o.cpu.get();
        ej.instance = inst.get();
        ej.buffers = Interleaved(&cpu);
        ej.path = kernel;
        REQUIRE(ej.Run());
        (kernel == SimdPath::kGeneric ? v.portable : v.fastest) = Compare(gpu_out, cpu);
      }
      o.worst.Merge(v);
    }
  }
  for (const Out& o : outs) {
    const char* kind = o.cpu->spec().kind == OutputKind::kBound ? "bound" : "level 8";
    INFO(file << " part " << o.cpu->part() << " " << kind << " (" << o.cpu->num_vertices()
              << " vertices), " << frames << " frames of clip " << clip << ": " << o.worst);
    CHECK(o.worst.ok());
    WARN(file << " part " << o.cpu->part() << " " << kind << " (" << o.cpu->num_vertices()
              << " vertices), " << frames << " frames: " << o.worst);
  }
  CHECK(vertices > 0);
  CheckValidation(*c);
}

}  // namespace

TEST_CASE("gpu: SimpleSkin through its clip at bound and level 8", "[data]") {
  CompareCharacter("SimpleSkin.gltf");
}
TEST_CASE("gpu: RiggedSimple through its clip at bound and level 8", "[data]") {
  CompareCharacter("RiggedSimple.glb");
}
TEST_CASE("gpu: RiggedFigure through its clip at bound and level 8", "[data]") {
  CompareCharacter("RiggedFigure.glb");
}
TEST_CASE("gpu: Fox through its clip at bound and level 8", "[data]") {
  CompareCharacter("Fox.glb");
}
TEST_CASE("gpu: CesiumMan through its clip at bound and level 8", "[data][heavy]") {
  CompareCharacter("CesiumMan.glb");
}

TEST_CASE("gpu: bad requests fail with a message and record nothing") {
  gpu::Context* c = Gpu();
  if (!c) return;
  const Character& ch = test::FittedCylinders();
  std::unique_ptr<RuntimeCharacter> rc, other;
  REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "a.dsurf", &rc).ok());
  REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "b.dsurf", &other).ok());
  std::unique_ptr<RuntimeInstance> inst;
  REQUIRE(RuntimeInstance::Create(*other, DeformerKind::kLbs, &inst).ok());
  OutputSpec spec;
  spec.level = 3;
  std::unique_ptr<RuntimeOutput> out0;
  REQUIRE(RuntimeOutput::Build(*rc, 0, spec, &out0).ok());
  std::unique_ptr<gpu::Output> g0;
  REQUIRE(gpu::Output::Upload(*c, *out0, {}, &g0).ok());
  std::unique_ptr<gpu::Patches> p1;
  REQUIRE(gpu::Patches::Create(*c, rc->num_control_vertices(0) + 1, 1, &p1).ok());
  std::unique_ptr<gpu::Buffer> buf;
  REQUIRE(gpu::Buffer::Create(*c, 1 << 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                              gpu::MemoryUse::kReadback, &buf)
              .ok());
  gpu::Targets t;
  t.positions = {buf->handle(), 0, 24};
  std::unique_ptr<gpu::Evaluation> e;
  Status s = gpu::Evaluation::Create(*c, *g0, *p1, t, &e);  // patches of another surface
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("control vertices") != std::string::npos);
  std::unique_ptr<gpu::Patches> p0;
  REQUIRE(gpu::Patches::Create(*c, rc->num_control_vertices(0), 1, &p0).ok());
  t.positions.stride = 8;  // below 12 bytes
  s = gpu::Evaluation::Create(*c, *g0, *p0, t, &e);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("stride") != std::string::npos);
  t.positions = {buf->handle(), 2, 24};  // not a multiple of 4
  CHECK_FALSE(gpu::Evaluation::Create(*c, *g0, *p0, t, &e).ok());
  t.positions = {VK_NULL_HANDLE, 0, 24};
  CHECK_FALSE(gpu::Evaluation::Create(*c, *g0, *p0, t, &e).ok());
  t.positions = {buf->handle(), 0, 24};
  REQUIRE(gpu::Evaluation::Create(*c, *g0, *p0, t, &e).ok());
  CHECK_FALSE(e->Record(VK_NULL_HANDLE, 0));
  CHECK_FALSE(p0->Write(1, inst->packed_patches(0)));  // one slot only
  CHECK_FALSE(p0->Write(0, static_cast<const float*>(nullptr)));
  CHECK_FALSE(p0->Write(0, *inst, 7));  // no part 7
  CHECK_FALSE(p1->Write(0, *inst, 0));  // another control-vertex count
  CHECK_FALSE(gpu::Patches::Create(*c, 0, 1, &p1).ok());
  CHECK_FALSE(
      gpu::Buffer::Create(*c, 0, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::MemoryUse::kDevice, &buf)
          .ok());
  // An instance of another character, and bad host buffers.
  std::unique_ptr<gpu::ReadbackEvaluator> r;
  REQUIRE(gpu::ReadbackEvaluator::Create(*c, *out0, {}, &r).ok());
  std::vector<float> v(6 * r->num_vertices());
  s = r->Run(*inst, Interleaved(&v));
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("another character") != std::string::npos);
  PlanOutputBuffers bad = Interleaved(&v);
  bad.position_stride = 4;
  CHECK_FALSE(r->Run(inst->packed_patches(0), bad).ok());
  CHECK_FALSE(r->Run(static_cast<const float*>(nullptr), Interleaved(&v)).ok());
  // A device index out of range names the count.
  std::unique_ptr<gpu::Context> none;
  gpu::ContextOptions o;
  o.device_index = 99;
  s = gpu::Context::Create(o, &none);
  CHECK_FALSE(s.ok());
  CHECK(s.message().find("99") != std::string::npos);
  CheckValidation(*c);
}

TEST_CASE("gpu: every Vulkan object is destroyed") {
  // The validation layer lists, when a device is destroyed, every object made from it that
  // still exists: a context of its own, used and destroyed, must draw no message.
  if (!Gpu()) return;
  struct Log {
    std::size_t count = 0;
    std::string last;
  } log;
  {
    gpu::ContextOptions o;
    o.validation = true;
    o.validation_callback = [](const char* message, void* user) {
      Log* l = static_cast<Log*>(user);
      ++l->count;
      l->last = message;
    };
    o.validation_user = &log;
    std::unique_ptr<gpu::Context> c;
    REQUIRE(gpu::Context::Create(o, &c).ok());
    if (GpuRequired()) CHECK(c->validation_enabled());
    const Character& ch = test::FittedCylinders();
    std::unique_ptr<RuntimeCharacter> rc;
    REQUIRE(RuntimeCharacter::FromBytes(SerializeCharacter(ch), "c.dsurf", &rc).ok());
    std::unique_ptr<RuntimeInstance> inst;
    REQUIRE(RuntimeInstance::Create(*rc, DeformerKind::kSweep, &inst).ok());
    OutputSpec spec;
    spec.level = 2;
    std::unique_ptr<RuntimeOutput> out;
    REQUIRE(RuntimeOutput::Build(*rc, 0, spec, &out).ok());
    std::unique_ptr<gpu::ReadbackEvaluator> r;
    REQUIRE(gpu::ReadbackEvaluator::Create(*c, *out, {}, &r).ok());
    std::vector<float> v(6 * r->num_vertices());
    double seconds = 0.0;
    REQUIRE(r->Run(*inst, Interleaved(&v), &seconds).ok());
    CHECK((seconds >= 0.0 || !c->has_timestamps()));
    r.reset();
    out.reset();
  }
  INFO("validation: " << log.last);
  CHECK(log.count == 0);
}

TEST_CASE("gpu: the C API evaluates like dermis_evaluate") {
  if (!Gpu()) return;
  const std::string bytes = SerializeCharacter(test::FittedCylinders());
  dermis_character* character = nullptr;
  REQUIRE(dermis_character_load_memory(bytes.data(), bytes.size(), "cyl.dsurf", &character) ==
          DERMIS_OK);
  dermis_instance* instance = nullptr;
  REQUIRE(dermis_instance_create(character, DERMIS_DEFORMER_SWEEP, &instance) == DERMIS_OK);
  dermis_gpu_context* context = nullptr;
  const dermis_status cs = dermis_gpu_context_create(-1, &context);
  INFO(dermis_last_error());
  REQUIRE(cs == DERMIS_OK);
  CHECK(std::strlen(dermis_gpu_device_name(context)) > 0);
  const size_t joints = dermis_character_joint_count(character, 0);
  std::vector<float> palette(16 * joints, 0.0f);
  for (size_t j = 0; j < joints; ++j) {
    const float angle = 0.3f * static_cast<float>(j + 1);  // rotations about z
    palette[16 * j + 0] = palette[16 * j + 5] = std::cos(angle);
    palette[16 * j + 1] = std::sin(angle);
    palette[16 * j + 4] = -std::sin(angle);
    palette[16 * j + 10] = palette[16 * j + 15] = 1.0f;
  }
  for (size_t part = 0; part < dermis_character_part_count(character); ++part) {
    REQUIRE(dermis_instance_pose(instance, part, palette.data(), joints) == DERMIS_OK);
    dermis_output_desc desc;
    dermis_output_desc_init(&desc);
    desc.level = 5;
    dermis_output* output = nullptr;
    REQUIRE(dermis_output_create(character, part, &desc, &output) == DERMIS_OK);
    dermis_gpu_output* g = nullptr;
    REQUIRE(dermis_gpu_output_create(context, output, &g) == DERMIS_OK);
    const size_t n = dermis_output_vertex_count(output);
    std::vector<float> cpu(6 * n), gpu_out(6 * n);
    REQUIRE(dermis_evaluate(instance, output, 0, SIZE_MAX, cpu.data(), 24, cpu.size() * 4,
                            cpu.data() + 3, 24, cpu.size() * 4 - 12) == DERMIS_OK);
    REQUIRE(dermis_gpu_evaluate(g, instance, gpu_out.data(), 24, gpu_out.data() + 3, 24) ==
            DERMIS_OK);
    const Difference d = Compare(gpu_out, cpu);
    INFO("part " << part << ": " << d);
    // dermis_evaluate runs the fastest CPU kernel: as against it in Versus, positions are held
    // to the bound and normals are not (AVX2's fused multiply-adds move a normal where the
    // derivatives nearly vanish; the shader equals the portable kernel, checked above).
    if (BestSimdPath() == SimdPath::kGeneric) {
      CHECK(d.ok());
    } else {
      CHECK(d.finite);
      CHECK(d.position < 1e-5);
    }
    // The accessors an engine with its own device uploads from.
    const void* blocks = nullptr;
    const float* data = nullptr;
    size_t block_bytes = 0, data_bytes = 0;
    REQUIRE(dermis_output_plan(output, &blocks, &block_bytes, &data, &data_bytes) == DERMIS_OK);
    CHECK(block_bytes == dermis_output_block_count(output) * gpu::kPlanBlockBytes);
    CHECK(data_bytes == dermis_output_block_count(output) * gpu::kPlanBlockDataBytes);
    const float* patches = nullptr;
    size_t floats = 0;
    REQUIRE(dermis_instance_packed_patches(instance, part, &patches, &floats) == DERMIS_OK);
    CHECK(floats == 32 * dermis_character_control_vertex_count(character, part));
    // Bad calls.
    CHECK(dermis_gpu_evaluate(g, instance, nullptr, 24, nullptr, 0) ==
          DERMIS_ERROR_INVALID_ARGUMENT);
    CHECK(std::strlen(dermis_last_error()) > 0);
    CHECK(dermis_gpu_evaluate(nullptr, instance, gpu_out.data(), 24, nullptr, 0) ==
          DERMIS_ERROR_INVALID_ARGUMENT);
    CHECK(dermis_instance_packed_patches(instance, 9, &patches, &floats) ==
          DERMIS_ERROR_INVALID_ARGUMENT);
    dermis_gpu_output_destroy(g);
    dermis_output_destroy(output);
  }
  CHECK(dermis_gpu_output_create(context, nullptr, nullptr) == DERMIS_ERROR_INVALID_ARGUMENT);
  dermis_gpu_context* none = nullptr;
  CHECK(dermis_gpu_context_create(99, &none) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(none == nullptr);
  CHECK(std::string(dermis_last_error()).find("99") != std::string::npos);
  dermis_gpu_context_destroy(context);
  dermis_gpu_context_destroy(nullptr);
  dermis_instance_destroy(instance);
  dermis_character_destroy(character);
}

}  // namespace dermis
