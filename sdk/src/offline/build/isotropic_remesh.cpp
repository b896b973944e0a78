// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Adaptive isotropic remeshing (Botsch & Kobbelt 2004, "A remeshing approach to multiresolution
// modeling", section 3; adaptive sizes as in Dunyach et al. 2013): split long edges, collapse
// short ones, flip towards valence 6 (4 on the boundary), relax tangentially and project back
// onto the reference surface. docs/fitting.md, "Control mesh".
#include "dermis/offline/build/isotropic_remesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

#include "dermis/offline/geometry/triangle_distance.h"
#include "tri_edit_mesh.h"

namespace dermis {
namespace {

using remesh_detail::TriEditMesh;

class Remesher {
 public:
  Remesher(const ReferenceSurface& reference, const SizingField& sizing,
           const IsotropicRemeshOptions& options, IsotropicRemeshStats* stats,
           const CreaseChains* creases)
      : ref_(reference),
        cr_(creases),
        sizing_(sizing),
        options_(options),
        stats_(stats),
        cos_max_change_(std::cos(options.max_normal_change_deg * 3.14159265358979323846 / 180.0)) {}

  TriEditMesh m;

  // Creases: each vertex's tag in m.feature, the crease edges (a < b) with their chain.
  int Feature(Index v) const { return m.feature[static_cast<std::size_t>(v)]; }
  int CreaseChain(Index a, Index b) const {
    if (crease_.empty()) return -1;
    const auto it = crease_.find({std::min(a, b), std::max(a, b)});
    return it == crease_.end() ? -1 : it->second;
  }
  // The two crease neighbours of crease vertex v (false if it has not exactly two).
  bool CreaseNeighbors(Index v, Index* p, Index* q) const {
    std::vector<Index> ring;
    m.Neighbors(v, &ring);
    int found = 0;
    for (Index w : ring) {
      if (CreaseChain(v, w) < 0) continue;
      if (found == 0) *p = w;
      if (found == 1) *q = w;
      ++found;
    }
    return found == 2;
  }
  // Where crease vertex v goes on its chain: between its crease neighbours, splitting the span
  // in the ratio t (-1: in proportion to the sizes); its position if it cannot move.
  Vec3 CreaseTarget(Index v, double t) const {
    Index p = kInvalidIndex, q = kInvalidIndex;
    if (!cr_ || Feature(v) < 0 || !CreaseNeighbors(v, &p, &q)) return m.position(v);
    if (t < 0.0) {
      const double hp = EdgeSize(p, v), hn = EdgeSize(v, q);
      t = hp / (hp + hn);
    }
    return cr_->Between(Feature(v), m.position(p), m.position(q), t);
  }

  Vec3 FaceNormal(Index f) const {
    const std::array<Index, 3>& t = m.face(f);
    return glm::cross(m.position(t[1]) - m.position(t[0]), m.position(t[2]) - m.position(t[0]));
  }
  Vec3 VertexNormal(Index v) const {
    Vec3 n(0.0);
    for (Index f : m.vertex_faces(v)) n += FaceNormal(f);
    const double l = glm::length(n);
    return l > 0.0 ? n / l : n;
  }
  Vec3 EdgeNormal(Index a, Index b) const {
    Vec3 n(0.0);
    for (Index f : m.vertex_faces(a)) {
      const std::array<Index, 3>& t = m.face(f);
      if (t[0] == b || t[1] == b || t[2] == b) n += FaceNormal(f);
    }
    const double l = glm::length(n);
    return l > 0.0 ? n / l : n;
  }
  double Size(Index v) const { return m.size[static_cast<std::size_t>(v)]; }
  // Half way along the reference loop between the ends of the boundary edge {a, b}.
  Vec3 LoopMidpoint(Index a, Index b) const {
    const bool forward = m.DirectedEdgeFace(a, b) != kInvalidIndex;
    return ref_.LoopBetween(m.loop[static_cast<std::size_t>(a)], m.position(forward ? a : b),
                            m.position(forward ? b : a), 0.5);
  }
  double EdgeSize(Index a, Index b) const { return 0.5 * (Size(a) + Size(b)); }
  // Whether the chord from p to q of chain c cuts the crease by more than allowed for size h.
  bool ChordTooFar(int c, const Vec3& p, const Vec3& q, double h) const {
    return cr_ && c >= 0 && cr_->ChordDeviation(c, p, q) > options_.crease_chord_error * h;
  }
  double Length(Index a, Index b) const { return glm::length(m.position(a) - m.position(b)); }
  Vec3 ProjectInside(const Vec3& p, const Vec3& n, double reach) const {
    return ref_.Project(p, n, reach).point;
  }
  void UpdateSize(Index v) {
    m.size[static_cast<std::size_t>(v)] = sizing_.At(m.position(v), VertexNormal(v));
  }
  void UpdateSizes() {
    for (Index v = 0; v < m.num_vertex_slots(); ++v) {
      if (m.vertex_alive(v)) UpdateSize(v);
    }
  }

