// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/geometry/triangle_distance.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace dermis {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Triangles with |(b - a) x (c - a)|^2 > kWellShaped * L^4 (L: longest edge), i.e. not much
/// thinner than a tenth of their length, take the classic Voronoi-region path. Its region tests
/// are products of dot products whose rounding grows like 1 / thinness^2, so thinner triangles
/// take the careful path in ClosestOnThinTriangle() instead.
constexpr double kWellShaped = 1e-2;
/// A triangle whose height over its longest edge is below kDegenerateHeight times that edge is
/// treated as its three edges (the error is at most that height, which is at rounding level).
constexpr double kDegenerateHeight = 1e-12;

/// Leaves hold at most this many triangles.
constexpr Index kLeafSize = 4;
/// Traversal stack size; a median-split tree over < 2^31 triangles is far shallower.
constexpr int kStackSize = 64;
/// Boxes are grown by this fraction of the largest coordinate magnitude, so that a rounded
/// closest point on a triangle never lies outside its node's box.
constexpr double kPadRelative = 1e-13;
/// A box is pruned only when its squared distance times this exceeds the best squared distance,
/// which absorbs the rounding of the two squared distances: ties are never pruned.
constexpr double kPruneScale = 1.0 - 1e-14;

bool IsFinite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Closest point to `p` on segment [a, b]; `t` receives its parameter in [0, 1].
Vec3 ClosestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b, double* t) {
  const Vec3 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  double s = len2 > 0.0 ? glm::dot(p - a, ab) / len2 : 0.0;
  if (!(s > 0.0)) {
    *t = 0.0;
    return a;
  }
  if (s >= 1.0) {
    *t = 1.0;
    return b;
  }
  *t = s;
  return a + s * ab;
}

double Distance2(const Vec3& p, const Vec3& q) {
  const Vec3 d = p - q;
  return glm::dot(d, d);
}

/// Closest point on the three edges of a degenerate triangle; the first edge wins ties.
Vec3 ClosestOnEdges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary) {
  double t_ab = 0.0, t_bc = 0.0, t_ca = 0.0;
  const Vec3 q_ab = ClosestOnSegment(p, a, b, &t_ab);
  const Vec3 q_bc = ClosestOnSegment(p, b, c, &t_bc);
  const Vec3 q_ca = ClosestOnSegment(p, c, a, &t_ca);
  const double d_ab = Distance2(p, q_ab);
  const double d_bc = Distance2(p, q_bc);
  const double d_ca = Distance2(p, q_ca);
  if (d_ab <= d_bc && d_ab <= d_ca) {
    if (bary) *bary = Vec3(1.0 - t_ab, t_ab, 0.0);
    return q_ab;
  }
  if (d_bc <= d_ca) {
    if (bary) *bary = Vec3(0.0, 1.0 - t_bc, t_bc);
    return q_bc;
  }
  if (bary) *bary = Vec3(t_ca, 0.0, 1.0 - t_ca);
  return q_ca;
}

/// Thin or degenerate triangles. In an orthonormal frame built from the longest edge (u) and the
/// re-orthogonalised altitude (v), the plane's normal can only be tilted about the longest edge by
/// rounding, which moves the result by rounding-level amounts. If the projection of `p` lies in
/// the triangle (three 2-D orientation tests) it is the answer; otherwise the closest point is on
/// the boundary and the closest of the three edges is taken. Degenerate triangles (coincident or
/// collinear corners) go straight to the edges.
Vec3 ClosestOnThinTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary) {
  // Relabel so that q0 -> q1 is the longest edge and q2 the apex; slot[k] is q_k's barycentric
  // slot in (a, b, c).
  const double l_ab = Distance2(a, b);
  const double l_bc = Distance2(b, c);
  const double l_ca = Distance2(c, a);
  const Vec3 *q0 = &a, *q1 = &b, *q2 = &c;
  int slot[3] = {0, 1, 2};
  if (!(l_ab >= l_bc && l_ab >= l_ca)) {
    if (l_bc >= l_ca) {
      q0 = &b, q1 = &c, q2 = &a;
      slot[0] = 1, slot[1] = 2, slot[2] = 0;
    } else {
      q0 = &c, q1 = &a, q2 = &b;
      slot[0] = 2, slot[1] = 0, slot[2] = 1;
    }
  }
  const Vec3 e = *q1 - *q0;
  const double el = std::sqrt(glm::dot(e, e));
  if (!(el > 0.0)) return ClosestOnEdges(p, a, b, c, bary);
  const Vec3 u = e / el;
  const Vec3 r = *q2 - *q0;
  const double cx = glm::dot(r, u);
  Vec3 h = r - cx * u;
  h -= glm::dot(h, u) * u;
  const double hl = std::sqrt(glm::dot(h, h));
  if (!(hl > kDegenerateHeight * el)) return ClosestOnEdges(p, a, b, c, bary);
  const Vec3 v = h / hl;
  const Vec3 normal = glm::cross(u, v);
  const double cy = glm::dot(r, v);

  // 2-D triangle (0, 0), (el, 0), (cx, cy), counter-clockwise; P = (x, y) is p projected.
  const Vec3 d = p - *q0;
  const double x = glm::dot(d, u);
  const double y = glm::dot(d, v);
  const bool inside =
      y >= 0.0 && (cx - el) * y - cy * (x - el) >= 0.0 && cy * x - cx * y >= 0.0 && cy > 0.0;
  if (!inside) return ClosestOnEdges(p, a, b, c, bary);
  if (bary) {
    const double w2 = std::min(std::max(y / cy, 0.0), 1.0);
    const double w1 = std::min(std::max((x - w2 * cx) / el, 0.0), 1.0 - w2);
    Vec3 w(0.0);
    w[slot[0]] = std::max(1.0 - w1 - w2, 0.0);
    w[slot[1]] = w1;
    w[slot[2]] = w2;
    *bary = w;
  }
  return p - glm::dot(d, normal) * normal;
}

