// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
//
// Dermis GPU evaluation: the displaced, blended surface of Yoon Eq. 3-4 (docs/math.md) at the
// precomputed samples of an EvaluationPlan, one invocation per sample. The buffers, bindings,
// push constants and dispatch sizes are documented in docs/gpu.md; the plan's memory layout in
// sdk/include/dermis/runtime/plan_layout.h. Per sample and face corner a (a chart):
//
//   S_a   = P_a(z) + d_a(z) N_a(z)                        (Eq. 3, the displaced chart surface)
//   S     = sum_a psi_a S_a                                (Eq. 4, the partition of unity)
//   dS/du = sum_a (dpsi_a/du S_a + psi_a dS_a/dz dz/du)    (likewise dS/dv)
//   n     = normalize(dS/du x dS/dv)
//
// with P_a the bi-quadratic local patch of the chart (the pose: refitted on the CPU, uploaded
// per frame), z the chart point, d_a the displacement and psi_a the blending weight (all from
// the plan, pose-independent). The arithmetic follows the CPU fast path term by term, in float.
#version 450

// Samples per plan block (kPlanLanes of plan_layout.h).
layout(constant_id = 0) const uint kLanes = 8;
// Invocations per workgroup: local_size_x, set by specialization constant 1 (default 64).
layout(local_size_x = 64, local_size_x_id = 1) in;

// Per-corner plan fields (PlanField of plan_layout.h), each kLanes floats.
const uint kFieldX = 0;
const uint kFieldY = 1;
const uint kFieldD = 2;
const uint kFieldGx = 3;
const uint kFieldGy = 4;
const uint kFieldW = 5;
const uint kFieldWu = 6;
const uint kFieldWv = 7;
const uint kFieldM00 = 8;
const uint kFieldM01 = 9;
const uint kFieldM10 = 10;
const uint kFieldM11 = 11;
const uint kPlanFields = 12;
// Floats per packed patch: 27 coefficients, the fallback normal, 2 of padding.
const uint kPatchFloats = 32;

// A PlanBlock as 32-bit words: chart[4], index[kLanes], dominant[kLanes], count, displaced.
const uint kBlockWords = 4 + 2 * kLanes + 2;