  // Splits every edge longer than split_ratio x its size, in passes until none is (a long
  // sliver of a low-poly seed is cut down to size before its short edges are collapsed).
  void SplitLongEdges() {
    std::vector<std::array<Index, 2>> edges;
    for (int pass = 0; pass < 16; ++pass) {
      m.Edges(&edges);
      int splits = 0;
      for (const auto& e : edges) {
        const Index a = e[0], b = e[1];
        if (!m.HasEdge(a, b)) continue;
        const double h = EdgeSize(a, b);
        if (!(Length(a, b) > options_.split_ratio * h) &&
            !ChordTooFar(CreaseChain(a, b), m.position(a), m.position(b), h)) {
          continue;
        }
        Split(a, b);
        ++splits;
      }
      if (splits == 0) break;
    }
  }

  Index Split(Index a, Index b) {
    const double h = EdgeSize(a, b);
    Vec3 mid = 0.5 * (m.position(a) + m.position(b));
    const Vec3 n = EdgeNormal(a, b);
    const int chain = CreaseChain(a, b);
    if (m.IsBoundaryEdge(a, b)) {
      mid = LoopMidpoint(a, b);
    } else if (chain >= 0 && cr_) {
      mid = cr_->Between(chain, m.position(a), m.position(b), 0.5);
    } else {
      mid = ProjectInside(mid, n, h);
    }
    const Index v = m.SplitEdge(a, b, mid);
    if (chain >= 0) {
      m.feature[static_cast<std::size_t>(v)] = chain;
      crease_.erase({std::min(a, b), std::max(a, b)});
      crease_[{std::min(a, v), std::max(a, v)}] = chain;
      crease_[{std::min(b, v), std::max(b, v)}] = chain;
    }
    UpdateSize(v);
    if (stats_) ++stats_->splits;
    return v;
  }

  struct CollapsePlan {
    Index from, to;
    Vec3 pos;
  };

  // The ways to collapse edge {a, b}: which vertex goes, which stays, and where the survivor
  // sits (the midpoint on the surface, or either end where it is).
  void PlanCollapse(Index a, Index b, std::vector<CollapsePlan>* plans) const {
    plans->clear();
    const bool ab = m.IsBoundaryVertex(a), bb = m.IsBoundaryVertex(b);
    const Vec3 mid = 0.5 * (m.position(a) + m.position(b));
    const int chain = CreaseChain(a, b);
    if (chain >= 0 || Feature(a) != kNoFeature || Feature(b) != kNoFeature) {
      // Features: a crease vertex leaves only along its crease, a corner never; the survivor
      // stays where it is unless both ends are on the crease (then half way along it).
      const bool boundary_edge = m.IsBoundaryEdge(a, b);
      auto removable = [&](Index v) {
        if (m.IsBoundaryVertex(v) && !boundary_edge) return false;
        return Feature(v) == kNoFeature || (Feature(v) >= 0 && chain >= 0);
      };
      if (chain >= 0 && cr_ && Feature(a) >= 0 && Feature(b) >= 0) {
        plans->push_back({a, b, cr_->Between(chain, m.position(a), m.position(b), 0.5)});
      }
      if (removable(b)) plans->push_back({b, a, m.position(a)});
      if (removable(a)) plans->push_back({a, b, m.position(b)});
      return;
    }
    if (m.IsBoundaryEdge(a, b)) {
      plans->push_back({a, b, LoopMidpoint(a, b)});
    } else if (ab && bb) {
      return;
    } else if (ab || bb) {
      // Interior into boundary: the boundary vertex keeps its place.
      plans->push_back({ab ? b : a, ab ? a : b, m.position(ab ? a : b)});
      return;
    } else {
      plans->push_back({a, b, ProjectInside(mid, EdgeNormal(a, b), EdgeSize(a, b))});
    }
    plans->push_back({b, a, m.position(a)});
    plans->push_back({a, b, m.position(b)});
  }

