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
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/patchMap.h>
#include <opensubdiv/far/patchTable.h>
#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/osd/bufferDescriptor.h>
#include <opensubdiv/osd/cpuEvaluator.h>
#include <opensubdiv/osd/cpuPatchTable.h>
#include <opensubdiv/osd/types.h>
#include <opensubdiv/version.h>

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
namespace Bfr = OpenSubdiv::Bfr;

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

// Median seconds per call of each of `fns`, their trials interleaved (trial k of every
// contender before trial k + 1 of any), so that a load that comes and goes on a shared machine
// weighs on every contender alike; each trial repeats its fn for at least min_seconds.
std::vector<double> TimeAlternating(const std::vector<std::function<void()>>& fns, int trials,
                                    double min_seconds) {
  std::vector<std::vector<double>> t(fns.size());
  for (const auto& fn : fns) fn();  // warm up
  for (int k = 0; k < trials; ++k) {
    for (std::size_t c = 0; c < fns.size(); ++c) {
      int reps = 0;
      const auto start = Clock::now();
      double elapsed = 0.0;
      do {
        fns[c]();
        ++reps;
        elapsed = std::chrono::duration<double>(Clock::now() - start).count();
      } while (elapsed < min_seconds);
      t[c].push_back(elapsed / reps);
    }
  }
  std::vector<double> median;
  for (std::vector<double>& v : t) {
    std::sort(v.begin(), v.end());
    median.push_back(v[v.size() / 2]);
  }
  return median;
}

struct Row {
  int level = 0;
  std::size_t samples = 0;
  int threads = 1;
  double dermis = 0.0;           // seconds per evaluation of all samples (best kernel)
  double generic = 0.0;          // the same with the portable kernel (1 thread only)
  double osd_eval = 0.0;         // Osd::CpuEvaluator::EvalStencils
  double osd_far = 0.0;          // Far::LimitStencilTable::UpdateValues + UpdateDerivs
  double osd_patch = 0.0;        // refined points by EvalStencils + Osd::CpuEvaluator::EvalPatches
  double osd_bfr = 0.0;          // Bfr::Surface PreparePatchPoints + Evaluate
  double osd_points = 0.0;       // of osd_patch: the refined and local points alone
  double lbs = 0.0;              // float LBS, 4 influences, positions + normals
  double scalar = 0.0;           // EvaluateSamples (double, reference), 1 thread, 0 if not run
  double gpu = 0.0;              // the compute shader's device time, 0 if not run
  double osd_stencil_cvs = 0.0;  // mean control vertices per OSD stencil
  std::size_t dermis_bytes = 0, osd_bytes = 0, osd_patch_bytes = 0, osd_bfr_bytes = 0;
  double best_osd() const {
    return std::min(std::min(osd_eval, osd_far), std::min(osd_patch, osd_bfr));
  }
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

// `adaptive`: refined adaptively to isolation level 3 (limit stencils, patch table); otherwise
// the base level only (Bfr).
std::unique_ptr<Far::TopologyRefiner> MakeRefiner(const MeshTopology& topo, bool adaptive) {
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
  if (r && adaptive) r->RefineAdaptive(Far::TopologyRefiner::AdaptiveOptions(3));
  return r;
}

// Bytes of a stencil table's arrays (sizes, offsets, indices, weights and, for limit stencils,
// du and dv weights).
std::size_t StencilBytes(const Far::StencilTable& t) {
  return (t.GetSizes().size() + t.GetOffsets().size() + t.GetControlIndices().size() +
          t.GetWeights().size()) *
         4;
}

// OpenSubdiv's patch-table evaluation of the limit surface (the path of its own examples and
// of Osd's GPU evaluators), set up once per control mesh: Far::PatchTableFactory on the
// adaptively refined mesh (isolation 3, Gregory-basis end caps: OpenSubdiv's defaults), the
// stencils of every refined and local (end-cap) point factorised to the control vertices, one
// vertex buffer [control | refined | local points] and Osd::CpuPatchTable's flat arrays. Per
// frame the control vertices move: Osd::CpuEvaluator::EvalStencils recomputes the refined and
// local points, then Osd::CpuEvaluator::EvalPatches evaluates position + du + dv at the
// samples' Osd::PatchCoord (found once by Far::PatchMap).
struct OsdPatchEval {
  std::unique_ptr<const Far::PatchTable> table;
  std::unique_ptr<const Far::StencilTable> stencils;  // refined + local points
  std::unique_ptr<Osd::CpuPatchTable> cpu;
  std::unique_ptr<Far::PatchMap> map;
  std::vector<float> vertices;  // 3 floats per control, refined and local point
  int num_control = 0;

