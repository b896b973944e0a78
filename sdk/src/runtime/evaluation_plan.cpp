// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Precomputation of the pose-independent part of Yoon Eq. 3-4 at fixed samples, following the
// scalar evaluator (surface_evaluator.cpp) term by term: per sample and face corner the chart
// point z = ChartMap(FaceToCorner(uv)), the displacement d(z) and its gradient, the weight psi
// and its face derivatives, and psi * dz/duv. The kernels (eval_kernel.h) do the rest per frame.
#include "dermis/runtime/evaluation_plan.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "dermis/core/parallel.h"
#include "dermis/runtime/plan_layout.h"
#include "dermis/surface/blend.h"
#include "dermis/surface/chart.h"
#include "runtime/kernels/kernels.h"

namespace dermis {

namespace {

float F32(double x) { return static_cast<float>(x); }

// Fills one corner's fields of lane `lane` of a block.
void SetLane(float* corner, int lane, const float (&values)[kPlanFields]) {
  for (int f = 0; f < kPlanFields; ++f) corner[f * kPlanLanes + lane] = values[f];
}

// The pose-independent terms of one sample, written into lane `lane` of a block.
void PrecomputeSample(const ManifoldDomain& domain, const Displacement* displacement,
                      const SampleLocation& sample, PlanBlock* block, float* data, int lane) {
  const MeshTopology& topo = domain.topology();
  const Index face = sample.face;
  const Vec2 uv = glm::clamp(Vec2(sample.u, sample.v), Vec2(0.0), Vec2(1.0));
  const Index base = topo.face_offset(face);
  const double lb = domain.options().blend_lb;
  const double ub = 1.0 - lb;
  const BlendType blend = domain.options().blend_type;
  const int dominant = DominantCorner(uv);
  const Vec2 cd_dom = FaceToCorner(dominant, uv);
  block->dominant[lane] = topo.halfedge_origin(base + dominant);
  float zero[kPlanFields] = {};
  for (int a = 0; a < 4; ++a) SetLane(data + a * kPlanFields * kPlanLanes, lane, zero);

  auto chart_terms = [&](int a, Vec2 cd, float(&f)[kPlanFields], glm::dmat2* jac) {
    const Index h = base + a;
    const Index v = topo.halfedge_origin(h);
    Vec2 z;
    const bool ok = ChartMap(domain.chart(v), topo.halfedge_ring_index(h), cd, &z, jac);
    double d = 0.0;
    Vec2 g(0.0);
    if (displacement) displacement->Evaluate(v, z, &d, &g);
    f[kFieldX] = F32(z.x);
    f[kFieldY] = F32(z.y);
    f[kFieldD] = F32(d);
    f[kFieldGx] = F32(g.x);
    f[kFieldGy] = F32(g.y);
    if (d != 0.0 || g.x != 0.0 || g.y != 0.0) block->displaced |= 1u << a;
    return ok;
  };

  if (cd_dom.x <= lb && cd_dom.y <= lb) {
    // One chart (psi = 1, all else 0): derivatives in the chart itself, as the scalar path.
    float f[kPlanFields] = {};
    glm::dmat2 jac;
    chart_terms(dominant, cd_dom, f, &jac);
    f[kFieldW] = 1.0f;
    f[kFieldM00] = 1.0f;
    f[kFieldM11] = 1.0f;
    SetLane(data + dominant * kPlanFields * kPlanLanes, lane, f);
    return;
  }
  float fields[4][kPlanFields] = {};
  glm::dmat2 m_dom(1.0);
  for (int a = 0; a < 4; ++a) {
    const Vec2 cd = FaceToCorner(a, uv);
    if (cd.x >= ub || cd.y >= ub) continue;
    float(&f)[kPlanFields] = fields[a];
    Vec2 grad_psi;
    const double psi = CornerWeight(blend, lb, cd, &grad_psi);
    glm::dmat2 jac;
    chart_terms(a, cd, f, &jac);
    const glm::dmat2 dj = FaceToCornerJacobian(a);
    const glm::dmat2 m = jac * dj;  // columns dz/du, dz/dv
    f[kFieldW] = F32(psi);
    f[kFieldWu] = F32(glm::dot(grad_psi, dj[0]));
    f[kFieldWv] = F32(glm::dot(grad_psi, dj[1]));
    f[kFieldM00] = F32(psi * m[0].x);
    f[kFieldM01] = F32(psi * m[0].y);
    f[kFieldM10] = F32(psi * m[1].x);
    f[kFieldM11] = F32(psi * m[1].y);
    if (a == dominant) m_dom = m;
  }
  // The scalar normal is (S_u x S_v) det(dz/duv)^-1 of the dominant chart, normalised: where
  // that determinant is negative, S_v is negated (positions do not use it).
  if (glm::determinant(m_dom) < 0.0) {
    for (auto& f : fields) {
      f[kFieldWv] = -f[kFieldWv];
      f[kFieldM10] = -f[kFieldM10];
      f[kFieldM11] = -f[kFieldM11];
    }
  }
  for (int a = 0; a < 4; ++a) SetLane(data + a * kPlanFields * kPlanLanes, lane, fields[a]);
}

bool ValidLocation(const ManifoldDomain& domain, const SampleLocation& s) {
  const double tol = 1e-12;
  return s.face >= 0 && s.face < domain.num_faces() && s.u >= -tol && s.u <= 1.0 + tol &&
         s.v >= -tol && s.v <= 1.0 + tol;
}

}  // namespace

EvaluationPlan::EvaluationPlan() = default;
EvaluationPlan::~EvaluationPlan() = default;
EvaluationPlan::EvaluationPlan(EvaluationPlan&&) noexcept = default;
EvaluationPlan& EvaluationPlan::operator=(EvaluationPlan&&) noexcept = default;

std::size_t EvaluationPlan::memory_bytes() const {
  return blocks_.capacity() * sizeof(PlanBlock) + data_.capacity() * sizeof(float);
}

Status EvaluationPlan::Build(const ManifoldDomain& domain, const Displacement* displacement,
                             const SampleLocation* samples, std::size_t count,
                             const EvaluationPlanOptions& options, EvaluationPlan* out) {
  if (count > 0 && !samples) return Status::InvalidInput("EvaluationPlan: no samples given");
  if (count > static_cast<std::size_t>(INT32_MAX)) {
    return Status::InvalidInput("EvaluationPlan: more than 2^31 - 1 samples");
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!ValidLocation(domain, samples[i])) {
      return Status::InvalidInput("EvaluationPlan: sample " + std::to_string(i) +
                                  " is not a valid (face, u, v) of the surface");
    }
  }
  // Samples grouped by face (stable: by face, then by index), kPlanLanes per block.
  std::vector<std::int32_t> order(count);
  for (std::size_t i = 0; i < count; ++i) order[i] = static_cast<std::int32_t>(i);
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) {
    return samples[a].face < samples[b].face;
  });
  std::vector<std::size_t> block_start;  // into `order`
  for (std::size_t i = 0; i < count;) {
    const Index face = samples[order[i]].face;
    std::size_t j = i;
    while (j < count && samples[order[j]].face == face && j - i < kPlanLanes) ++j;
    block_start.push_back(i);
    i = j;
  }
  block_start.push_back(count);
  const std::size_t num_blocks = block_start.size() - 1;

  EvaluationPlan plan;
  plan.num_samples_ = count;
  plan.num_vertices_ = static_cast<std::size_t>(domain.num_vertices());
  plan.blocks_.resize(num_blocks);
  plan.data_.assign(num_blocks * kPlanBlockFloats, 0.0f);
  const MeshTopology& topo = domain.topology();

  auto build_range = [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b < last; ++b) {
      PlanBlock& block = plan.blocks_[b];
      float* data = plan.data_.data() + b * kPlanBlockFloats;
      const std::size_t begin = block_start[b], end = block_start[b + 1];
      const Index face = samples[order[begin]].face;
      block = PlanBlock{};
      block.count = static_cast<std::int32_t>(end - begin);
      for (int lane = 0; lane < kPlanLanes; ++lane) {
        // Unused lanes repeat lane 0 (finite values, results dropped).
        const std::size_t k =
            begin +
            (static_cast<std::size_t>(lane) < end - begin ? static_cast<std::size_t>(lane) : 0);
        block.index[lane] = order[k];
        PrecomputeSample(domain, displacement, samples[order[k]], &block, data, lane);
      }
      // Corners no lane weighs (weight, its derivatives and Jacobian all zero) are skipped.
      for (int a = 0; a < 4; ++a) {
        const float* c = data + a * kPlanFields * kPlanLanes;
        bool used = false;
        for (int f = kFieldW; f < kPlanFields && !used; ++f) {
          for (int l = 0; l < kPlanLanes; ++l) used = used || c[f * kPlanLanes + l] != 0.0f;
        }
        block.chart[a] = used ? topo.halfedge_origin(topo.face_offset(face) + a) : -1;
        if (!used) block.displaced &= ~(1u << a);
      }
    }
  };
  // At least 64 blocks per thread; every block is written by itself, so the split does not
  // change the plan.
  const int threads = static_cast<int>(
      std::min<std::size_t>(static_cast<std::size_t>(ResolveThreadCount(options.threads)),
                            std::max<std::size_t>(1, num_blocks / 64)));
  ParallelFor(threads, num_blocks, build_range);
  *out = std::move(plan);
  return Status::Ok();
}