  // Geometric checks of a collapse: the two ends do not lie on opposite sides of a thin part
  // (their normals more than 90 degrees apart), no triangle turns by more than the allowed
  // angle or loses its area, and no new edge is longer than the split threshold. Returns the
  // larger distance of the two old positions from the new triangles, or -1 if a check fails.
  double CollapseError(Index from, Index to, const Vec3& pos, bool check_long) const {
    if (glm::dot(VertexNormal(from), VertexNormal(to)) < 0.0 &&
        Length(from, to) > 0.2 * EdgeSize(from, to)) {
      return -1.0;
    }
    const double h_new = sizing_.At(pos, VertexNormal(to));
    double d_from = std::numeric_limits<double>::infinity(), d_to = d_from;
    // No new triangle sharper than min_angle_deg, or than the sharpest one there now.
    double old_angle = 180.0, new_angle = 180.0;
    for (Index v : {from, to}) {
      for (Index f : m.vertex_faces(v)) {
        const std::array<Index, 3>& t = m.face(f);
        old_angle =
            std::min(old_angle, MinAngle(m.position(t[0]), m.position(t[1]), m.position(t[2])));
      }
    }
    for (Index v : {from, to}) {
      for (Index f : m.vertex_faces(v)) {
        std::array<Index, 3> t = m.face(f);
        bool has_from = false, has_to = false;
        for (Index w : t) has_from |= w == from, has_to |= w == to;
        if (has_from && has_to) continue;
        std::array<Vec3, 3> x;
        for (int k = 0; k < 3; ++k) {
          const Index w = t[static_cast<std::size_t>(k)];
          x[static_cast<std::size_t>(k)] = (w == from || w == to) ? pos : m.position(w);
        }
        const Vec3 n_old = FaceNormal(f);
        const Vec3 n_new = glm::cross(x[1] - x[0], x[2] - x[0]);
        const double l_old = glm::length(n_old), l_new = glm::length(n_new);
        if (!(l_new > 1e-10 * h_new * h_new)) return -1.0;
        if (l_old > 0.0 && glm::dot(n_old, n_new) < cos_max_change_ * l_old * l_new) return -1.0;
        new_angle = std::min(new_angle, MinAngle(x[0], x[1], x[2]));
        d_from = std::min(
            d_from, glm::length(m.position(from) - ClosestPointOnTriangle(m.position(from), x[0],
                                                                          x[1], x[2], nullptr)));
        d_to = std::min(
            d_to, glm::length(m.position(to) -
                              ClosestPointOnTriangle(m.position(to), x[0], x[1], x[2], nullptr)));
        if (!check_long) continue;
        for (Index w : t) {
          if (w == from || w == to) continue;
          if (glm::length(pos - m.position(w)) > options_.split_ratio * 0.5 * (h_new + Size(w))) {
            return -1.0;
          }
        }
      }
    }
    if (new_angle < std::min(options_.min_angle_deg, old_angle)) return -1.0;
    // Along a crease: the new crease edges still follow it.
    if (CreaseChain(from, to) >= 0) {
      std::vector<Index> ring;
      for (Index v : {from, to}) {
        m.Neighbors(v, &ring);
        for (Index w : ring) {
          if (w == from || w == to) continue;
          const int c = CreaseChain(v, w);
          if (ChordTooFar(c, pos, m.position(w), h_new)) return -1.0;
        }
      }
    }
    const double error = std::max(d_from, d_to);
    const double limit = options_.max_collapse_error * std::min(h_new, EdgeSize(from, to));
    return error <= limit ? error : -1.0;
  }

