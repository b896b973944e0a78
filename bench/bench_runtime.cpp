// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Runtime performance benchmark (docs/performance.md), every figure measured in the same run:
//
//  1. Per-sample evaluation on one control mesh (the Stanford bunny fitted with 540 control
//     vertices): Dermis' EvaluationPlan fast path (position + unit normal of the displaced
//     surface, Eq. 3-4) against OpenSubdiv 3.5's CPU limit stencils (position + first
//     derivatives of the Catmull-Clark limit surface of the same control mesh at the same
//     (face, u, v) locations), evaluated by Osd::CpuEvaluator::EvalStencils and by
//     Far::LimitStencilTable::UpdateValues/UpdateDerivs (the faster of the two is the baseline).
//     Also linear blend skinning (4 influences, positions + normals, float) of a mesh with the
//     same vertex count, and Dermis' scalar reference evaluator. Sample counts 10k -> 1M, threads
//     1 and 2.
//  2. A full frame of CesiumMan (pose -> sweep -> refit -> evaluate) for the bound vertices and
//     at tessellation levels 4 and 8, one thread and two.
//  Both tables have a GPU column when the build has dermis::gpu and the machine a Vulkan device
//  (the device is named): the same plan evaluated by the compute shader (docs/gpu.md), timed by
//  the device's timestamps around the dispatches (patch upload and pose excluded, as for the
//  CPU columns; the frame table adds the CPU pose).
//
// Prints a table and, with --json FILE, writes the same figures as JSON. Asserts nothing. Exit
// status 77 when the shared data is absent.
// Usage (from the repo root): bench_runtime [--data DIR] [--json FILE] [--quick]
//                                           [--gpu-device N | --no-gpu]
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/osd/bufferDescriptor.h>
#include <opensubdiv/osd/cpuEvaluator.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/core/parallel.h"
#include "dermis/deform/deformer.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/evaluation_plan.h"
#include "dermis/runtime/runtime.h"
#include "dermis/surface/surface_evaluator.h"
#if defined(DERMIS_BENCH_GPU)
#include "dermis/gpu/gpu.h"
#endif

using namespace dermis;
namespace Far = OpenSubdiv::Far;
namespace Osd = OpenSubdiv::Osd;

