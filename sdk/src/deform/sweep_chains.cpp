// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The chains of the sweep deformer (docs/deformation.md, "Chains"; docs/notes/sweep.md section 2
// reads chains off the skeleton, this file makes every joint that carries skin own a bone): the
// continuation of a chain through branch joints, chains starting at their first skinned joint,
// and the virtual end bone of a skinned last joint.
#include "dermis/deform/sweep_chains.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "deform/deform_math.h"

namespace dermis {

Status BuildSweepChains(const SkinRig& rig, const Vec3* rest, const VertexWeights* influences,
                        std::size_t count, const SweepOptions& options,
                        std::vector<SweepChain>* out) {
  const Status st = ValidateRig(rig, influences, count, "sweep");
  if (!st.ok()) return st;
  out->clear();
  const std::size_t n = rig.parents.size();
  std::vector<Vec3> bind(n);
  double scale = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    bind[j] = Vec3(rig.bind[j][3]);
    scale = std::max(scale, glm::length(bind[j]));
  }
  for (std::size_t v = 0; v < count; ++v) scale = std::max(scale, glm::length(rest[v]));
  if (!(scale > 0.0)) scale = 1.0;
  const double min_bone = 1e-9 * scale;
  auto bone_ok = [&](std::size_t from, std::size_t to) {
    return glm::length(bind[to] - bind[from]) > min_bone;
  };
  std::vector<std::vector<std::size_t>> children(n);
  for (std::size_t j = 0; j < n; ++j) {
    if (rig.parents[j] >= 0) children[static_cast<std::size_t>(rig.parents[j])].push_back(j);
  }
  // Skin weight carried by each joint and by its subtree.
  std::vector<double> skin(n, 0.0);
  for (std::size_t v = 0; v < count; ++v) {
    const glm::dvec4 w = deform::NormalizedWeights(influences[v]);
    for (int k = 0; k < 4; ++k) {
      if (w[k] > 0.0) skin[influences[v].joints[k]] += w[k];
    }
  }
  std::vector<double> subtree = skin;
  for (std::size_t j = 0; j < n; ++j) {
    for (Index up = rig.parents[j]; up >= 0; up = rig.parents[static_cast<std::size_t>(up)]) {
      subtree[static_cast<std::size_t>(up)] += skin[j];
    }
  }
  // The child each joint's chain continues into (or none).
  std::vector<Index> next(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    const Index p = rig.parents[j];
    const bool incoming = p >= 0 && skin[static_cast<std::size_t>(p)] > 0.0 &&
                          bone_ok(static_cast<std::size_t>(p), j);
    const Vec3 t_in =
        incoming ? glm::normalize(bind[j] - bind[static_cast<std::size_t>(p)]) : Vec3(0.0);
    double best_score = 0.0;
    for (const std::size_t c : children[j]) {
      if (!bone_ok(j, c)) continue;
      const double score =
          incoming ? glm::dot(t_in, glm::normalize(bind[c] - bind[j])) : subtree[c];
      if (next[j] < 0 || score > best_score) {
        next[j] = static_cast<Index>(c);
        best_score = score;
      }
    }
  }
  // The bone before each joint within its chain (the parent, if the parent continues into
  // it), or -1.
  std::vector<Index> before(n, -1);
  for (std::size_t j = 0; j < n; ++j) {
    const Index p = rig.parents[j];
    if (p >= 0 && next[static_cast<std::size_t>(p)] == static_cast<Index>(j)) before[j] = p;
  }
  // The virtual end bone of each skinned joint that continues into no child: along its vertices.
  std::vector<Vec3> end(n, Vec3(0.0));
  std::vector<SweepChain::EndDirection> end_direction(n, SweepChain::EndDirection::kNone);
  for (std::size_t leaf = 0; leaf < n; ++leaf) {
    if (next[leaf] >= 0 || !(skin[leaf] > 0.0)) continue;
    Vec3 centroid(0.0);
    double wsum = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
      const glm::dvec4 w = deform::NormalizedWeights(influences[v]);
      for (int k = 0; k < 4; ++k) {
        if (w[k] > 0.0 && influences[v].joints[k] == leaf) {
          centroid += w[k] * rest[v];
          wsum += w[k];
        }
      }
    }
    centroid /= wsum;
    double spread = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
      const glm::dvec4 w = deform::NormalizedWeights(influences[v]);
      for (int k = 0; k < 4; ++k) {
        if (w[k] > 0.0 && influences[v].joints[k] == leaf) {
          const Vec3 d = rest[v] - centroid;
          spread += w[k] * glm::dot(d, d);
        }
      }
    }
    spread = std::sqrt(spread / wsum);
    const Vec3 q = bind[leaf];
    const Index p = before[leaf];
    const double len_in = p >= 0 ? glm::length(q - bind[static_cast<std::size_t>(p)]) : 0.0;
    Vec3 dir;
    if (glm::length(centroid - q) > 0.25 * spread && glm::length(centroid - q) > min_bone) {
      dir = glm::normalize(centroid - q);
      end_direction[leaf] = SweepChain::EndDirection::kSkin;
    } else if (len_in > 0.0) {
      dir = (q - bind[static_cast<std::size_t>(p)]) / len_in;
      end_direction[leaf] = SweepChain::EndDirection::kIncoming;
    } else {
      dir = Vec3(rig.bind[leaf][1]);
      dir = glm::length(dir) > 0.0 ? glm::normalize(dir) : Vec3(0.0, 1.0, 0.0);
      end_direction[leaf] = SweepChain::EndDirection::kLocalFrame;
    }
    // Length: as far as its vertices reach along it, at least half the bone before it (or
    // their spread), never degenerate.
    double reach = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
      const VertexWeights& iw = influences[v];
      for (int k = 0; k < 4; ++k) {
        if (iw.weights[k] > 0.0f && iw.joints[k] == leaf) {
          reach = std::max(reach, glm::dot(rest[v] - q, dir));
        }
      }
    }
    end[leaf] = q + std::max({reach, p >= 0 ? 0.5 * len_in : spread, 1e-6 * scale}) * dir;
  }
  // Cuts: where the skin is too thick for the bones, a joint's largest blend zone (half-length
  // max_blend_fraction * the shorter bone) folds as soon as its arc radius, that half-length /
  // tan(theta / 2), falls below the skin radius. A joint whose fold angle is below
  // min_fold_angle, or below its own rest bend, ends its chain and starts the next one; the
  // skin around it blends the two chains' frames (a torso or neck on short spine bones, a
  // bushy tail, a foot bent at rest).
  std::vector<bool> cut(n, false);
  for (std::size_t j = 0; j < n; ++j) {
    const Index p = before[j];
    if (p < 0) continue;
    const Vec3 a = bind[static_cast<std::size_t>(p)], b = bind[j];
    const Vec3 c = next[j] >= 0 ? bind[static_cast<std::size_t>(next[j])] : end[j];
    if (next[j] < 0 && end_direction[j] == SweepChain::EndDirection::kNone) continue;
    const Vec3 t1 = glm::normalize(b - a), t2 = glm::normalize(c - b);
    const double theta = std::atan2(glm::length(glm::cross(t1, t2)), glm::dot(t1, t2));
    const double shorter = std::min(glm::length(b - a), glm::length(c - b));
    std::vector<double> dist, far;
    for (std::size_t v = 0; v < count; ++v) {
      // The skin of these two bones: vertices with at least half their weight on P, J or the
      // joint after J (not the torso beside a hanging arm).
      const glm::dvec4 w = deform::NormalizedWeights(influences[v]);
      double mine = 0.0;
      for (int k = 0; k < 4; ++k) {
        const Index jk = static_cast<Index>(influences[v].joints[k]);
        if (jk == static_cast<Index>(j) || jk == p || (next[j] >= 0 && jk == next[j])) mine += w[k];
      }
      if (!(mine >= 0.5)) continue;
      // Closest point on the two bones, kept if within half the shorter bone of the joint.
      const Vec3 x = rest[v];
      const double f1 = std::clamp(glm::dot(x - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
      const double f2 = std::clamp(glm::dot(x - b, c - b) / glm::dot(c - b, c - b), 0.0, 1.0);
      const Vec3 q1 = a + f1 * (b - a), q2 = b + f2 * (c - b);
      const double d1 = glm::length(x - q1), d2 = glm::length(x - q2);
      const Vec3 q = d1 < d2 ? q1 : q2;
      (glm::length(q - b) <= 0.5 * shorter ? dist : far).push_back(std::min(d1, d2));
    }
    // None of that skin around the joint (all of it nearest to a far part of a bone: skin well
    // off the bone axis, toward which a virtual end bone leans): its radius is that of all the
    // bones' skin, else the sweep would carry it through the joint's arc as if it lay on the
    // bone.
    if (dist.empty()) dist.swap(far);
    if (dist.empty()) continue;
    std::sort(dist.begin(), dist.end());
    const double radius = dist[std::min(
        dist.size() - 1, static_cast<std::size_t>(0.9 * static_cast<double>(dist.size())))];
    // The bend at which the largest blend zone's arc gets tighter than the skin (and the sweep
    // folds): cut where that is below min_fold_angle or below the rest bend itself.
    const double fold = 2.0 * std::atan2(options.max_blend_fraction * shorter, radius);
    cut[j] = fold < std::max(options.min_fold_angle, theta);
  }
  for (std::size_t head = 0; head < n; ++head) {
    const Index p = rig.parents[head];
    if (p >= 0 && next[static_cast<std::size_t>(p)] == static_cast<Index>(head) && !cut[head]) {
      continue;
    }
    SweepChain c;
    Index cur = static_cast<Index>(head);
    bool ended_by_cut = false;
    for (;;) {
      // Leading joints without skin own no bone.
      if (!c.joints.empty() || skin[static_cast<std::size_t>(cur)] > 0.0) {
        c.joints.push_back(cur);
        c.points.push_back(bind[static_cast<std::size_t>(cur)]);
      }
      const Index nx = next[static_cast<std::size_t>(cur)];
      if (nx < 0) break;
      cur = nx;
      if (cut[static_cast<std::size_t>(cur)]) {
        // The cut joint ends this chain (owning no bone in it) and heads the next.
        if (!c.joints.empty()) {
          c.joints.push_back(cur);
          c.points.push_back(bind[static_cast<std::size_t>(cur)]);
          ended_by_cut = true;
        }
        break;
      }
    }
    if (c.joints.empty()) continue;
    const std::size_t last = static_cast<std::size_t>(c.joints.back());
    if (!ended_by_cut && end_direction[last] != SweepChain::EndDirection::kNone) {
      c.points.push_back(end[last]);
      c.virtual_end = true;
      c.end_direction = end_direction[last];
    }
    if (c.points.size() < 2) continue;  // an unskinned joint alone: nothing to sweep
    out->push_back(std::move(c));
  }
  return Status::Ok();
}

}  // namespace dermis