/// Squared distance from `p` to the box [lo, hi] (0 inside).
double BoxDistance2(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const double gx = std::max(std::max(lo.x - p.x, p.x - hi.x), 0.0);
  const double gy = std::max(std::max(lo.y - p.y, p.y - hi.y), 0.0);
  const double gz = std::max(std::max(lo.z - p.z, p.z - hi.z), 0.0);
  return gx * gx + gy * gy + gz * gz;
}

}  // namespace

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            Vec3* barycentric) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 bc = c - b;
  const Vec3 n = glm::cross(ab, ac);
  const double longest2 = std::max(glm::dot(ab, ab), std::max(glm::dot(ac, ac), glm::dot(bc, bc)));
  // Also sends degenerate triangles (n = 0) and non-finite input to the careful path.
  if (!(glm::dot(n, n) > kWellShaped * longest2 * longest2)) {
    return ClosestOnThinTriangle(p, a, b, c, barycentric);
  }

  // Vertex region of a.
  const Vec3 ap = p - a;
  const double d1 = glm::dot(ab, ap);
  const double d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    if (barycentric) *barycentric = Vec3(1.0, 0.0, 0.0);
    return a;
  }
  // Vertex region of b.
  const Vec3 bp = p - b;
  const double d3 = glm::dot(ab, bp);
  const double d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) {
    if (barycentric) *barycentric = Vec3(0.0, 1.0, 0.0);
    return b;
  }
  // Edge region of ab: outside the edge and between the perpendiculars at a and b.
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double den = d1 - d3;  // = |ab|^2 > 0.
    const double v = den > 0.0 ? std::min(d1 / den, 1.0) : 0.0;
    if (barycentric) *barycentric = Vec3(1.0 - v, v, 0.0);
    return a + v * ab;
  }
  // Vertex region of c.
  const Vec3 cp = p - c;
  const double d5 = glm::dot(ab, cp);
  const double d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) {
    if (barycentric) *barycentric = Vec3(0.0, 0.0, 1.0);
    return c;
  }
  // Edge region of ac.
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double den = d2 - d6;  // = |ac|^2 > 0.
    const double w = den > 0.0 ? std::min(d2 / den, 1.0) : 0.0;
    if (barycentric) *barycentric = Vec3(1.0 - w, 0.0, w);
    return a + w * ac;
  }
  // Edge region of bc.
  const double va = d3 * d6 - d5 * d4;
  const double e_b = d4 - d3;  // Progress of p along bc measured from b.
  const double e_c = d5 - d6;  // ... and from c.
  if (va <= 0.0 && e_b >= 0.0 && e_c >= 0.0) {
    const double den = e_b + e_c;  // = |bc|^2 > 0.
    const double w = den > 0.0 ? std::min(e_b / den, 1.0) : 0.0;
    if (barycentric) *barycentric = Vec3(0.0, 1.0 - w, w);
    return b + w * bc;
  }
  // Face region: va, vb, vc are the (scaled) barycentric coordinates of the projection of p.
  const double sum = va + vb + vc;  // = |n|^2 > 0.
  if (!(sum > 0.0)) return ClosestOnThinTriangle(p, a, b, c, barycentric);
  double v = std::max(vb / sum, 0.0);
  double w = std::max(vc / sum, 0.0);
  if (v + w > 1.0) {  // Only through rounding; keeps the point on the triangle.
    const double s = v + w;
    v /= s;
    w /= s;
  }
  if (barycentric) *barycentric = Vec3(std::max(1.0 - v - w, 0.0), v, w);
  return a + v * ab + w * ac;
}

