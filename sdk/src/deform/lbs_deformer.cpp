// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Linear blend skinning of control vertices, the baseline (docs/notes/sweep.md section 3, "LBS"):
// x' = sum_j w_j M_j x, normals by the inverse transpose of the blended matrix.
#include <algorithm>
#include <vector>

#include "deform/deform_math.h"
#include "dermis/deform/deformer.h"

namespace dermis {
namespace {

class LbsDeformer final : public Deformer {
 public:
  LbsDeformer(std::size_t joints, const Vec3* rest, const Vec3* normals,
              const VertexWeights* influences, std::size_t count)
      : rest_(rest, rest + count),
        normals_(normals ? std::vector<Vec3>(normals, normals + count) : std::vector<Vec3>()),
        weights_(influences, influences + count),
        palette_(joints, glm::dmat4(1.0)) {}

  DeformerKind kind() const override { return DeformerKind::kLbs; }
  std::size_t num_vertices() const override { return rest_.size(); }
  std::size_t num_joints() const override { return palette_.size(); }

  Status SetPose(const glm::dmat4* skin_matrices) override {
    for (std::size_t j = 0; j < palette_.size(); ++j) {
      if (!deform::IsFinite(skin_matrices[j])) {
        return Status::InvalidInput("lbs: skin matrix of joint " + std::to_string(j) +
                                    " is not finite");
      }
    }
    std::copy(skin_matrices, skin_matrices + palette_.size(), palette_.begin());
    return Status::Ok();
  }

  void Deform(std::size_t begin, std::size_t end, Vec3* positions, Vec3* normals) const override {
    end = std::min(end, rest_.size());
    for (std::size_t v = begin; v < end; ++v) {
      const VertexWeights& iw = weights_[v];
      const glm::dvec4 w = deform::NormalizedWeights(iw);
      glm::dmat4 m(0.0);
      for (int k = 0; k < 4; ++k) {
        if (w[k] > 0.0) m += w[k] * palette_[iw.joints[k]];
      }
      positions[v] = Vec3(m * glm::dvec4(rest_[v], 1.0));
      if (normals != nullptr && !normals_.empty()) {
        // Inverse transpose = cofactor / det: the cofactor alone has the right direction (up to
        // the sign of det) and stays defined when the blend loses a rank.
        const glm::dmat3 linear(m);
        Vec3 n = deform::Cofactor(linear) * normals_[v];
        if (glm::determinant(linear) < 0.0) n = -n;
        const double len = glm::length(n);
        normals[v] = len > 0.0 ? n / len : normals_[v];
      }
    }
  }

 private:
  std::vector<Vec3> rest_;
  std::vector<Vec3> normals_;
  std::vector<VertexWeights> weights_;
  std::vector<glm::dmat4> palette_;
};

}  // namespace

Status MakeLbsDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                       const VertexWeights* influences, std::size_t count,
                       std::unique_ptr<Deformer>* out) {
  const Status s = ValidateRig(rig, influences, count, "lbs");
  if (!s.ok()) return s;
  *out = std::make_unique<LbsDeformer>(rig.parents.size(), rest_positions, rest_normals, influences,
                                       count);
  return Status::Ok();
}

}  // namespace dermis