  bool Build(const Far::TopologyRefiner& refiner, const std::vector<float>& cv) {
    Far::PatchTableFactory::Options po(3);
    po.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    table.reset(Far::PatchTableFactory::Create(refiner, po));
    if (!table) return false;
    Far::StencilTableFactory::Options so;
    so.generateOffsets = true;
    so.generateIntermediateLevels = true;
    std::unique_ptr<const Far::StencilTable> refined(Far::StencilTableFactory::Create(refiner, so));
    if (!refined) return false;
    if (const Far::StencilTable* local = table->GetLocalPointStencilTable()) {
      stencils.reset(
          Far::StencilTableFactory::AppendLocalPointStencilTable(refiner, refined.get(), local));
    } else {
      stencils = std::move(refined);
    }
    if (!stencils) return false;
    cpu.reset(Osd::CpuPatchTable::Create(table.get()));
    map = std::make_unique<Far::PatchMap>(*table);
    num_control = refiner.GetLevel(0).GetNumVertices();
    vertices.assign(3 * (static_cast<std::size_t>(num_control) +
                         static_cast<std::size_t>(stencils->GetNumStencils())),
                    0.0f);
    std::copy(cv.begin(), cv.end(), vertices.begin());
    return true;
  }

  // Per-frame state and tables (the patch map is a setup-time search structure, not counted).
  std::size_t bytes() const {
    return StencilBytes(*stencils) + vertices.size() * 4 +
           cpu->GetNumPatchArrays() * sizeof(Osd::PatchArray) + cpu->GetPatchIndexSize() * 4 +
           cpu->GetPatchParamSize() * sizeof(Osd::PatchParam);
  }

  // Refined and local points of stencils [b, e) from the control vertices.
  void UpdatePoints(std::size_t b, std::size_t e) {
    Osd::CpuEvaluator::EvalStencils(vertices.data(), Osd::BufferDescriptor(0, 3, 3),
                                    vertices.data(), Osd::BufferDescriptor(3 * num_control, 3, 3),
                                    &stencils->GetSizes()[0], &stencils->GetOffsets()[0],
                                    &stencils->GetControlIndices()[0], &stencils->GetWeights()[0],
                                    static_cast<int>(b), static_cast<int>(e));
  }

  // Samples [b, e) of `coords` into 3-float position, du and dv arrays (indexed like coords).
  void Evaluate(const Osd::PatchCoord* coords, std::size_t b, std::size_t e, float* p, float* du,
                float* dv) const {
    const Osd::BufferDescriptor d(0, 3, 3);
    Osd::CpuEvaluator::EvalPatches(vertices.data(), d, p + 3 * b, d, du + 3 * b, d, dv + 3 * b, d,
                                   static_cast<int>(e - b), coords + b, cpu->GetPatchArrayBuffer(),
                                   cpu->GetPatchIndexBuffer(), cpu->GetPatchParamBuffer());
  }
};

// OpenSubdiv's Bfr (3.5): one Bfr::Surface per face, made once by Bfr::RefinerSurfaceFactory
// (irregular faces approximated to level 3, as the patch table's isolation, instead of Bfr's
// default 2, so that the three OpenSubdiv evaluators give the same surface; the factory caches
// their patch trees); per frame each face's patch points are prepared from the control vertices and
// its samples evaluated (position + du + dv).
struct BfrEval {
  std::unique_ptr<Far::TopologyRefiner> refiner;  // base level only
  std::unique_ptr<Bfr::RefinerSurfaceFactory<>> factory;
  std::vector<Bfr::Surface<float>> surfaces;
  std::vector<std::size_t> point_offset;  // per face: first float in patch_points
  std::vector<float> patch_points;

  bool Build(std::unique_ptr<Far::TopologyRefiner> r) {
    refiner = std::move(r);
    Bfr::RefinerSurfaceFactory<>::Options fo;
    fo.SetApproxLevelSmooth(3);  // as the patch table's isolation level
    factory = std::make_unique<Bfr::RefinerSurfaceFactory<>>(*refiner, fo);
    const int faces = refiner->GetLevel(0).GetNumFaces();
    surfaces.resize(static_cast<std::size_t>(faces));
    point_offset.resize(surfaces.size() + 1, 0);
    for (int f = 0; f < faces; ++f) {
      Bfr::Surface<float>& sf = surfaces[static_cast<std::size_t>(f)];
      if (!factory->InitVertexSurface(f, &sf) || !sf.IsValid()) return false;
      point_offset[static_cast<std::size_t>(f) + 1] =
          point_offset[static_cast<std::size_t>(f)] +
          3 * static_cast<std::size_t>(sf.GetNumPatchPoints());
    }
    patch_points.assign(point_offset.back(), 0.0f);
    return true;
  }

