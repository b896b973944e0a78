// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Dual-quaternion skinning (Kavan, Collins, Zara, O'Sullivan 2008; docs/notes/sweep.md section 3,
// "DQS"), the second baseline. Each skin matrix M_j = R_j S_j + t_j is split into its rigid part
// (rotation R_j by polar decomposition, translation t_j) and its stretch S_j. Per vertex the
// stretches are blended linearly and applied first (the two-phase variant), then the rigid
// parts are blended as unit dual quaternions, each flipped into the hemisphere of the strongest
// joint, and normalised by the norm of the real part.
#include <algorithm>
#include <cmath>
#include <vector>

#include "deform/deform_math.h"
#include "dermis/deform/deformer.h"

namespace dermis {
namespace {

class DqsDeformer final : public Deformer {
 public:
  DqsDeformer(std::size_t joints, const Vec3* rest, const Vec3* normals,
              const VertexWeights* influences, std::size_t count)
      : rest_(rest, rest + count),
        normals_(normals ? std::vector<Vec3>(normals, normals + count) : std::vector<Vec3>()),
        weights_(influences, influences + count),
        dq_(joints),
        stretch_(joints, glm::dmat3(1.0)),
        has_stretch_(false) {}

  DeformerKind kind() const override { return DeformerKind::kDqs; }
  std::size_t num_vertices() const override { return rest_.size(); }
  std::size_t num_joints() const override { return dq_.size(); }

  Status SetPose(const glm::dmat4* m) override {
    for (std::size_t j = 0; j < dq_.size(); ++j) {
      if (!deform::IsFinite(m[j])) {
        return Status::InvalidInput("dqs: skin matrix of joint " + std::to_string(j) +
                                    " is not finite");
      }
    }
    bool stretch = false;
    for (std::size_t j = 0; j < dq_.size(); ++j) {
      stretch = deform::SplitSkinMatrix(m[j], &dq_[j], &stretch_[j]) || stretch;
    }
    has_stretch_ = stretch;
    return Status::Ok();
  }

  void Deform(std::size_t begin, std::size_t end, Vec3* positions, Vec3* normals) const override {
    end = std::min(end, rest_.size());
    const bool want_normals = normals != nullptr && !normals_.empty();
    for (std::size_t v = begin; v < end; ++v) {
      deform::DqsPoint(dq_.data(), stretch_.data(), has_stretch_, weights_[v], rest_[v],
                       want_normals ? normals_[v] : Vec3(0.0), &positions[v],
                       want_normals ? &normals[v] : nullptr);
    }
  }

 private:
  std::vector<Vec3> rest_;
  std::vector<Vec3> normals_;
  std::vector<VertexWeights> weights_;
  std::vector<deform::DualQuat> dq_;
  std::vector<glm::dmat3> stretch_;
  bool has_stretch_;
};

}  // namespace

Status MakeDqsDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                       const VertexWeights* influences, std::size_t count,
                       std::unique_ptr<Deformer>* out) {
  const Status s = ValidateRig(rig, influences, count, "dqs");
  if (!s.ok()) return s;
  *out = std::make_unique<DqsDeformer>(rig.parents.size(), rest_positions, rest_normals, influences,
                                       count);
  return Status::Ok();
}

}  // namespace dermis