namespace {

using Clock = std::chrono::steady_clock;

// Median seconds per call of fn over `trials` trials, each repeating fn until it has run for
// at least min_seconds.
double TimePerCall(const std::function<void()>& fn, int trials, double min_seconds) {
  fn();  // warm up (page faults, caches)
  std::vector<double> t;
  for (int k = 0; k < trials; ++k) {
    int reps = 0;
    const auto start = Clock::now();
    double elapsed = 0.0;
    do {
      fn();
      ++reps;
      elapsed = std::chrono::duration<double>(Clock::now() - start).count();
    } while (elapsed < min_seconds);
    t.push_back(elapsed / reps);
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

struct Row {
  int level = 0;
  std::size_t samples = 0;
  int threads = 1;
  double dermis = 0.0;           // seconds per evaluation of all samples (best kernel)
  double generic = 0.0;          // the same with the portable kernel (1 thread only)
  double osd_eval = 0.0;         // Osd::CpuEvaluator::EvalStencils
  double osd_far = 0.0;          // Far::LimitStencilTable::UpdateValues + UpdateDerivs
  double lbs = 0.0;              // float LBS, 4 influences, positions + normals
  double scalar = 0.0;           // EvaluateSamples (double, reference), 1 thread, 0 if not run
  double gpu = 0.0;              // the compute shader's device time, 0 if not run
  double osd_stencil_cvs = 0.0;  // mean control vertices per OSD stencil
  std::size_t dermis_bytes = 0, osd_bytes = 0;
};

struct FrameRow {
  std::string output;
  std::size_t vertices = 0;
  int threads = 1;
  double pose = 0.0;      // PoseJob over every part (deform + refit + pack)
  double evaluate = 0.0;  // EvaluateJob over every part
  double gpu = 0.0;       // the compute shader's device time over every part, 0 if not run
};

// A float LBS baseline of n vertices: 4 influences each from `joints` joints, 3x4 matrices.
struct LbsMesh {
  std::vector<float> pos, nrm, out_pos, out_nrm, weights;
  std::vector<std::uint16_t> joints;
  std::vector<float> palette;  // 12 floats per joint (3x4, row-major)

  LbsMesh(std::size_t n, int num_joints) {
    pos.resize(3 * n);
    nrm.resize(3 * n);
    out_pos.resize(3 * n);
    out_nrm.resize(3 * n);
    weights.resize(4 * n);
    joints.resize(4 * n);
    std::uint64_t state = 12345;
    auto next = [&state]() {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return static_cast<float>(state >> 40) / 16777216.0f;
    };
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) pos[3 * i + k] = next();
      nrm[3 * i + 2] = 1.0f;
      float sum = 0.0f;
      for (int k = 0; k < 4; ++k) {
        joints[4 * i + k] = static_cast<std::uint16_t>(next() * static_cast<float>(num_joints - 1));
        weights[4 * i + k] = next() + 0.01f;
        sum += weights[4 * i + k];
      }
      for (int k = 0; k < 4; ++k) weights[4 * i + k] /= sum;
    }
    palette.resize(12 * static_cast<std::size_t>(num_joints));
    for (int j = 0; j < num_joints; ++j) {
      const float a = 0.01f * static_cast<float>(j);
      const float c = std::cos(a), s = std::sin(a);
      const float m[12] = {c, -s, 0, 0.1f, s, c, 0, 0.2f, 0, 0, 1, 0.3f};
      std::memcpy(&palette[12 * static_cast<std::size_t>(j)], m, sizeof(m));
    }
  }

  void Skin(std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      float m[12] = {};
      for (int k = 0; k < 4; ++k) {
        const float w = weights[4 * i + k];
        const float* p = &palette[12 * joints[4 * i + k]];
        for (int e = 0; e < 12; ++e) m[e] += w * p[e];
      }
      const float* x = &pos[3 * i];
      const float* n = &nrm[3 * i];
      for (int r = 0; r < 3; ++r) {
        out_pos[3 * i + r] =
            m[4 * r] * x[0] + m[4 * r + 1] * x[1] + m[4 * r + 2] * x[2] + m[4 * r + 3];
      }
      // Normal by the blended linear part (rigid palettes: its own inverse transpose), then
      // normalised, as a vertex shader does.
      float o[3];
      for (int r = 0; r < 3; ++r)
        o[r] = m[4 * r] * n[0] + m[4 * r + 1] * n[1] + m[4 * r + 2] * n[2];
      const float inv = 1.0f / std::sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
      for (int r = 0; r < 3; ++r) out_nrm[3 * i + r] = o[r] * inv;
    }
  }
};

struct OsdVertex {
  float x, y, z;
  void Clear() { x = y = z = 0.0f; }
  void AddWithWeight(const OsdVertex& s, float w) {
    x += w * s.x;
    y += w * s.y;
    z += w * s.z;
  }
};

std::unique_ptr<Far::TopologyRefiner> MakeRefiner(const MeshTopology& topo) {
  std::vector<int> verts_per_face(static_cast<std::size_t>(topo.num_faces()), 4);
  std::vector<int> indices;
  for (Index f = 0; f < topo.num_faces(); ++f) {
    for (int c = 0; c < 4; ++c) indices.push_back(topo.face_vertex(f, c));
  }
  Far::TopologyDescriptor desc;
  desc.numVertices = topo.num_vertices();
  desc.numFaces = topo.num_faces();
  desc.numVertsPerFace = verts_per_face.data();
  desc.vertIndicesPerFace = indices.data();
  OpenSubdiv::Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(OpenSubdiv::Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> r(
      Factory::Create(desc, Factory::Options(OpenSubdiv::Sdc::SCHEME_CATMARK, sdc)));
  if (r) r->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(3));
  return r;
}