layout(std430, set = 0, binding = 0) readonly buffer PlanBlocks { int block_words[]; };
layout(std430, set = 0, binding = 1) readonly buffer PlanData { float plan[]; };
layout(std430, set = 0, binding = 2) readonly buffer Patches { float patches[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Normals { float normals[]; };

layout(push_constant) uniform Push {
  uint block_begin;      // first block of this dispatch, relative to the bound block range
  uint block_end;        // one past the last block, relative to the bound block range
  uint position_offset;  // bytes from the start of the bound positions range, multiple of 4
  uint position_stride;  // bytes between vertices, multiple of 4, >= 12
  uint normal_offset;    // likewise for normals
  uint normal_stride;    // 0: write no normals
} pc;

float PlanField(uint corner_base, uint field) { return plan[corner_base + field * kLanes]; }

// Cross and dot products spelled out in the CPU kernel's order (the built-ins leave the order
// and fused multiply-adds to the driver).
#define DERMIS_CROSS(a, b) \
  vec3((a).y * (b).z - (a).z * (b).y, (a).z * (b).x - (a).x * (b).z, (a).x * (b).y - (a).y * (b).x)
#define DERMIS_DOT(a, b) ((a).x * (b).x + (a).y * (b).y + (a).z * (b).z)

// Adds chart a's weighted contribution (Eq. 3 and the terms of Eq. 4) to s, su, sv. Every
// value is `precise` (SPIR-V NoContraction): additions and multiplications are then correctly
// rounded one by one in the CPU kernel's order on every conformant device, so the result
// follows the portable CPU kernel to within the few ulps Vulkan allows division and sqrt
// (docs/gpu.md, section 8).
void AccumulateCorner(uint patch_base, uint corner_base, bool displaced, inout precise vec3 s,
                      inout precise vec3 su, inout precise vec3 sv) {
  const float x = PlanField(corner_base, kFieldX);
  const float y = PlanField(corner_base, kFieldY);
  precise const float x2 = 2.0 * x, y2 = 2.0 * y;
  precise vec3 p, px, py, pxx, pxy, pyy;
  for (uint k = 0; k < 3; ++k) {
    // Coefficient c_mn of coordinate k at patch + 9k + 3m + n: P = sum c_mn x^m y^n.
    const uint c = patch_base + 9 * k;
    const float c00 = patches[c + 0], c01 = patches[c + 1], c02 = patches[c + 2];
    const float c10 = patches[c + 3], c11 = patches[c + 4], c12 = patches[c + 5];
    const float c20 = patches[c + 6], c21 = patches[c + 7], c22 = patches[c + 8];
    // A_m = sum_n c_mn y^n, B_m = dA_m/dy.
    precise const float a0 = c00 + y * (c01 + y * c02);
    precise const float a1 = c10 + y * (c11 + y * c12);
    precise const float a2 = c20 + y * (c21 + y * c22);
    precise const float b0 = c01 + y2 * c02;
    precise const float b1 = c11 + y2 * c12;
    precise const float b2 = c21 + y2 * c22;
    p[k] = a0 + x * (a1 + x * a2);
    px[k] = a1 + x2 * a2;
    py[k] = b0 + x * (b1 + x * b2);
    pxx[k] = 2.0 * a2;
    pxy[k] = b1 + x2 * b2;
    pyy[k] = 2.0 * (c02 + x * (c12 + x * c22));
  }
  // The patch frame: regular where |px x py| > 1e-6 |px| |py|, else the fallback normal with
  // zero derivatives (the CPU kernel's test).
  precise const vec3 nr = DERMIS_CROSS(px, py);
  precise const float l2 = DERMIS_DOT(nr, nr);
  precise const float pxpx = DERMIS_DOT(px, px), pypy = DERMIS_DOT(py, py);
  precise const float limit = 1e-12 * pxpx * pypy;
  const bool ok = l2 > limit && l2 > 1e-30;
  precise const float inv = 1.0 / sqrt(ok ? l2 : 1.0);
  const vec3 fallback =
      vec3(patches[patch_base + 27], patches[patch_base + 28], patches[patch_base + 29]);
  precise const vec3 n = ok ? nr * inv : fallback;
  precise vec3 xp = p, xx = px, xy = py;
  if (displaced) {
    const float d = PlanField(corner_base, kFieldD);
    const float gx = PlanField(corner_base, kFieldGx);
    const float gy = PlanField(corner_base, kFieldGy);
    precise const vec3 dnx = DERMIS_CROSS(pxx, py) + DERMIS_CROSS(px, pxy);
    precise const vec3 dny = DERMIS_CROSS(pxy, py) + DERMIS_CROSS(px, pyy);
    precise const float invd = (ok ? inv : 0.0) * d;
    // d dN/dx = d (dn - N (N . dn)) / |n|, likewise for y.
    precise const float ndx = DERMIS_DOT(n, dnx), ndy = DERMIS_DOT(n, dny);
    precise const vec3 nx = (dnx - n * ndx) * invd;
    precise const vec3 ny = (dny - n * ndy) * invd;
    xp = p + d * n;
    xx = (px + gx * n) + nx;
    xy = (py + gy * n) + ny;
  }
  const float w = PlanField(corner_base, kFieldW);
  const float wu = PlanField(corner_base, kFieldWu);
  const float wv = PlanField(corner_base, kFieldWv);
  const float m00 = PlanField(corner_base, kFieldM00);
  const float m01 = PlanField(corner_base, kFieldM01);
  const float m10 = PlanField(corner_base, kFieldM10);
  const float m11 = PlanField(corner_base, kFieldM11);
  s = s + w * xp;
  su = ((su + wu * xp) + m00 * xx) + m01 * xy;
  sv = ((sv + wv * xp) + m10 * xx) + m11 * xy;
}

void main() {
  const uint slot = gl_GlobalInvocationID.x;
  const uint block = pc.block_begin + slot / kLanes;
  const uint lane = slot % kLanes;
  if (block >= pc.block_end) return;
  const uint words = block * kBlockWords;
  const int count = block_words[words + 4 + 2 * kLanes];
  if (int(lane) >= count) return;  // unused lanes repeat lane 0 and write nothing
  const uint displaced = uint(block_words[words + 4 + 2 * kLanes + 1]);
  const uint data = block * (4 * kPlanFields * kLanes) + lane;
  precise vec3 s = vec3(0.0), su = vec3(0.0), sv = vec3(0.0);
  for (uint a = 0; a < 4; ++a) {
    const int chart = block_words[words + a];
    if (chart < 0) continue;  // no lane of this block weighs corner a
    AccumulateCorner(uint(chart) * kPatchFloats, data + a * kPlanFields * kLanes,
                     (displaced & (1u << a)) != 0u, s, su, sv);
  }
  const uint index = uint(block_words[words + 4 + lane]);
  const uint po = (pc.position_offset + index * pc.position_stride) >> 2;
  positions[po + 0] = s.x;
  positions[po + 1] = s.y;
  positions[po + 2] = s.z;
  if (pc.normal_stride == 0u) return;
  precise const vec3 nr = DERMIS_CROSS(su, sv);
  precise const float l2 = DERMIS_DOT(nr, nr);
  precise vec3 n;
  if (l2 > 1e-30) {
    n = nr * (1.0 / sqrt(l2));
  } else {
    // Degenerate surface: the fallback normal of the dominant corner's chart.
    const uint dominant = uint(block_words[words + 4 + kLanes + lane]) * kPatchFloats;
    n = vec3(patches[dominant + 27], patches[dominant + 28], patches[dominant + 29]);
  }
  const uint no = (pc.normal_offset + index * pc.normal_stride) >> 2;
  normals[no + 0] = n.x;
  normals[no + 1] = n.y;
  normals[no + 2] = n.z;
}