struct TriangleDistanceTree::BuildItem {
  Vec3 centroid;
  Index id;
};

bool TriangleDistanceTree::Build(const std::vector<Vec3>& positions,
                                 const std::vector<std::uint32_t>& triangles) {
  nodes_.clear();
  corners_.clear();
  triangle_ids_.clear();
  if (triangles.size() % 3 != 0) return false;
  const std::size_t count = triangles.size() / 3;
  // Node indices go up to 2 * count.
  if (count > static_cast<std::size_t>(std::numeric_limits<Index>::max() / 2)) return false;
  double max_abs = 0.0;
  for (const std::uint32_t v : triangles) {
    if (v >= positions.size() || !IsFinite(positions[v])) return false;
    const Vec3& x = positions[v];
    max_abs = std::max(max_abs, std::max(std::abs(x.x), std::max(std::abs(x.y), std::abs(x.z))));
  }
  if (count == 0) return true;

  // Topology first: median splits over the centroids only.
  std::vector<BuildItem> items(count);
  for (std::size_t t = 0; t < count; ++t) {
    const Vec3& a = positions[triangles[3 * t]];
    const Vec3& b = positions[triangles[3 * t + 1]];
    const Vec3& c = positions[triangles[3 * t + 2]];
    items[t] = BuildItem{(a + b + c) * (1.0 / 3.0), static_cast<Index>(t)};
  }
  nodes_.reserve(2 * (count / 2 + 1));
  int max_depth = 0;
  BuildNode(0, static_cast<Index>(count), 1, &items, &max_depth);
  if (max_depth >= kStackSize) {  // Cannot happen with median splits; kept as a guard.
    nodes_.clear();
    return false;
  }

  // Triangles in leaf order.
  corners_.reserve(count);
  triangle_ids_.reserve(count);
  for (const BuildItem& item : items) {
    const std::size_t t = static_cast<std::size_t>(item.id);
    corners_.push_back(Corners{positions[triangles[3 * t]], positions[triangles[3 * t + 1]],
                               positions[triangles[3 * t + 2]]});
    triangle_ids_.push_back(item.id);
  }

  // Boxes bottom-up (children follow their parent in the array), grown by the padding.
  const double pad = kPadRelative * max_abs;
  for (std::size_t i = nodes_.size(); i-- > 0;) {
    Node& node = nodes_[i];
    if (node.count > 0) {
      Vec3 lo(kInf), hi(-kInf);
      for (Index k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
        const Corners& t = corners_[static_cast<std::size_t>(k)];
        lo = glm::min(lo, glm::min(t.a, glm::min(t.b, t.c)));
        hi = glm::max(hi, glm::max(t.a, glm::max(t.b, t.c)));
      }
      node.lo = lo - pad;
      node.hi = hi + pad;
    } else {
      const Node& left = nodes_[i + 1];
      const Node& right = nodes_[static_cast<std::size_t>(node.right_or_first)];
      node.lo = glm::min(left.lo, right.lo);
      node.hi = glm::max(left.hi, right.hi);
    }
  }
  return true;
}

Index TriangleDistanceTree::BuildNode(Index begin, Index end, int depth,
                                      std::vector<BuildItem>* items, int* max_depth) {
  *max_depth = std::max(*max_depth, depth);
  const Index id = static_cast<Index>(nodes_.size());
  nodes_.emplace_back();
  BuildItem* data = items->data();

  if (end - begin <= kLeafSize) {
    // Sorted so that the layout depends only on the input, not on nth_element's internals.
    std::sort(data + begin, data + end,
              [](const BuildItem& x, const BuildItem& y) { return x.id < y.id; });
    nodes_[id].right_or_first = begin;
    nodes_[id].count = end - begin;
    return id;
  }

  // Median split on the longest axis of the centroid bounds (lowest axis on ties). Equal
  // centroids are ordered by triangle index, so the split is fully determined by the input.
  Vec3 c_lo(kInf), c_hi(-kInf);
  for (Index i = begin; i < end; ++i) {
    c_lo = glm::min(c_lo, data[i].centroid);
    c_hi = glm::max(c_hi, data[i].centroid);
  }
  const Vec3 extent = c_hi - c_lo;
  int axis = 0;
  if (extent.y > extent[axis]) axis = 1;
  if (extent.z > extent[axis]) axis = 2;
  const Index mid = begin + (end - begin) / 2;
  std::nth_element(data + begin, data + mid, data + end,
                   [axis](const BuildItem& x, const BuildItem& y) {
                     const double cx = x.centroid[axis];
                     const double cy = y.centroid[axis];
                     return cx < cy || (cx == cy && x.id < y.id);
                   });
  BuildNode(begin, mid, depth + 1, items, max_depth);
  const Index right = BuildNode(mid, end, depth + 1, items, max_depth);
  nodes_[id].right_or_first = right;
  nodes_[id].count = 0;
  return id;
}