#if defined(DERMIS_BENCH_GPU)
// One plan on the device: uploaded once, its patches written, the dispatches timed by the
// device's timestamps (median of `trials`, after one warm-up); 0 if anything fails.
double GpuSecondsPerCall(gpu::Context& ctx, const EvaluationPlan& plan, const float* packed,
                         int trials) {
  std::unique_ptr<gpu::Output> out;
  std::unique_ptr<gpu::Patches> patches;
  std::unique_ptr<gpu::Buffer> vertices;
  std::unique_ptr<gpu::Evaluation> eval;
  Status s = gpu::Output::Upload(ctx, plan, {}, &out);
  if (s.ok()) s = gpu::Patches::Create(ctx, plan.num_vertices(), 1, &patches);
  if (s.ok()) {
    s = gpu::Buffer::Create(ctx, std::max<std::size_t>(1, plan.num_samples()) * 24,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                            gpu::MemoryUse::kDevice, &vertices);
  }
  if (s.ok()) {
    gpu::Targets t;
    t.positions = {vertices->handle(), 0, 24};
    t.normals = {vertices->handle(), 12, 24};
    s = gpu::Evaluation::Create(ctx, *out, *patches, t, &eval);
  }
  if (!s.ok()) {
    std::fprintf(stderr, "bench_runtime: GPU: %s\n", s.message().c_str());
    return 0.0;
  }
  patches->Write(0, packed);
  std::vector<double> t;
  for (int k = 0; k <= trials; ++k) {
    double seconds = -1.0;
    s = ctx.Submit([&](VkCommandBuffer cmd) { eval->Record(cmd, 0); }, &seconds);
    if (!s.ok() || seconds < 0.0) return 0.0;
    if (k > 0) t.push_back(seconds);  // the first one warms up
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}
#endif

}  // namespace

int main(int argc, char** argv) {
  std::string data = "../shared/data";
  std::string json_path;
  bool quick = false, use_gpu = true;
  int gpu_device = -1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--data" && i + 1 < argc) {
      data = argv[++i];
    } else if (a == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else if (a == "--quick") {
      quick = true;
    } else if (a == "--gpu-device" && i + 1 < argc) {
      gpu_device = std::atoi(argv[++i]);
    } else if (a == "--no-gpu") {
      use_gpu = false;
    } else {
      std::fprintf(stderr,
                   "usage: bench_runtime [--data DIR] [--json FILE] [--quick] "
                   "[--gpu-device N | --no-gpu]\n");
      return 2;
    }
  }
  const int trials = quick ? 3 : 7;
  const double min_seconds = quick ? 0.02 : 0.1;
  const std::string bunny_path = data + "/scans/stanford-bunny.obj";
  const std::string cesium_path = data + "/gltf/CesiumMan.glb";
  if (!std::filesystem::exists(bunny_path) || !std::filesystem::exists(cesium_path)) {
    std::fprintf(stderr, "bench_runtime: %s or %s not found (pass --data DIR)\n",
                 bunny_path.c_str(), cesium_path.c_str());
    return 77;  // "skipped" for ctest's smoke run
  }
  std::printf("# bench_runtime: kernel %s, %u hardware threads\n", SimdPathName(SimdPath::kAuto),
              std::thread::hardware_concurrency());
  // The GPU column's device (the first of the best type, or --gpu-device).
  std::string gpu_name = "none";
#if defined(DERMIS_BENCH_GPU)
  std::unique_ptr<gpu::Context> gpu_ctx;
  if (use_gpu) {
    gpu::ContextOptions go;
    go.device_index = gpu_device;
    const Status gs = gpu::Context::Create(go, &gpu_ctx);
    if (!gs.ok()) {
      gpu_name = "none (" + gs.message() + ")";
    } else if (!gpu_ctx->has_timestamps()) {
      gpu_name = "none (" + gpu_ctx->device_name() + " has no timestamps on its compute queue)";
      gpu_ctx.reset();
    } else {
      gpu_name = gpu_ctx->device_name() + ", " + gpu_ctx->device_type();
    }
  }