  // Collapses edge {a, b} the way that keeps the surface closest (so the tip of an ear or a
  // finger stays where it is), if any way passes the checks.
  bool TryCollapse(Index a, Index b, bool check_long) {
    std::vector<CollapsePlan> plans;
    PlanCollapse(a, b, &plans);
    const CollapsePlan* best = nullptr;
    double best_error = 0.0;
    for (const CollapsePlan& p : plans) {
      if (!m.CanCollapse(p.from, p.to)) continue;
      const double e = CollapseError(p.from, p.to, p.pos, check_long);
      if (e < 0.0 || (best && !(e < best_error))) continue;
      best = &p, best_error = e;
    }
    if (!best) return false;
    const CollapsePlan p = *best;
    if (!crease_.empty()) {
      std::vector<Index> ring;
      m.Neighbors(p.from, &ring);
      for (Index w : ring) {
        const int c = CreaseChain(p.from, w);
        if (c < 0) continue;
        crease_.erase({std::min(p.from, w), std::max(p.from, w)});
        if (w != p.to) crease_[{std::min(p.to, w), std::max(p.to, w)}] = c;
      }
    }
    m.Collapse(p.from, p.to);
    m.position(p.to) = p.pos;
    UpdateSize(p.to);
    if (stats_) ++stats_->collapses;
    return true;
  }

  void CollapseShortEdges() {
    std::vector<std::array<Index, 2>> edges;
    m.Edges(&edges);
    std::vector<std::tuple<double, Index, Index>> order;
    for (const auto& e : edges) {
      const double r = Length(e[0], e[1]) / EdgeSize(e[0], e[1]);
      if (r < options_.collapse_ratio) order.emplace_back(r, e[0], e[1]);
    }
    std::sort(order.begin(), order.end());
    for (const auto& o : order) {
      const Index a = std::get<1>(o), b = std::get<2>(o);
      if (!m.vertex_alive(a) || !m.vertex_alive(b) || !m.HasEdge(a, b)) continue;
      if (!(Length(a, b) < options_.collapse_ratio * EdgeSize(a, b))) continue;
      TryCollapse(a, b, true);
    }
  }

  // Smallest angle of a triangle, degrees.
  static double MinAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 x[3] = {a, b, c};
    double lo = 180.0;
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = x[(k + 1) % 3] - x[k], w = x[(k + 2) % 3] - x[k];
      lo = std::min(lo,
                    std::atan2(glm::length(glm::cross(u, w)), glm::dot(u, w)) * 57.29577951308232);
    }
    return lo;
  }

  int Deviation(Index v, int valence) const {
    const int d = valence - (m.IsBoundaryVertex(v) ? 4 : 6);
    return d * d;
  }

  void EqualizeValences() {
    std::vector<std::array<Index, 2>> edges;
    m.Edges(&edges);
    for (const auto& e : edges) {
      const Index a = e[0], b = e[1];
      if (!m.HasEdge(a, b) || m.IsBoundaryEdge(a, b) || CreaseChain(a, b) >= 0) continue;
      const Index f1 = m.DirectedEdgeFace(a, b), f2 = m.DirectedEdgeFace(b, a);
      if (f1 == kInvalidIndex || f2 == kInvalidIndex) continue;
      const Index c = m.Opposite(f1, a, b), d = m.Opposite(f2, a, b);
      const int va = m.Valence(a), vb = m.Valence(b), vc = m.Valence(c), vd = m.Valence(d);
      const int before = Deviation(a, va) + Deviation(b, vb) + Deviation(c, vc) + Deviation(d, vd);
      const int after =
          Deviation(a, va - 1) + Deviation(b, vb - 1) + Deviation(c, vc + 1) + Deviation(d, vd + 1);
      const Vec3 &pa = m.position(a), &pb = m.position(b), &pc = m.position(c), &pd = m.position(d);
      // Flip to even out valences, or to remove a sliver: where the smallest angle of the pair
      // grows by 10 degrees and the valences do not get worse (from below 10 degrees: even if
      // they do).
      const double old_min = std::min(MinAngle(pa, pb, pc), MinAngle(pb, pa, pd));
      const double new_min = std::min(MinAngle(pa, pd, pc), MinAngle(pd, pb, pc));
      const bool sliver = new_min > old_min + 10.0 && (after <= before || old_min < 10.0);
      if ((after >= before && !sliver) || !m.CanFlip(a, b)) continue;
      // Along creases a flip may join a crease vertex's two neighbours into a flat triangle:
      // with creases, no flip makes a triangle sharper than min_angle_deg (or the old pair).
      if (!crease_.empty() && new_min < std::min(options_.min_angle_deg, old_min)) continue;
      const Vec3 n1 = glm::cross(pb - pa, pc - pa), n2 = glm::cross(pa - pb, pd - pb);
      const Vec3 n3 = glm::cross(pd - pa, pc - pa), n4 = glm::cross(pb - pd, pc - pd);
      const double l1 = glm::length(n1), l2 = glm::length(n2), l3 = glm::length(n3),
                   l4 = glm::length(n4);
      if (!(l3 > 1e-10 * (l1 + l2)) || !(l4 > 1e-10 * (l1 + l2))) continue;
      const Vec3 old_n = n1 / std::max(l1, 1e-300) + n2 / std::max(l2, 1e-300);
      // The new pair keeps the orientation and folds no more than the allowed angle.
      if (glm::dot(n3, old_n) <= 0.0 || glm::dot(n4, old_n) <= 0.0) continue;
      if (glm::dot(n3, n4) < cos_max_change_ * l3 * l4 &&
          glm::dot(n3, n4) * l1 * l2 < glm::dot(n1, n2) * l3 * l4) {
        continue;
      }
      // Not across a thin part (c and d on opposite sides), and the new pair still passes
      // near the old edge (no flip over a ridge much sharper than the mesh can follow).
      if (glm::dot(VertexNormal(c), VertexNormal(d)) < 0.0) continue;
      const Vec3 mid = 0.5 * (pa + pb);
      const double dev =
          std::min(glm::length(mid - ClosestPointOnTriangle(mid, pa, pd, pc, nullptr)),
                   glm::length(mid - ClosestPointOnTriangle(mid, pd, pb, pc, nullptr)));
      if (dev > options_.max_collapse_error * EdgeSize(a, b)) continue;
      m.Flip(a, b);
      if (stats_) ++stats_->flips;
    }
  }