void PackPatches(const LocalPatch* patches, std::size_t count, float* out) {
  for (std::size_t v = 0; v < count; ++v) {
    float* o = out + v * kPackedPatchStride;
    for (int k = 0; k < 3; ++k) {
      for (int m = 0; m < 3; ++m) {
        for (int n = 0; n < 3; ++n) o[k * 9 + m * 3 + n] = F32(patches[v].coeff[m][n][k]);
      }
    }
    for (int k = 0; k < 3; ++k) o[27 + k] = F32(patches[v].fallback_normal[k]);
    o[30] = o[31] = 0.0f;
  }
}

bool SimdPathAvailable(SimdPath path) { return kernels::FindBackend(path) != nullptr; }

SimdPath BestSimdPath() { return kernels::FindBackend(SimdPath::kAuto)->path; }

const char* SimdPathName(SimdPath path) {
  if (path == SimdPath::kAuto) path = BestSimdPath();
  switch (path) {
    case SimdPath::kGeneric:
      return "generic";
    case SimdPath::kAvx2:
      return "avx2";
    case SimdPath::kScalar:
      return "scalar";
    case SimdPath::kAuto:
      break;
  }
  return "unknown";
}

bool EvaluatePlan(const EvaluationPlan& plan, const float* packed_patches, std::size_t block_begin,
                  std::size_t block_end, const PlanOutputBuffers& out, SimdPath path) {
  if (block_begin > block_end || block_end > plan.num_blocks()) return false;
  if (block_begin == block_end) return true;
  if (!packed_patches || !out.positions || out.position_stride < 3 * sizeof(float)) return false;
  if (out.normals && out.normal_stride < 3 * sizeof(float)) return false;
  if (out.tangents && (!out.tangent_frames || out.tangent_stride < 4 * sizeof(float))) return false;
  if (out.derivatives && out.derivative_stride < 6 * sizeof(float)) return false;
  const kernels::Backend* backend = kernels::FindBackend(path);
  if (backend == nullptr) return false;
  backend->evaluate(PlanView{plan.blocks(), plan.block_data()}, packed_patches, block_begin,
                    block_end, out);
  return true;
}

}  // namespace dermis
