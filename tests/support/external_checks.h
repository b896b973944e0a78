// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: the external JavaScript checks of tests/js (the
// Khronos glTF-Validator and three.js's GLTFLoader in Node), shared by the glTF and character
// pipeline tests. Uses Catch2 assertions, so call it from inside a TEST_CASE.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "dermis/asset/asset.h"
#include "support/temp_files.h"

namespace dermis {
namespace test {

/// The shared third-party glTF characters (relative to the repository root, where ctest runs).
inline const char* const kSharedGltfDir = "../shared/data/gltf/";

/// Runs a shell command; its exit status, or -1 if it did not exit normally.
int Run(const std::string& command);

/// True if node and tests/js/node_modules are installed. If not: FAILs when the CI variable is
/// set (CI must run every external check), otherwise WARNs and returns false.
bool JsToolsReady();

/// What tests/js/validate.js reports for one file.
struct ValidatorReport {
  int errors = 0;
  int warnings = 0;
  std::set<std::string> error_codes, warning_codes;
  nlohmann::json raw;
};

/// Runs the Khronos glTF-Validator on `file` (scratch files go to `tmp`).
ValidatorReport Validate(const std::string& file, const TempDir& tmp);

/// Every message of a report, one per line: "severity code pointer message".
std::string Messages(const ValidatorReport& report);

/// World positions of every drawn (node, primitive) as three.js's GLTFLoader and
/// SkinnedMesh.applyBoneTransform compute them (tests/js/three_pose.js): the rest pose when
/// `clip` < 0, else clip `clip` at `time` seconds. Flat xyz per vertex.
std::map<std::pair<int, int>, std::vector<double>> ThreePose(const std::string& gltf, int clip,
                                                             double time, const TempDir& tmp);

/// Largest distance between three.js's positions and PosePrimitive()'s for the same pose of
/// `asset` (which must be the asset three.js read); `diagonal` receives the bounding box
/// diagonal of our posed positions. CHECKs that both drew the same primitives.
double PoseDifference(const Asset& asset, int clip, double time,
                      const std::map<std::pair<int, int>, std::vector<double>>& three,
                      double* diagonal);

/// Poses `asset` (re-imported from `gltf`) with three.js and with PosePrimitive() at rest and at
/// the start, 37 % and end of every clip; CHECKs they agree within 1e-4 of the diagonal.
void CheckThreeMatchesOurPoses(const std::string& gltf, const Asset& asset, const TempDir& tmp);

/// CHECKs equal counts of nodes, skins (and their joints), animations (channels, samplers),
/// materials, textures and images (and equal image bytes).
void CheckSameSceneCounts(const Asset& a, const Asset& b);
/// CheckSameSceneCounts() plus the same meshes, primitives, vertex counts and indices.
void CheckSameCounts(const Asset& a, const Asset& b);

}  // namespace test
}  // namespace dermis