  void Relax() {
    const Index n = m.num_vertex_slots();
    std::vector<Vec3> target(static_cast<std::size_t>(n));
    for (Index v = 0; v < n; ++v) {
      if (!m.vertex_alive(v)) continue;
      const Vec3 p = m.position(v);
      target[static_cast<std::size_t>(v)] = p;
      if (Feature(v) == kCornerFeature) continue;
      if (Feature(v) >= 0) {
        target[static_cast<std::size_t>(v)] = CreaseTarget(v, -1.0);
        continue;
      }
      if (m.IsBoundaryVertex(v)) {
        Index prev = kInvalidIndex, next = kInvalidIndex;
        m.BoundaryNeighbors(v, &prev, &next);
        if (prev == kInvalidIndex || next == kInvalidIndex) continue;
        // Along the loop, towards the point between the neighbours that splits the span in
        // proportion to the sizes.
        const double hp = EdgeSize(prev, v), hn = EdgeSize(v, next);
        target[static_cast<std::size_t>(v)] =
            ref_.LoopBetween(m.loop[static_cast<std::size_t>(v)], m.position(prev),
                             m.position(next), hp / (hp + hn));
        continue;
      }
      // Area-weighted centroid of the one-ring triangles, each weighted by the density
      // 1 / size^2 at its centroid (a Lloyd step for the sizing field).
      Vec3 c(0.0);
      double w = 0.0;
      for (Index f : m.vertex_faces(v)) {
        const std::array<Index, 3>& t = m.face(f);
        const double h = (Size(t[0]) + Size(t[1]) + Size(t[2])) / 3.0;
        const double a = glm::length(FaceNormal(f)) / (h * h);
        c += a * (m.position(t[0]) + m.position(t[1]) + m.position(t[2])) / 3.0;
        w += a;
      }
      if (!(w > 0.0)) continue;
      c /= w;
      // In the tangent plane of the reference surface (smooth vertex normals), not of the
      // coarse mesh, whose normal tilts at a tip and would let the tip slide down.
      const Vec3 nv = VertexNormal(v);
      const ClosestPoint here = ref_.Project(p, nv, Size(v));
      const Vec3 nr =
          here.triangle != kInvalidIndex ? ref_.Normal(here.triangle, here.barycentric) : nv;
      const Vec3 d = (c - p) - nr * glm::dot(c - p, nr);
      target[static_cast<std::size_t>(v)] = ProjectInside(p + d, nv, Size(v));
    }
    for (Index v = 0; v < n; ++v) {
      if (!m.vertex_alive(v)) continue;
      const Vec3 old = m.position(v);
      const Vec3 p = target[static_cast<std::size_t>(v)];
      if (p == old) continue;
      std::vector<Vec3> before;
      for (Index f : m.vertex_faces(v)) before.push_back(FaceNormal(f));
      m.position(v) = p;
      bool ok = true;
      std::size_t i = 0;
      // The old position (a point of the reference) must stay close to the new triangles, so
      // a tip does not creep down.
      double cover = std::numeric_limits<double>::infinity();
      for (Index f : m.vertex_faces(v)) {
        const Vec3 nn = FaceNormal(f);
        const Vec3& no = before[i++];
        const double ln = glm::length(nn), lo = glm::length(no);
        if (!(ln > 1e-10 * Size(v) * Size(v)) ||
            (lo > 0.0 && glm::dot(nn, no) < cos_max_change_ * ln * lo)) {
          ok = false;
          break;
        }
        const std::array<Index, 3>& t = m.face(f);
        cover = std::min(
            cover, glm::length(old - ClosestPointOnTriangle(old, m.position(t[0]), m.position(t[1]),
                                                            m.position(t[2]), nullptr)));
      }
      if (ok && cover > options_.max_relax_error * Size(v)) ok = false;
      if (!ok) {
        m.position(v) = old;
        if (stats_) ++stats_->rejected_moves;
      }
    }
  }