#else
  (void)use_gpu;
  (void)gpu_device;
  gpu_name = "none (built without dermis::gpu)";
#endif
  std::printf("# GPU column: %s\n", gpu_name.c_str());

  // ---- Part 1: per-sample evaluation on the fitted bunny.
  PolygonMesh mesh;
  Index dropped = 0;
  Status s = ReadFitInput(bunny_path, &mesh, &dropped);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  FitInput input;
  input.points = mesh.positions;
  input.mesh = &mesh;
  input.points_dropped = dropped;
  FitOptions fo;
  fo.threads = 2;
  FittedSurface fitted;
  FitReport report;
  s = FitSurface(input, fo, &fitted, &report);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  const ManifoldDomain& domain = *fitted.surface.domain;
  const std::vector<Vec3>& control = fitted.surface.control.positions;
  std::vector<float> packed(control.size() * kPackedPatchStride);
  PackPatches(fitted.surface.patches.data(), control.size(), packed.data());
  std::unique_ptr<Far::TopologyRefiner> refiner = MakeRefiner(domain.topology());
  if (!refiner) {
    std::fprintf(stderr, "bench_runtime: OpenSubdiv refused the control mesh\n");
    return 1;
  }
  std::vector<float> cv(3 * control.size());
  for (std::size_t i = 0; i < control.size(); ++i) {
    for (int k = 0; k < 3; ++k) cv[3 * i + k] = static_cast<float>(control[i][k]);
  }
  std::printf("# bunny: %d control vertices, %d faces, %d displacement levels\n",
              domain.num_vertices(), domain.num_faces(), fitted.displacement->max_levels());

  std::vector<Row> rows;
  const std::vector<int> levels =
      quick ? std::vector<int>{5, 8} : std::vector<int>{5, 8, 16, 32, 44};
  for (int level : levels) {
    TessellationPattern pattern;
    if (!TessellationPattern::Build(domain.topology(), level, &pattern).ok()) return 1;
    const std::size_t n = pattern.samples.size();
    EvaluationPlan plan;
    EvaluationPlanOptions po;
    po.threads = 2;
    s = EvaluationPlan::Build(domain, fitted.displacement.get(), pattern.samples.data(), n, po,
                              &plan);
    if (!s.ok()) return 1;
    // OpenSubdiv at the same (face, u, v): one location array per face (ptex index = face).
    std::vector<std::vector<float>> us(static_cast<std::size_t>(domain.num_faces())), vs(us.size());
    std::vector<std::size_t> order;  // OSD stencil k -> sample index
    for (std::size_t i = 0; i < n; ++i) {
      us[static_cast<std::size_t>(pattern.samples[i].face)].push_back(
          static_cast<float>(pattern.samples[i].u));
      vs[static_cast<std::size_t>(pattern.samples[i].face)].push_back(
          static_cast<float>(pattern.samples[i].v));
    }
    Far::LimitStencilTableFactory::LocationArrayVec locs;
    for (std::size_t f = 0; f < us.size(); ++f) {
      if (us[f].empty()) continue;
      Far::LimitStencilTableFactory::LocationArray la;
      la.ptexIdx = static_cast<int>(f);
      la.numLocations = static_cast<int>(us[f].size());
      la.s = us[f].data();
      la.t = vs[f].data();
      locs.push_back(la);
    }
    std::unique_ptr<const Far::LimitStencilTable> table(
        Far::LimitStencilTableFactory::Create(*refiner, locs));
    if (!table || static_cast<std::size_t>(table->GetNumStencils()) != n) {
      std::fprintf(stderr, "bench_runtime: OpenSubdiv made %d stencils for %zu samples\n",
                   table ? table->GetNumStencils() : -1, n);
      return 1;
    }
    std::vector<float> out_p(3 * n), out_n(3 * n), osd_p(3 * n), osd_du(3 * n), osd_dv(3 * n);
    LbsMesh lbs(n, 64);
    const Osd::BufferDescriptor desc(0, 3, 3);
    for (int threads : {1, 2}) {
      Row r;
      r.level = level;
      r.samples = n;
      r.threads = threads;
      r.dermis_bytes = plan.memory_bytes();
      r.osd_bytes = (table->GetControlIndices().size() + table->GetWeights().size() +
                     table->GetDuWeights().size() + table->GetDvWeights().size()) *
                        4 +
                    (table->GetSizes().size() + table->GetOffsets().size()) * 4;
      r.osd_stencil_cvs =
          static_cast<double>(table->GetControlIndices().size()) / static_cast<double>(n);
      PlanOutputBuffers ob;
      ob.positions = out_p.data();
      ob.normals = out_n.data();
      r.dermis = TimePerCall(
          [&] {
            ParallelFor(threads, plan.num_blocks(), [&](std::size_t b, std::size_t e) {
              EvaluatePlan(plan, packed.data(), b, e, ob);
            });
          },
          trials, min_seconds);
      r.osd_eval = TimePerCall(
          [&] {
            ParallelFor(threads, n, [&](std::size_t b, std::size_t e) {
              Osd::CpuEvaluator::EvalStencils(
                  cv.data(), desc, osd_p.data(), desc, osd_du.data(), desc, osd_dv.data(), desc,
                  table->GetSizes().data(), table->GetOffsets().data(),
                  table->GetControlIndices().data(), table->GetWeights().data(),
                  table->GetDuWeights().data(), table->GetDvWeights().data(), static_cast<int>(b),
                  static_cast<int>(e));
            });
          },
          trials, min_seconds);
      const OsdVertex* src = reinterpret_cast<const OsdVertex*>(cv.data());
      r.osd_far = TimePerCall(
          [&] {
            ParallelFor(threads, n, [&](std::size_t b, std::size_t e) {
              table->UpdateValues(src, reinterpret_cast<OsdVertex*>(osd_p.data()),
                                  static_cast<int>(b), static_cast<int>(e));
              table->UpdateDerivs(src, reinterpret_cast<OsdVertex*>(osd_du.data()),
                                  reinterpret_cast<OsdVertex*>(osd_dv.data()), static_cast<int>(b),
                                  static_cast<int>(e));
            });
          },
          trials, min_seconds);
      r.lbs = TimePerCall(
          [&] { ParallelFor(threads, n, [&](std::size_t b, std::size_t e) { lbs.Skin(b, e); }); },
          trials, min_seconds);
      if (threads == 1 && SimdPathAvailable(SimdPath::kAvx2)) {
        r.generic = TimePerCall(
            [&] {
              EvaluatePlan(plan, packed.data(), 0, plan.num_blocks(), ob, SimdPath::kGeneric);
            },
            trials, min_seconds);
      }
#if defined(DERMIS_BENCH_GPU)
      if (threads == 1 && gpu_ctx) r.gpu = GpuSecondsPerCall(*gpu_ctx, plan, packed.data(), trials);
#endif
      if (threads == 1 && level <= 8) {
        std::vector<Vec3> rp(n), rn(n);
        r.scalar = TimePerCall(
            [&] {
              EvaluateSamples(domain, fitted.surface.patches.data(), fitted.displacement.get(),
                              pattern.samples.data(), n, rp.data(), rn.data());
            },
            1, min_seconds);
      }
      rows.push_back(r);
    }
  }

  std::printf(
      "\n## Per-sample evaluation, bunny (540 control vertices), Dermis position + normal "
      "vs OpenSubdiv limit stencils position + du + dv\n\n");
  std::printf(
      "| level | samples | threads | Dermis M/s | OSD CpuEvaluator M/s | OSD Far M/s | "
      "ratio Dermis/OSD (time) | LBS M/s | Dermis generic kernel M/s | Dermis scalar M/s | "
      "Dermis GPU M/s | OSD CVs/stencil | Dermis MB | OSD MB "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double osd = std::min(r.osd_eval, r.osd_far);
    const double ms = static_cast<double>(r.samples) * 1e-6;
    char scalar[32] = "-", generic[32] = "-", gpu_col[32] = "-";
    if (r.scalar > 0) std::snprintf(scalar, sizeof(scalar), "%.2f", ms / r.scalar);
    if (r.generic > 0) std::snprintf(generic, sizeof(generic), "%.1f", ms / r.generic);
    if (r.gpu > 0) std::snprintf(gpu_col, sizeof(gpu_col), "%.1f", ms / r.gpu);
    std::printf(
        "| %d | %zu | %d | %.1f | %.1f | %.1f | %.3f | %.1f | %s | %s | %s | %.1f | %.1f | %.1f "
        "|\n",
        r.level, r.samples, r.threads, ms / r.dermis, ms / r.osd_eval, ms / r.osd_far,
        r.dermis / osd, ms / r.lbs, generic, scalar, gpu_col, r.osd_stencil_cvs,
        static_cast<double>(r.dermis_bytes) / 1048576.0,
        static_cast<double>(r.osd_bytes) / 1048576.0);
  }
  std::printf("\nDermis GPU: %s (device time of the dispatches, 1 row per level)\n",
              gpu_name.c_str());

  // ---- Part 2: full frames of CesiumMan.
  Asset asset;
  s = ImportGltf(cesium_path, &asset);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  Character character;
  CharacterFitOptions cfo;
  cfo.fit.threads = 2;
  s = FitCharacter(asset, cfo, &character, nullptr);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  std::unique_ptr<RuntimeCharacter> rc;
  s = RuntimeCharacter::FromCharacter(std::move(character), &rc);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  std::unique_ptr<RuntimeInstance> inst;
  s = RuntimeInstance::Create(*rc, DeformerKind::kSweep, &inst);
  if (!s.ok()) {
    std::fprintf(stderr, "%s\n", s.message().c_str());
    return 1;
  }
  std::size_t control_total = 0;
  for (std::size_t p = 0; p < rc->num_parts(); ++p) control_total += rc->num_control_vertices(p);
  std::printf("\n# CesiumMan: %zu fitted parts, %zu control vertices, %zu joints\n",
              rc->num_parts(), control_total, rc->num_joints(0));
  // Joint palettes of 30 frames of the first clip (the engine's animation system; not timed).
  const Asset& a = rc->character().asset;
  std::vector<std::vector<float>> palettes;
  for (int f = 0; f < 30; ++f) {
    AssetPose pose;
    SamplePose(a, 0, 0.05 * f, &pose);
    std::vector<glm::dmat4> world, joints;
    ComputeWorldMatrices(a, pose, &world);
    ComputeJointMatrices(a.skins[0], world, &joints);
    std::vector<float> pal(16 * joints.size());
    for (std::size_t j = 0; j < joints.size(); ++j) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) pal[16 * j + 4 * c + r] = static_cast<float>(joints[j][c][r]);
      }
    }
    palettes.push_back(std::move(pal));
  }
  std::vector<FrameRow> frames;
  struct Spec {
    const char* name;
    OutputSpec spec;
  };
  std::vector<Spec> specs = {{"bound", {OutputKind::kBound, 0, -1, 2}},
                             {"level 4", {OutputKind::kLevel, 4, -1, 2}},
                             {"level 8", {OutputKind::kLevel, 8, -1, 2}}};
  for (const Spec& sp : specs) {
    std::vector<std::unique_ptr<RuntimeOutput>> outs;
    std::size_t verts = 0;
    for (std::size_t p = 0; p < rc->num_parts(); ++p) {
      std::unique_ptr<RuntimeOutput> o;
      if (!RuntimeOutput::Build(*rc, p, sp.spec, &o).ok()) return 1;
      verts += o->num_vertices();
      outs.push_back(std::move(o));
    }
    std::vector<std::vector<float>> buf(outs.size());
    for (std::size_t p = 0; p < outs.size(); ++p) buf[p].resize(6 * outs[p]->num_vertices());
    for (int threads : {1, 2}) {
      FrameRow fr;
      fr.output = sp.name;
      fr.vertices = verts;
      fr.threads = threads;
      std::size_t frame = 0;
      auto pose = [&] {
        const std::vector<float>& pal = palettes[frame++ % palettes.size()];
        for (std::size_t p = 0; p < rc->num_parts(); ++p) {
          PoseJob job;
          job.instance = inst.get();
          job.part = p;
          job.skin_matrices = pal.data();
          job.num_skin_matrices = rc->num_joints(p);
          job.Run();
        }
      };
      auto evaluate = [&] {
        for (std::size_t p = 0; p < outs.size(); ++p) {
          ParallelFor(threads, outs[p]->plan().num_blocks(), [&](std::size_t b, std::size_t e) {
            EvaluateJob job;
            job.output = outs[p].get();
            job.instance = inst.get();
            job.block_begin = b;
            job.block_end = e;
            job.buffers.positions = buf[p].data();
            job.buffers.normals = buf[p].data() + 3;
            job.buffers.position_stride = job.buffers.normal_stride = 6 * sizeof(float);
            job.Run();
          });
        }
      };
      fr.pose = TimePerCall(pose, trials, min_seconds);
      fr.evaluate = TimePerCall(evaluate, trials, min_seconds);
#if defined(DERMIS_BENCH_GPU)
      if (threads == 1 && gpu_ctx) {
        double sum = 0.0;
        bool all = true;
        for (std::size_t p = 0; p < outs.size(); ++p) {
          const double g = GpuSecondsPerCall(*gpu_ctx, outs[p]->plan(),
                                             inst->packed_patches(outs[p]->part()), trials);
          all = all && g > 0.0;
          sum += g;
        }
        fr.gpu = all ? sum : 0.0;
      }
#endif
      frames.push_back(fr);
    }
  }
  std::printf("\n## Full frame, CesiumMan (pose -> sweep -> refit -> evaluate)\n\n");
  std::printf(
      "| output | vertices | threads | pose + sweep + refit ms | evaluate ms | frame ms | "
      "output M vertices/s | GPU evaluate ms | GPU frame ms (CPU pose + GPU) |\n"
      "|---|---|---|---|---|---|---|---|---|\n");
  for (const FrameRow& f : frames) {
    const double total = f.pose + f.evaluate;
    char gpu_eval[32] = "-", gpu_frame[32] = "-";
    if (f.gpu > 0) {
      std::snprintf(gpu_eval, sizeof(gpu_eval), "%.3f", f.gpu * 1e3);
      std::snprintf(gpu_frame, sizeof(gpu_frame), "%.3f", (f.pose + f.gpu) * 1e3);
    }
    std::printf("| %s | %zu | %d | %.3f | %.3f | %.3f | %.1f | %s | %s |\n", f.output.c_str(),
                f.vertices, f.threads, f.pose * 1e3, f.evaluate * 1e3, total * 1e3,
                static_cast<double>(f.vertices) * 1e-6 / total, gpu_eval, gpu_frame);
  }

  // The deformers alone on CesiumMan's control vertices (part 0), over the same 30 palettes:
  // the sweep against DQS in the same process, whose ratio survives a busy machine better than
  // either time (docs/deformation.md, "Cost").
  double deform_s[3] = {0.0, 0.0, 0.0};
  {
    const CharacterPart& part = rc->character().parts[0];
    const std::size_t n = part.surface.rest_positions.size();
    std::vector<VertexWeights> w(n);
    for (std::size_t i = 0; i < n; ++i) {
      w[i].joints = part.control_joints[i];
      w[i].weights = part.control_weights[i];
    }
    std::vector<std::vector<glm::dmat4>> dpal;
    for (const std::vector<float>& pal : palettes) {
      std::vector<glm::dmat4> d(pal.size() / 16);
      for (std::size_t j = 0; j < d.size(); ++j) {
        for (int c = 0; c < 4; ++c) {
          for (int r = 0; r < 4; ++r) d[j][c][r] = static_cast<double>(pal[16 * j + 4 * c + r]);
        }
      }
      dpal.push_back(std::move(d));
    }
    std::vector<Vec3> out(n);
    const DeformerKind kinds[3] = {DeformerKind::kLbs, DeformerKind::kDqs, DeformerKind::kSweep};
    for (int k = 0; k < 3; ++k) {
      std::unique_ptr<Deformer> d;
      if (!MakeDeformer(kinds[k], *rc->rig(0), part.surface.rest_positions.data(), nullptr,
                        w.data(), n, &d)
               .ok()) {
        return 1;
      }
      std::size_t frame = 0;
      deform_s[k] = TimePerCall(
          [&] {
            d->SetPose(dpal[frame++ % dpal.size()].data());
            d->Deform(0, n, out.data(), nullptr);
          },
          trials, min_seconds);
    }
    std::printf(
        "\nDeformers alone (SetPose + Deform of the %zu control vertices, one thread): LBS %.3f "
        "ms, DQS %.3f ms, sweep %.3f ms (%.2f x DQS)\n",
        n, deform_s[0] * 1e3, deform_s[1] * 1e3, deform_s[2] * 1e3, deform_s[2] / deform_s[1]);
  }

  if (!json_path.empty()) {
    std::FILE* j = std::fopen(json_path.c_str(), "w");
    if (!j) {
      std::fprintf(stderr, "bench_runtime: cannot write %s\n", json_path.c_str());
      return 1;
    }
    std::string gpu_json;  // the device name as a JSON string
    for (char ch : gpu_name) {
      if (ch == '"' || ch == '\\') gpu_json += '\\';
      if (static_cast<unsigned char>(ch) >= 0x20) gpu_json += ch;
    }
    std::fprintf(j,
                 "{\n  \"version\": 1,\n  \"kernel\": \"%s\",\n  \"gpu_device\": \"%s\",\n"
                 "  \"per_sample\": [\n",
                 SimdPathName(SimdPath::kAuto), gpu_json.c_str());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      std::fprintf(j,
                   "    {\"level\": %d, \"samples\": %zu, \"threads\": %d, \"dermis_s\": %.9g, "
                   "\"osd_cpu_evaluator_s\": %.9g, \"osd_far_s\": %.9g, \"lbs_s\": %.9g, "
                   "\"dermis_generic_s\": %.9g, \"dermis_scalar_s\": %.9g, \"gpu_s\": %.9g, "
                   "\"ratio\": %.6f, "
                   "\"osd_cvs_per_stencil\": %.3f, "
                   "\"dermis_bytes\": %zu, \"osd_bytes\": %zu}%s\n",
                   r.level, r.samples, r.threads, r.dermis, r.osd_eval, r.osd_far, r.lbs, r.generic,
                   r.scalar, r.gpu, r.dermis / std::min(r.osd_eval, r.osd_far), r.osd_stencil_cvs,
                   r.dermis_bytes, r.osd_bytes, i + 1 < rows.size() ? "," : "");
    }
    std::fprintf(j, "  ],\n  \"frames\": [\n");
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const FrameRow& f = frames[i];
      std::fprintf(j,
                   "    {\"output\": \"%s\", \"vertices\": %zu, \"threads\": %d, \"pose_s\": %.9g, "
                   "\"evaluate_s\": %.9g, \"gpu_evaluate_s\": %.9g, \"vertices_per_s\": %.6g}%s\n",
                   f.output.c_str(), f.vertices, f.threads, f.pose, f.evaluate, f.gpu,
                   static_cast<double>(f.vertices) / (f.pose + f.evaluate),
                   i + 1 < frames.size() ? "," : "");
    }
    std::fprintf(j, "  ]\n}\n");
    std::fclose(j);
  }
  return 0;
}
