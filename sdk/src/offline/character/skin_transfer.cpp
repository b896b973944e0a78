// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Attribute transfer through the nearest surface point (used for control-vertex skin weights,
// and for the weights and UVs of tessellated exports).
#include "dermis/offline/character/skin_transfer.h"

#include <algorithm>
#include <numeric>

namespace dermis {

std::vector<std::uint32_t> PrimitiveTriangles(const AssetPrimitive& p) {
  std::vector<std::uint32_t> order;
  if (p.indices.empty()) {
    order.resize(p.positions.size());
    std::iota(order.begin(), order.end(), 0u);
  } else {
    order = p.indices;
  }
  std::vector<std::uint32_t> tris;
  switch (p.mode) {
    case PrimitiveMode::kTriangles:
      tris.assign(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(order.size() / 3 * 3));
      break;
    case PrimitiveMode::kTriangleStrip:
      for (std::size_t i = 2; i < order.size(); ++i) {
        if (i % 2 == 0) {
          tris.insert(tris.end(), {order[i - 2], order[i - 1], order[i]});
        } else {
          tris.insert(tris.end(), {order[i - 1], order[i - 2], order[i]});
        }
      }
      break;
    case PrimitiveMode::kTriangleFan:
      for (std::size_t i = 2; i < order.size(); ++i) {
        tris.insert(tris.end(), {order[0], order[i - 1], order[i]});
      }
      break;
    default:
      break;
  }
  return tris;
}

std::vector<Influence> VertexInfluences(const AssetPrimitive& primitive, std::size_t vertex) {
  std::vector<Influence> out;
  const std::size_t sets = std::min(primitive.joints.size(), primitive.weights.size());
  for (std::size_t s = 0; s < sets; ++s) {
    if (vertex >= primitive.joints[s].size() || vertex >= primitive.weights[s].size()) continue;
    for (int k = 0; k < 4; ++k) {
      const float w = primitive.weights[s][vertex][k];
      if (!(w > 0.0f)) continue;
      const std::uint16_t j = primitive.joints[s][vertex][k];
      auto it =
          std::find_if(out.begin(), out.end(), [j](const Influence& x) { return x.joint == j; });
      if (it != out.end()) {
        it->weight += w;
      } else {
        out.push_back({j, w});
      }
    }
  }
  std::sort(out.begin(), out.end(),
            [](const Influence& x, const Influence& y) { return x.joint < y.joint; });
  return out;
}

void BlendInfluences(const std::vector<Influence>& a, const std::vector<Influence>& b,
                     const std::vector<Influence>& c, const Vec3& barycentric, glm::u16vec4* joints,
                     glm::vec4* weights) {
  std::vector<std::pair<std::uint16_t, double>> sum;
  const std::vector<Influence>* lists[3] = {&a, &b, &c};
  for (int k = 0; k < 3; ++k) {
    const double t = barycentric[k];
    if (!(t > 0.0)) continue;
    for (const Influence& in : *lists[k]) {
      auto it = std::find_if(
          sum.begin(), sum.end(),
          [&](const std::pair<std::uint16_t, double>& x) { return x.first == in.joint; });
      if (it != sum.end()) {
        it->second += t * in.weight;
      } else {
        sum.emplace_back(in.joint, t * in.weight);
      }
    }
  }
  std::sort(sum.begin(), sum.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second > y.second : x.first < y.first;
  });
  if (sum.size() > 4) sum.resize(4);
  double total = 0.0;
  for (const auto& x : sum) total += x.second;
  *joints = glm::u16vec4(0);
  *weights = glm::vec4(0.0f);
  if (!(total > 0.0)) return;
  for (std::size_t k = 0; k < sum.size(); ++k) {
    (*joints)[int(k)] = sum[k].first;
    (*weights)[int(k)] = static_cast<float>(sum[k].second / total);
  }
}

}  // namespace dermis