  // Untangling: a triangle that faces against all its neighbours (a fold) or has no area
  // moves its corners to the mean of their neighbours, projected back, until none is left (at
  // most `rounds` times). Returns the folds left.
  int Untangle(int rounds) {
    std::vector<char> marked;
    std::vector<Index> ring;
    for (int round = 0;; ++round) {
      marked.assign(static_cast<std::size_t>(m.num_vertex_slots()), 0);
      int folds = 0;
      for (Index f = 0; f < m.num_face_slots(); ++f) {
        if (!m.face_alive(f)) continue;
        const std::array<Index, 3>& t = m.face(f);
        // Turned over: against every neighbour (on a thin part a triangle faces away from
        // the neighbours across the rim but not from those on its own side).
        const Vec3 n = FaceNormal(f);
        int against = 0, neighbours = 0;
        for (int k = 0; k < 3; ++k) {
          const Index a = t[static_cast<std::size_t>(k)];
          const Index b = t[static_cast<std::size_t>((k + 1) % 3)];
          const Index g = m.DirectedEdgeFace(b, a);
          if (g == kInvalidIndex) continue;
          ++neighbours;
          against += glm::dot(n, FaceNormal(g)) < 0.0 ? 1 : 0;
        }
        const double ln = glm::length(n);
        if (ln > 1e-12 * Size(t[0]) * Size(t[0]) && (neighbours == 0 || against < neighbours)) {
          continue;
        }
        ++folds;
        for (Index v : t) marked[static_cast<std::size_t>(v)] = 1;
      }
      if (folds == 0 || round >= rounds) return folds;
      for (Index v = 0; v < m.num_vertex_slots(); ++v) {
        if (!marked[static_cast<std::size_t>(v)]) continue;
        if (Feature(v) == kCornerFeature) continue;
        if (Feature(v) >= 0) {
          m.position(v) = CreaseTarget(v, 0.5);
          continue;
        }
        if (m.IsBoundaryVertex(v)) {
          Index prev = kInvalidIndex, next = kInvalidIndex;
          m.BoundaryNeighbors(v, &prev, &next);
          if (prev == kInvalidIndex || next == kInvalidIndex) continue;
          m.position(v) = ref_.LoopBetween(m.loop[static_cast<std::size_t>(v)], m.position(prev),
                                           m.position(next), 0.5);
          continue;
        }
        m.Neighbors(v, &ring);
        Vec3 c(0.0), n(0.0);
        for (Index w : ring) c += m.position(w), n += VertexNormal(w);
        c /= static_cast<double>(ring.size());
        m.position(v) = ProjectInside(c, glm::length(n) > 0.0 ? n / glm::length(n) : n, Size(v));
      }
    }
  }

