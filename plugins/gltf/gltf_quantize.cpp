// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// KHR_mesh_quantization encodings for the glTF exporter (docs/gltf-compression.md,
// "Quantisation"): the position grid chosen from the model size and its median edge length.
#include "gltf_quantize.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace dermis::gltf_quantize {
namespace {

/// Triangle edge lengths of a primitive (indexed or not; strips and fans by their triangles).
void AddEdges(const AssetPrimitive& p, std::vector<double>* edges) {
  const std::size_t n = p.positions.size();
  auto vertex = [&](std::size_t k) -> std::uint32_t {
    return p.indices.empty() ? static_cast<std::uint32_t>(k) : p.indices[k];
  };
  const std::size_t count = p.indices.empty() ? n : p.indices.size();
  if (p.mode != PrimitiveMode::kTriangles) return;
  for (std::size_t t = 0; t + 2 < count; t += 3) {
    const std::uint32_t v[3] = {vertex(t), vertex(t + 1), vertex(t + 2)};
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = v[e], b = v[(e + 1) % 3];
      if (a >= n || b >= n) continue;
      edges->push_back(glm::distance(glm::dvec3(p.positions[a]), glm::dvec3(p.positions[b])));
    }
  }
}

}  // namespace

PositionGrid ChoosePositionGrid(const Asset& asset) {
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  bool any = false, morphs = false;
  std::vector<double> edges;
  for (const AssetMesh& m : asset.meshes) {
    for (const AssetPrimitive& p : m.primitives) {
      for (const glm::vec3& v : p.positions) {
        lo = glm::min(lo, glm::dvec3(v));
        hi = glm::max(hi, glm::dvec3(v));
        any = true;
      }
      for (const AssetMorphTarget& t : p.targets) {
        if (t.positions.empty()) continue;
        morphs = true;
        for (std::size_t i = 0; i < t.positions.size() && i < p.positions.size(); ++i) {
          const glm::dvec3 v = glm::dvec3(glm::vec3(p.positions[i] + t.positions[i]));
          lo = glm::min(lo, v);
          hi = glm::max(hi, v);
        }
      }
      AddEdges(p, &edges);
    }
  }
  PositionGrid grid;
  if (!any) return grid;
  const glm::dvec3 size = hi - lo;
  const double extent = std::max({size.x, size.y, size.z});
  grid.origin = lo;
  const int max_bits = morphs ? 15 : 16;
  double median = 0.0;
  if (!edges.empty()) {
    std::nth_element(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(edges.size() / 2),
                     edges.end());
    median = edges[edges.size() / 2];
  }
  grid.target_error = median / kEdgeFraction;
  grid.bits = max_bits;
  if (extent > 0.0 && grid.target_error > 0.0) {
    for (int bits = 10; bits <= max_bits; ++bits) {
      const double step = extent / static_cast<double>((1 << bits) - 1);
      if (step * std::sqrt(3.0) / 2.0 <= grid.target_error) {
        grid.bits = bits;
        break;
      }
    }
  }
  grid.step = extent > 0.0 ? extent / static_cast<double>((1 << grid.bits) - 1) : 1.0;
  return grid;
}

glm::u16vec3 Quantize(const PositionGrid& grid, const glm::vec3& p) {
  const double top = static_cast<double>((1 << grid.bits) - 1);
  glm::u16vec3 q;
  for (int c = 0; c < 3; ++c) {
    const double x = std::round((static_cast<double>(p[c]) - grid.origin[c]) / grid.step);
    q[c] = static_cast<std::uint16_t>(std::clamp(x, 0.0, top));
  }
  return q;
}

glm::dvec3 Dequantize(const PositionGrid& grid, const glm::ivec3& q) {
  return grid.origin + grid.step * glm::dvec3(q);
}

std::int16_t Snorm16(float v) {
  const double x = std::round(std::clamp(static_cast<double>(v), -1.0, 1.0) * 32767.0);
  return static_cast<std::int16_t>(x);
}

std::uint16_t Unorm16(float v) {
  const double x = std::round(std::clamp(static_cast<double>(v), 0.0, 1.0) * 65535.0);
  return static_cast<std::uint16_t>(x);
}

void QuantizeWeights(const float* slots, std::size_t count, std::uint16_t* out) {
  long sum = 0;
  for (std::size_t k = 0; k < count; ++k) {
    out[k] = Unorm16(slots[k]);
    sum += out[k];
  }
  // Slot 0 holds the largest weight (>= 1/count of the total): it absorbs the residue.
  const long fixed = static_cast<long>(out[0]) + (65535 - sum);
  out[0] = static_cast<std::uint16_t>(std::clamp(fixed, 0L, 65535L));
}

}  // namespace dermis::gltf_quantize