  // The surfaces' control indices and patch points (the factory's cache of irregular patch
  // trees, shared by the surfaces, is not counted).
  std::size_t bytes() const {
    std::size_t b = surfaces.size() * sizeof(Bfr::Surface<float>) + patch_points.size() * 4;
    for (const Bfr::Surface<float>& sf : surfaces) {
      b += static_cast<std::size_t>(sf.GetNumControlPoints()) * 4;
    }
    return b;
  }

  // Faces [fb, fe): samples of face f are uv[2k..] for k in [first[f], first[f + 1]), written
  // at the same index k of p, du, dv.
  void Evaluate(const float* cv, const std::vector<std::size_t>& first, const float* uv,
                std::size_t fb, std::size_t fe, float* p, float* du, float* dv) {
    const Bfr::Surface<float>::PointDescriptor d(3);
    for (std::size_t f = fb; f < fe; ++f) {
      float* pp = patch_points.data() + point_offset[f];
      surfaces[f].PreparePatchPoints(cv, d, pp, d);
      for (std::size_t k = first[f]; k < first[f + 1]; ++k) {
        surfaces[f].Evaluate(uv + 2 * k, pp, d, p + 3 * k, du + 3 * k, dv + 3 * k);
      }
    }
  }
};

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

// The control vertices' skin weights of `part`, as the deformers take them.
std::vector<VertexWeights> ControlWeights(const CharacterPart& part) {
  std::vector<VertexWeights> w(part.surface.rest_positions.size());
  for (std::size_t i = 0; i < w.size(); ++i) {
    w[i].joints = part.control_joints[i];
    w[i].weights = part.control_weights[i];
  }
  return w;
}

// Column-major float joint palettes (16 floats per joint) as double matrices.
std::vector<std::vector<glm::dmat4>> DoublePalettes(
    const std::vector<std::vector<float>>& palettes) {
  std::vector<std::vector<glm::dmat4>> out;
  for (const std::vector<float>& pal : palettes) {
    std::vector<glm::dmat4> d(pal.size() / 16);
    for (std::size_t j = 0; j < d.size(); ++j) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) d[j][c][r] = static_cast<double>(pal[16 * j + 4 * c + r]);
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

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
  std::unique_ptr<Far::TopologyRefiner> refiner = MakeRefiner(domain.topology(), true);
  std::unique_ptr<Far::TopologyRefiner> base_refiner = MakeRefiner(domain.topology(), false);
  if (!refiner || !base_refiner) {
    std::fprintf(stderr, "bench_runtime: OpenSubdiv refused the control mesh\n");
    return 1;
  }
  std::vector<float> cv(3 * control.size());
  for (std::size_t i = 0; i < control.size(); ++i) {
    for (int k = 0; k < 3; ++k) cv[3 * i + k] = static_cast<float>(control[i][k]);
  }
  OsdPatchEval osd_patches;
  BfrEval bfr;
  if (!osd_patches.Build(*refiner, cv) || !bfr.Build(std::move(base_refiner))) {
    std::fprintf(stderr, "bench_runtime: OpenSubdiv's patch table or Bfr surfaces failed\n");
    return 1;
  }
  double diagonal = 0.0;  // of the control points' bounding box, for the agreement check
  {
    Vec3 lo = control[0], hi = control[0];
    for (const Vec3& c : control) {
      lo = glm::min(lo, c);
      hi = glm::max(hi, c);
    }
    diagonal = glm::length(hi - lo);
  }
  std::printf(
      "# bunny: %d control vertices, %d faces, %d displacement levels; OpenSubdiv patch table: "
      "%d patches, %d refined and local points\n",
      domain.num_vertices(), domain.num_faces(), fitted.displacement->max_levels(),
      osd_patches.table->GetNumPatchesTotal(), osd_patches.stencils->GetNumStencils());

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
    const Osd::BufferDescriptor desc(0, 3, 3);
    // The patch-table and Bfr evaluators take the samples in the stencils' order (face by
    // face): `first[f]` is face f's first, `uv` their (u, v), `coords` their patch coordinates.
    std::vector<std::size_t> first(us.size() + 1, 0);
    std::vector<float> uv;
    std::vector<Osd::PatchCoord> coords;
    uv.reserve(2 * n);
    coords.reserve(n);
    for (std::size_t f = 0; f < us.size(); ++f) {
      first[f + 1] = first[f] + us[f].size();
      for (std::size_t k = 0; k < us[f].size(); ++k) {
        uv.push_back(us[f][k]);
        uv.push_back(vs[f][k]);
        const Far::PatchTable::PatchHandle* h =
            osd_patches.map->FindPatch(static_cast<int>(f), us[f][k], vs[f][k]);
        if (!h) {
          std::fprintf(stderr, "bench_runtime: no OpenSubdiv patch at face %zu\n", f);
          return 1;
        }
        coords.emplace_back(*h, us[f][k], vs[f][k]);
      }
    }
    const std::size_t num_points = static_cast<std::size_t>(osd_patches.stencils->GetNumStencils());
    // The three OpenSubdiv evaluators give the same limit surface: check it once per level
    // (largest position difference against the limit stencils, over the bounding-box diagonal),
    // so that a wrong setup cannot pass for a fast one.
    {
      std::vector<float> sp(3 * n), sdu(3 * n), sdv(3 * n), pp(3 * n), pdu(3 * n), pdv(3 * n),
          bp(3 * n), bdu(3 * n), bdv(3 * n);
      Osd::CpuEvaluator::EvalStencils(cv.data(), desc, sp.data(), desc, sdu.data(), desc,
                                      sdv.data(), desc, table->GetSizes().data(),
                                      table->GetOffsets().data(), table->GetControlIndices().data(),
                                      table->GetWeights().data(), table->GetDuWeights().data(),
                                      table->GetDvWeights().data(), 0, static_cast<int>(n));
      osd_patches.UpdatePoints(0, num_points);
      osd_patches.Evaluate(coords.data(), 0, n, pp.data(), pdu.data(), pdv.data());
      bfr.Evaluate(cv.data(), first, uv.data(), 0, us.size(), bp.data(), bdu.data(), bdv.data());
      double dp = 0.0, db = 0.0;
      for (std::size_t i = 0; i < 3 * n; ++i) {
        dp = std::max(dp, static_cast<double>(std::fabs(pp[i] - sp[i])));
        db = std::max(db, static_cast<double>(std::fabs(bp[i] - sp[i])));
      }
      std::printf(
          "# level %d: OpenSubdiv's evaluators agree: EvalPatches %.2g, Bfr %.2g of the diagonal "
          "from the limit stencils (largest position difference)\n",
          level, dp / diagonal, db / diagonal);
      if (!(dp <= 1e-5 * diagonal && db <= 1e-5 * diagonal)) {
        std::fprintf(stderr, "bench_runtime: OpenSubdiv's evaluators disagree\n");
        return 1;
      }
    }
    LbsMesh lbs(n, 64);
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
      r.osd_patch_bytes = osd_patches.bytes() + coords.size() * sizeof(Osd::PatchCoord);
      r.osd_bfr_bytes = bfr.bytes() + uv.size() * 4 + first.size() * sizeof(std::size_t);
      r.osd_stencil_cvs =
          static_cast<double>(table->GetControlIndices().size()) / static_cast<double>(n);
      PlanOutputBuffers ob;
      ob.positions = out_p.data();
      ob.normals = out_n.data();
      const OsdVertex* src = reinterpret_cast<const OsdVertex*>(cv.data());
      // Every contender of the row, interleaved (the patch table's refined-point update alone
      // too, to show how much of its time it is).
      const std::vector<double> t = TimeAlternating(
          {[&] {
             ParallelFor(threads, plan.num_blocks(), [&](std::size_t b, std::size_t e) {
               EvaluatePlan(plan, packed.data(), b, e, ob);
             });
           },
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
           [&] {
             ParallelFor(threads, num_points,
                         [&](std::size_t b, std::size_t e) { osd_patches.UpdatePoints(b, e); });
             ParallelFor(threads, n, [&](std::size_t b, std::size_t e) {
               osd_patches.Evaluate(coords.data(), b, e, osd_p.data(), osd_du.data(),
                                    osd_dv.data());
             });
           },
           [&] {
             ParallelFor(threads, us.size(), [&](std::size_t b, std::size_t e) {
               bfr.Evaluate(cv.data(), first, uv.data(), b, e, osd_p.data(), osd_du.data(),
                            osd_dv.data());
             });
           },
           [&] {
             ParallelFor(threads, n, [&](std::size_t b, std::size_t e) {
               table->UpdateValues(src, reinterpret_cast<OsdVertex*>(osd_p.data()),
                                   static_cast<int>(b), static_cast<int>(e));
               table->UpdateDerivs(src, reinterpret_cast<OsdVertex*>(osd_du.data()),
                                   reinterpret_cast<OsdVertex*>(osd_dv.data()), static_cast<int>(b),
                                   static_cast<int>(e));
             });
           },
           [&] { ParallelFor(threads, n, [&](std::size_t b, std::size_t e) { lbs.Skin(b, e); }); },
           [&] {
             ParallelFor(threads, num_points,
                         [&](std::size_t b, std::size_t e) { osd_patches.UpdatePoints(b, e); });
           }},
          trials, min_seconds);
      r.dermis = t[0];
      r.osd_eval = t[1];
      r.osd_patch = t[2];
      r.osd_bfr = t[3];
      r.osd_far = t[4];
      r.lbs = t[5];
      r.osd_points = t[6];
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
      "\n## Per-sample evaluation, bunny (%d control vertices), Dermis position + normal "
      "vs OpenSubdiv %d.%d.%d limit surface position + du + dv\n\n",
      domain.num_vertices(), OPENSUBDIV_VERSION_MAJOR, OPENSUBDIV_VERSION_MINOR,
      OPENSUBDIV_VERSION_PATCH);
  std::printf(
      "| level | samples | threads | Dermis M/s | OSD stencils CpuEvaluator M/s | OSD stencils "
      "Far M/s | OSD EvalPatches M/s | of which refined points | OSD Bfr M/s | ratio Dermis/best "
      "OSD (time) | LBS M/s | "
      "Dermis generic kernel M/s | Dermis scalar M/s | Dermis GPU M/s | OSD CVs/stencil | "
      "bytes/sample Dermis | stencils | patches | Bfr "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double ms = static_cast<double>(r.samples) * 1e-6;
    const double per = 1.0 / static_cast<double>(r.samples);
    char scalar[32] = "-", generic[32] = "-", gpu_col[32] = "-";
    if (r.scalar > 0) std::snprintf(scalar, sizeof(scalar), "%.2f", ms / r.scalar);
    if (r.generic > 0) std::snprintf(generic, sizeof(generic), "%.1f", ms / r.generic);
    if (r.gpu > 0) std::snprintf(gpu_col, sizeof(gpu_col), "%.1f", ms / r.gpu);
    std::printf(
        "| %d | %zu | %d | %.1f | %.1f | %.1f | %.1f | %.0f %% | %.1f | %.3f | %.1f | %s | %s | %s "
        "| %.1f | "
        "%.0f | %.0f | %.0f | %.0f |\n",
        r.level, r.samples, r.threads, ms / r.dermis, ms / r.osd_eval, ms / r.osd_far,
        ms / r.osd_patch, 100.0 * r.osd_points / r.osd_patch, ms / r.osd_bfr,
        r.dermis / r.best_osd(), ms / r.lbs, generic, scalar, gpu_col, r.osd_stencil_cvs,
        static_cast<double>(r.dermis_bytes) * per, static_cast<double>(r.osd_bytes) * per,
        static_cast<double>(r.osd_patch_bytes) * per, static_cast<double>(r.osd_bfr_bytes) * per);
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
    const std::vector<VertexWeights> w = ControlWeights(part);
    const std::vector<std::vector<glm::dmat4>> dpal = DoublePalettes(palettes);
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

  // Where the bound output's frame goes (part 0, one thread, interleaved): the sweep (SetPose +
  // Deform of the control vertices), the refit of every local patch (Eq. 2), the packing, and
  // the evaluation of the bound vertices, with how full its 8-lane blocks are.
  double bound_split[4] = {0.0, 0.0, 0.0, 0.0};
  std::size_t bound_blocks = 0, bound_lanes = 0, bound_faces = 0;
  {
    const CharacterPart& part = rc->character().parts[0];
    const std::size_t n = part.surface.rest_positions.size();
    const ManifoldDomain& dom = *part.surface.domain;
    const std::vector<VertexWeights> w = ControlWeights(part);
    const std::vector<std::vector<glm::dmat4>> dpal = DoublePalettes(palettes);
    std::unique_ptr<Deformer> d;
    if (!MakeDeformer(DeformerKind::kSweep, *rc->rig(0), part.surface.rest_positions.data(),
                      nullptr, w.data(), n, &d)
             .ok()) {
      return 1;
    }
    std::unique_ptr<RuntimeOutput> bound;
    if (!RuntimeOutput::Build(*rc, 0, {OutputKind::kBound, 0, -1, 2}, &bound).ok()) return 1;
    const EvaluationPlan& bp = bound->plan();
    bound_blocks = bp.num_blocks();
    std::vector<char> face_seen(static_cast<std::size_t>(dom.num_faces()), 0);
    for (std::size_t b = 0; b < bp.num_blocks(); ++b) {
      bound_lanes += static_cast<std::size_t>(bp.blocks()[b].count);
    }
    for (const SampleLocation& l : rc->bound_locations(0)) {
      bound_faces += face_seen[static_cast<std::size_t>(l.face)] ? 0 : 1;
      face_seen[static_cast<std::size_t>(l.face)] = 1;
    }
    std::vector<Vec3> ctrl(n);
    std::vector<LocalPatch> patches(n);
    std::vector<float> pk(n * kPackedPatchStride);
    std::vector<float> vb(6 * bound->num_vertices());
    std::size_t frame = 0;
    d->SetPose(dpal[0].data());
    d->Deform(0, n, ctrl.data(), nullptr);
    dom.FitPatches(ctrl.data(), patches.data());
    PackPatches(patches.data(), n, pk.data());
    PlanOutputBuffers ob;
    ob.positions = vb.data();
    ob.normals = vb.data() + 3;
    ob.position_stride = ob.normal_stride = 6 * sizeof(float);
    const std::vector<double> t =
        TimeAlternating({[&] {
                           d->SetPose(dpal[frame++ % dpal.size()].data());
                           d->Deform(0, n, ctrl.data(), nullptr);
                         },
                         [&] { dom.FitPatches(ctrl.data(), patches.data()); },
                         [&] { PackPatches(patches.data(), n, pk.data()); },
                         [&] { EvaluatePlan(bp, pk.data(), 0, bp.num_blocks(), ob); }},
                        trials, min_seconds);
    for (int k = 0; k < 4; ++k) bound_split[k] = t[static_cast<std::size_t>(k)];
    std::printf(
        "\nBound output of part 0 (%zu vertices on %zu of %d faces, %zu control vertices): %zu "
        "blocks, %.0f %% of their lanes used; one thread: sweep %.3f ms, refit %.3f ms, pack "
        "%.3f ms, evaluate %.3f ms\n",
        bound->num_vertices(), bound_faces, dom.num_faces(), n, bound_blocks,
        100.0 * static_cast<double>(bound_lanes) / static_cast<double>(8 * bound_blocks),
        t[0] * 1e3, t[1] * 1e3, t[2] * 1e3, t[3] * 1e3);
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
                   "\"osd_cpu_evaluator_s\": %.9g, \"osd_far_s\": %.9g, \"osd_eval_patches_s\": "
                   "%.9g, \"osd_bfr_s\": %.9g, \"lbs_s\": %.9g, "
                   "\"dermis_generic_s\": %.9g, \"dermis_scalar_s\": %.9g, \"gpu_s\": %.9g, "
                   "\"ratio\": %.6f, "
                   "\"osd_cvs_per_stencil\": %.3f, "
                   "\"dermis_bytes\": %zu, \"osd_bytes\": %zu, \"osd_patch_bytes\": %zu, "
                   "\"osd_bfr_bytes\": %zu}%s\n",
                   r.level, r.samples, r.threads, r.dermis, r.osd_eval, r.osd_far, r.osd_patch,
                   r.osd_bfr, r.lbs, r.generic, r.scalar, r.gpu, r.dermis / r.best_osd(),
                   r.osd_stencil_cvs, r.dermis_bytes, r.osd_bytes, r.osd_patch_bytes,
                   r.osd_bfr_bytes, i + 1 < rows.size() ? "," : "");
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
    std::fprintf(j,
                 "  ],\n  \"bound_split\": {\"blocks\": %zu, \"lanes_used\": %zu, \"faces\": %zu, "
                 "\"sweep_s\": %.9g, \"refit_s\": %.9g, \"pack_s\": %.9g, \"evaluate_s\": "
                 "%.9g}\n}\n",
                 bound_blocks, bound_lanes, bound_faces, bound_split[0], bound_split[1],
                 bound_split[2], bound_split[3]);
    std::fclose(j);
  }
  return 0;
}