  void Load(const RemeshTriangles& mesh) {
    m.Init(mesh.positions, mesh.triangles);
    m.loop = mesh.loop;
    if (cr_ && mesh.feature.size() == mesh.positions.size()) {
      m.feature = mesh.feature;
      for (const auto& e : mesh.crease_edges) {
        const Index a = static_cast<Index>(e[0]), b = static_cast<Index>(e[1]);
        crease_[{std::min(a, b), std::max(a, b)}] = static_cast<int>(e[2]);
      }
    }
    UpdateSizes();
  }
  void Store(RemeshTriangles* mesh) {
    std::vector<Index> old_to_new;
    m.Compact(&old_to_new);
    m.Export(&mesh->positions, &mesh->triangles);
    mesh->loop = m.loop;
    if (!cr_ || mesh->feature.empty()) return;
    mesh->feature = m.feature;
    mesh->crease_edges.clear();
    for (const auto& e : crease_) {
      const Index a = old_to_new[static_cast<std::size_t>(e.first.first)];
      const Index b = old_to_new[static_cast<std::size_t>(e.first.second)];
      mesh->crease_edges.push_back({static_cast<std::uint32_t>(std::min(a, b)),
                                    static_cast<std::uint32_t>(std::max(a, b)),
                                    static_cast<std::uint32_t>(e.second)});
    }
    std::sort(mesh->crease_edges.begin(), mesh->crease_edges.end());
  }

 private:
  const ReferenceSurface& ref_;
  const CreaseChains* cr_;
  std::map<std::pair<Index, Index>, int> crease_;
  const SizingField& sizing_;
  IsotropicRemeshOptions options_;
  IsotropicRemeshStats* stats_;
  double cos_max_change_;
};

Status CheckMesh(const RemeshTriangles& mesh) {
  if (mesh.triangles.empty() || mesh.triangles.size() % 3 != 0 ||
      mesh.loop.size() != mesh.positions.size()) {
    return Status::InvalidInput("isotropic remesh: empty or mismatched triangle mesh");
  }
  for (std::uint32_t v : mesh.triangles) {
    if (v >= mesh.positions.size()) {
      return Status::InvalidInput("isotropic remesh: triangle index out of range");
    }
  }
  return Status::Ok();
}

}  // namespace

Status RemeshIsotropic(const ReferenceSurface& reference, const SizingField& sizing,
                       const IsotropicRemeshOptions& options, RemeshTriangles* mesh,
                       IsotropicRemeshStats* stats, const CreaseChains* creases) {
  Status s = CheckMesh(*mesh);
  if (!s.ok()) return s;
  Remesher r(reference, sizing, options, stats, creases);
  r.Load(*mesh);
  for (int it = 0; it < options.iterations; ++it) {
    r.SplitLongEdges();
    r.CollapseShortEdges();
    r.EqualizeValences();
    r.Relax();
    r.UpdateSizes();
  }
  r.Untangle(10);
  r.Store(mesh);
  return Status::Ok();
}

int AdjustVertexCount(const ReferenceSurface& reference, const SizingField& sizing, int delta,
                      const IsotropicRemeshOptions& options, RemeshTriangles* mesh,
                      const CreaseChains* creases) {
  if (delta == 0 || !CheckMesh(*mesh).ok()) return 0;
  Remesher r(reference, sizing, options, nullptr, creases);
  r.Load(*mesh);
  int done = 0;
  std::vector<std::array<Index, 2>> edges;
  while (done != delta) {
    r.m.Edges(&edges);
    std::vector<std::tuple<double, Index, Index>> order;
    for (const auto& e : edges) {
      order.emplace_back(r.Length(e[0], e[1]) / r.EdgeSize(e[0], e[1]), e[0], e[1]);
    }
    if (order.empty()) break;
    std::sort(order.begin(), order.end());
    if (delta > 0) {
      const auto& o = order.back();
      r.Split(std::get<1>(o), std::get<2>(o));
      ++done;
      continue;
    }
    bool collapsed = false;
    for (const auto& o : order) {
      if (r.TryCollapse(std::get<1>(o), std::get<2>(o), false)) {
        collapsed = true;
        break;
      }
    }
    if (!collapsed) break;
    --done;
  }
  for (int it = 0; it < 2; ++it) {
    r.EqualizeValences();
    r.Relax();
    r.UpdateSizes();
  }
  r.Untangle(10);
  r.Store(mesh);
  return done;
}

}  // namespace dermis
