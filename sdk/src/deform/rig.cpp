// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Rig validation (docs/deformation.md section "Rigs").
#include <cmath>
#include <string>

#include "deform/deform_math.h"
#include "dermis/deform/deformer.h"

namespace dermis {

Status ValidateRig(const SkinRig& rig, const VertexWeights* influences, std::size_t count,
                   const std::string& name) {
  const std::size_t n = rig.parents.size();
  auto joint = [&](std::size_t j) {
    std::string s = "joint " + std::to_string(j);
    if (j < rig.names.size() && !rig.names[j].empty()) s += " (" + rig.names[j] + ")";
    return s;
  };
  if (n == 0) return Status::InvalidInput(name + ": the rig has no joints");
  if (n > 65535) return Status::InvalidInput(name + ": more than 65535 joints");
  if (rig.bind.size() != n) {
    return Status::InvalidInput(name + ": " + std::to_string(rig.bind.size()) +
                                " bind matrices for " + std::to_string(n) + " joints");
  }
  for (std::size_t j = 0; j < n; ++j) {
    const Index p = rig.parents[j];
    if (p < -1 || p >= static_cast<Index>(n) || p == static_cast<Index>(j)) {
      return Status::InvalidInput(name + ": " + joint(j) + ": parent " + std::to_string(p) +
                                  " is not a joint of the rig");
    }
    if (!deform::IsFinite(rig.bind[j])) {
      return Status::InvalidInput(name + ": " + joint(j) + ": bind matrix is not finite");
    }
    const double det = glm::determinant(glm::dmat3(rig.bind[j]));
    if (!(std::fabs(det) > 1e-12)) {
      return Status::InvalidInput(name + ": " + joint(j) + ": bind matrix is singular");
    }
  }
  // Cycles: walking up from any joint must reach a root within n steps.
  for (std::size_t j = 0; j < n; ++j) {
    Index p = rig.parents[j];
    std::size_t steps = 0;
    while (p >= 0 && steps <= n) {
      p = rig.parents[static_cast<std::size_t>(p)];
      ++steps;
    }
    if (steps > n) {
      return Status::InvalidInput(name + ": " + joint(j) + ": the joint hierarchy has a cycle");
    }
  }
  for (std::size_t v = 0; v < count; ++v) {
    const VertexWeights& w = influences[v];
    float sum = 0.0f;
    for (int k = 0; k < 4; ++k) {
      if (!std::isfinite(w.weights[k]) || w.weights[k] < 0.0f) {
        return Status::InvalidInput(name + ": vertex " + std::to_string(v) +
                                    ": weights must be finite and non-negative");
      }
      if (w.weights[k] > 0.0f && w.joints[k] >= n) {
        return Status::InvalidInput(name + ": vertex " + std::to_string(v) + ": joint " +
                                    std::to_string(w.joints[k]) + " is out of range (" +
                                    std::to_string(n) + " joints)");
      }
      sum += w.weights[k];
    }
    if (!(sum > 1e-6f)) {
      return Status::InvalidInput(name + ": vertex " + std::to_string(v) +
                                  ": weights sum to 0 (no joint moves it)");
    }
  }
  return Status::Ok();
}

}  // namespace dermis
