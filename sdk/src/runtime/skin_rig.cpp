// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The skeleton of one glTF skin as the deformers see it (docs/notes/sweep.md section 2): joint
// parents within the skin and bind matrices from the inverse bind matrices.
#include <cmath>
#include <map>
#include <string>

#include "dermis/runtime/character.h"

namespace dermis {
namespace {

std::string SkinPointer(Index skin) { return "/skins/" + std::to_string(skin); }

}  // namespace

Status MakeSkinRig(const Asset& asset, Index skin, SkinRig* out) {
  if (skin < 0 || static_cast<std::size_t>(skin) >= asset.skins.size()) {
    return Status::InvalidInput(asset.source + ": skin " + std::to_string(skin) +
                                " does not exist");
  }
  const AssetSkin& s = asset.skins[static_cast<std::size_t>(skin)];
  const std::size_t n = s.joints.size();
  std::map<Index, Index> joint_of_node;
  for (std::size_t j = 0; j < n; ++j) joint_of_node.emplace(s.joints[j], static_cast<Index>(j));
  SkinRig rig;
  rig.parents.assign(n, -1);
  rig.bind.assign(n, glm::dmat4(1.0));
  rig.names.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Index node = s.joints[j];
    if (node < 0 || static_cast<std::size_t>(node) >= asset.nodes.size()) {
      return Status::InvalidInput(asset.source + ": " + SkinPointer(skin) + "/joints/" +
                                  std::to_string(j) + ": node " + std::to_string(node) +
                                  " does not exist");
    }
    rig.names[j] = asset.nodes[static_cast<std::size_t>(node)].name;
    // Nearest ancestor that is a joint of this skin (at most one step per node: no cycles).
    Index p = asset.nodes[static_cast<std::size_t>(node)].parent;
    for (std::size_t steps = 0; p >= 0 && steps <= asset.nodes.size(); ++steps) {
      const auto it = joint_of_node.find(p);
      if (it != joint_of_node.end()) {
        rig.parents[j] = it->second;
        break;
      }
      p = asset.nodes[static_cast<std::size_t>(p)].parent;
    }
    if (j < s.inverse_bind_matrices.size()) {
      const glm::dmat4 ibm(s.inverse_bind_matrices[j]);
      const double det = glm::determinant(glm::dmat3(ibm));
      if (!std::isfinite(det) || !(std::fabs(det) > 1e-300)) {
        return Status::InvalidInput(asset.source + ": " + SkinPointer(skin) +
                                    "/inverseBindMatrices/" + std::to_string(j) +
                                    ": not invertible");
      }
      rig.bind[j] = glm::inverse(ibm);
    }
  }
  const Status v = ValidateRig(rig, nullptr, 0, asset.source + ": " + SkinPointer(skin));
  if (!v.ok()) return v;
  *out = std::move(rig);
  return Status::Ok();
}

}  // namespace dermis
