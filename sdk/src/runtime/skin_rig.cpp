// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The skeleton of one glTF skin as the deformers see it (docs/notes/sweep.md section 2): joint
// parents within the skin and bind matrices from the inverse bind matrices.
#include <cmath>
#include <map>
#include <string>

#include "dermis/runtime/character.h"
#include "dermis/runtime/runtime.h"

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

Status RuntimeCharacter::RemapJointsByName(std::size_t p,
                                           const std::vector<std::string_view>& engine_names,
                                           std::vector<std::int32_t>* remap) const {
  const std::string& file = character_.asset.source;
  if (p >= num_parts())
    return Status::InvalidInput(file + ": part " + std::to_string(p) + " does not exist");
  if (engine_names.size() > static_cast<std::size_t>(INT32_MAX))
    return Status::InvalidInput("joint remap: more than 2^31 - 1 engine joints");
  const SkinRig* r = rig(p);
  std::vector<std::int32_t> result(r ? r->parents.size() : 0, -1);
  if (!r) {
    *remap = std::move(result);
    return Status::Ok();
  }
  std::map<std::string_view, std::int32_t> by_name;
  std::map<std::string_view, bool> duplicate;
  for (std::size_t i = 0; i < engine_names.size(); ++i) {
    if (!by_name.emplace(engine_names[i], static_cast<std::int32_t>(i)).second)
      duplicate[engine_names[i]] = true;
  }
  for (std::size_t j = 0; j < result.size(); ++j) {
    const std::string_view name =
        j < r->names.size() ? std::string_view(r->names[j]) : std::string_view();
    const auto it = by_name.find(name);
    if (name.empty() || it == by_name.end()) {
      return Status::InvalidInput(file + ": part " + std::to_string(p) + ": skin joint " +
                                  std::to_string(j) + " (\"" + std::string(name) +
                                  "\") is not among the engine's " +
                                  std::to_string(engine_names.size()) + " joints");
    }
    if (duplicate.count(name)) {
      return Status::InvalidInput(file + ": part " + std::to_string(p) +
                                  ": the engine lists joint \"" + std::string(name) +
                                  "\" more than once");
    }
    result[j] = it->second;
  }
  *remap = std::move(result);
  return Status::Ok();
}

}  // namespace dermis