ClosestPoint TriangleDistanceTree::Query(const Vec3& p, double max_distance) const {
  return QueryImpl(p, max_distance, nullptr);
}

ClosestPoint TriangleDistanceTree::QueryIf(const Vec3& p, const TriangleFilter& accept,
                                           double max_distance) const {
  return QueryImpl(p, max_distance, accept ? &accept : nullptr);
}

ClosestPoint TriangleDistanceTree::QueryImpl(const Vec3& p, double max_distance,
                                             const TriangleFilter* accept) const {
  ClosestPoint result;
  result.distance = kInf;
  if (nodes_.empty() || !(max_distance >= 0.0) || !IsFinite(p)) return result;

  double best_d2 = max_distance * max_distance;
  Index best = kInvalidIndex;  // Input index of the best triangle so far.
  Vec3 best_point(0.0), best_bary(0.0);

  struct Entry {
    Index node;
    double d2;
  };
  Entry stack[kStackSize];
  int top = 0;

  Index node = 0;
  if (BoxDistance2(p, nodes_[0].lo, nodes_[0].hi) * kPruneScale > best_d2) return result;
  for (;;) {
    const Node& nd = nodes_[static_cast<std::size_t>(node)];
    bool descend = false;
    if (nd.count > 0) {
      const Index last = nd.right_or_first + nd.count;
      for (Index i = nd.right_or_first; i < last; ++i) {
        const Index id = triangle_ids_[static_cast<std::size_t>(i)];
        if (accept && !(*accept)(id)) continue;
        const Corners& t = corners_[static_cast<std::size_t>(i)];
        Vec3 bary;
        const Vec3 q = ClosestPointOnTriangle(p, t.a, t.b, t.c, &bary);
        const double d2 = Distance2(p, q);
        if (d2 < best_d2 || (d2 == best_d2 && (best == kInvalidIndex || id < best))) {
          best_d2 = d2;
          best = id;
          best_point = q;
          best_bary = bary;
        }
      }
    } else {
      const Index left = node + 1;
      const Index right = nd.right_or_first;
      const Node& ln = nodes_[static_cast<std::size_t>(left)];
      const Node& rn = nodes_[static_cast<std::size_t>(right)];
      const double dl = BoxDistance2(p, ln.lo, ln.hi);
      const double dr = BoxDistance2(p, rn.lo, rn.hi);
      const bool keep_l = !(dl * kPruneScale > best_d2);
      const bool keep_r = !(dr * kPruneScale > best_d2);
      if (keep_l && keep_r) {
        if (dr < dl) {
          stack[top++] = Entry{left, dl};
          node = right;
        } else {
          stack[top++] = Entry{right, dr};
          node = left;
        }
        descend = true;
      } else if (keep_l || keep_r) {
        node = keep_l ? left : right;
        descend = true;
      }
    }
    if (descend) continue;
    // Pop the next subtree that can still hold a closer (or equally close) triangle.
    bool found = false;
    while (top > 0) {
      const Entry e = stack[--top];
      if (!(e.d2 * kPruneScale > best_d2)) {
        node = e.node;
        found = true;
        break;
      }
    }
    if (!found) break;
  }

  if (best != kInvalidIndex) {
    result.distance = std::sqrt(best_d2);
    result.point = best_point;
    result.triangle = best;
    result.barycentric = best_bary;
  }
  return result;
}

std::vector<std::uint32_t> TriangulateFan(const PolygonMesh& mesh) {
  std::vector<std::uint32_t> triangles;
  const Index faces = mesh.num_faces();
  std::size_t total = 0;
  for (Index f = 0; f < faces; ++f) {
    total += 3 * static_cast<std::size_t>(std::max<Index>(mesh.face_size(f) - 2, 0));
  }
  triangles.reserve(total);
  for (Index f = 0; f < faces; ++f) {
    const Index first = mesh.face_offsets[static_cast<std::size_t>(f)];
    const Index size = mesh.face_size(f);
    for (Index k = 1; k + 1 < size; ++k) {
      triangles.push_back(static_cast<std::uint32_t>(mesh.face_vertices[first]));
      triangles.push_back(static_cast<std::uint32_t>(mesh.face_vertices[first + k]));
      triangles.push_back(static_cast<std::uint32_t>(mesh.face_vertices[first + k + 1]));
    }
  }
  return triangles;
}

}  // namespace dermis
