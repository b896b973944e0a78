// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The morph-target bake of the shared Khronos characters (issue 5's acceptance test): fit ->
// CharacterPoser (sweep, LBS, DQS) -> BuildBakedAsset -> ExportGltf, then judged from outside:
// the Khronos glTF-Validator (no errors, no warnings) and three.js playing the baked file,
// whose vertex positions at sampled frame times must match the poser's (what `dermis animate`
// writes) within float32 rounding.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/character.h"
#include "support/external_checks.h"

namespace dermis {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

/// Largest distance between three.js's positions of a baked (or posed) file and the poser's, and
/// the bounding-box diagonal of the poser's.
double BakeDifference(const CharacterPoser& poser, const std::vector<PosedPrimitive>& posed,
                      const std::map<std::pair<int, int>, std::vector<double>>& three,
                      double* diagonal) {
  const std::vector<DrawnPrimitive>& drawn = poser.drawn();
  REQUIRE(three.size() == drawn.size());
  glm::dvec3 lo(1e300), hi(-1e300);
  double worst = 0.0;
  int node = -1;
  for (std::size_t d = 0; d < drawn.size(); ++d) {
    if (d == 0 || drawn[d - 1].node != drawn[d].node) ++node;  // BuildPosedAsset's nodes
    INFO("baked node " << node << " primitive " << drawn[d].primitive);
    const auto it = three.find({node, static_cast<int>(drawn[d].primitive)});
    REQUIRE(it != three.end());
    REQUIRE(it->second.size() == 3 * posed[d].positions.size());
    for (std::size_t v = 0; v < posed[d].positions.size(); ++v) {
      const glm::dvec3 theirs(it->second[3 * v], it->second[3 * v + 1], it->second[3 * v + 2]);
      worst = std::max(worst, glm::length(theirs - posed[d].positions[v]));
      lo = glm::min(lo, posed[d].positions[v]);
      hi = glm::max(hi, posed[d].positions[v]);
    }
  }
  *diagonal = glm::length(hi - lo);
  return worst;
}

void CheckBake(const std::string& name) {
  const std::string source = std::string(test::kSharedGltfDir) + name;
  if (!fs::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return;
  }
  if (!test::JsToolsReady()) return;
  INFO(name);
  TempDir tmp("dermis_bake");
  Asset asset;
  Status s = ImportGltf(source, &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  CharacterFitOptions fit_options;
  fit_options.fit.threads = 2;
  Character ch;
  s = FitCharacter(asset, fit_options, &ch, nullptr);
  INFO(s.message());
  REQUIRE(s.ok());
  REQUIRE(!ch.asset.animations.empty());

  const double fps = kDefaultPoseStepsPerSecond;
  for (const DeformerKind kind : {DeformerKind::kSweep, DeformerKind::kLbs, DeformerKind::kDqs}) {
    INFO(DeformerName(kind));
    CharacterPoseOptions options;
    options.deformer = kind;
    options.threads = 2;
    CharacterPoser poser;
    s = CharacterPoser::Build(ch, options, &poser);
    INFO(s.message());
    REQUIRE(s.ok());
    Asset baked;
    CharacterBakeReport report;
    s = BuildBakedAsset(&poser, fps, &baked, &report);
    INFO(s.message());
    REQUIRE(s.ok());
    const std::string file = tmp.File(std::string("baked_") + DeformerName(kind) + ".glb");
    GltfExportOptions gltf;
    s = ExportGltf(baked, gltf, file);
    INFO(s.message());
    REQUIRE(s.ok());
    const test::ValidatorReport validation = test::Validate(file, tmp);
    INFO(test::Messages(validation));
    CHECK(validation.errors == 0);
    CHECK(validation.warnings == 0);
    // The same bake with --quantize --compress (docs/gltf-compression.md): validator-clean,
    // and three.js (with its meshopt decoder) draws it within the reported position error
    // (the sweep's bake only, to keep the test short).
    const bool check_packed = kind == DeformerKind::kSweep;
    const std::string packed_file = tmp.File(std::string("packed_") + DeformerName(kind) + ".glb");
    GltfExportOptions packed_options;
    packed_options.quantize = packed_options.compress = true;
    GltfExportReport packed;
    if (check_packed) {
      s = ExportGltf(baked, packed_options, packed_file, &packed);
      INFO(s.message());
      REQUIRE(s.ok());
      const test::ValidatorReport packed_validation = test::Validate(packed_file, tmp);
      INFO(test::Messages(packed_validation));
      CHECK(packed_validation.errors == 0);
      CHECK(packed_validation.warning_codes.empty());
      // Our importer decodes it (meshopt, and the EXPONENTIAL filter of float normal deltas):
      // the morph normal deltas within the snorm16 step or the filter's reported error.
      Asset packed_back;
      s = ImportGltf(packed_file, &packed_back);
      INFO(s.message());
      REQUIRE(s.ok());
      const AssetPrimitive& a = baked.meshes[0].primitives[0];
      const AssetPrimitive& b = packed_back.meshes[0].primitives[0];
      REQUIRE(a.targets.size() == b.targets.size());
      double worst_normal = 0.0;
      for (std::size_t k = 0; k < a.targets.size(); ++k) {
        REQUIRE(a.targets[k].normals.size() == b.targets[k].normals.size());
        for (std::size_t v = 0; v < a.targets[k].normals.size(); ++v) {
          const glm::vec3 d = a.targets[k].normals[v] - b.targets[k].normals[v];
          worst_normal = std::max(
              worst_normal,
              static_cast<double>(std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)})));
        }
      }
      CHECK(worst_normal <= std::max(0.5 / 32767.0, packed.max_filtered_target_error) + 1e-6);
    }
    Asset back;
    s = ImportGltf(file, &back);
    INFO(s.message());
    REQUIRE(s.ok());
    REQUIRE(back.meshes.size() == baked.meshes.size());
    CHECK(back.meshes[0].primitives[0].targets.size() == report.targets);
    CHECK(back.animations.size() == ch.asset.animations.size());
    CHECK(back.skins.empty());

    // three.js plays the baked file: at rest, and at the first, a middle and the last frame of
    // every clip; the poser posed at those times (the bake's own steps) must agree.
    double worst_relative = 0.0;
    for (int clip = -1; clip < static_cast<int>(ch.asset.animations.size()); ++clip) {
      const std::vector<double> frames =
          clip < 0
              ? std::vector<double>{0.0}
              : ClipStepTimes(ch.asset.animations[static_cast<std::size_t>(clip)].Duration(), fps);
      std::vector<std::size_t> picks = {0, (frames.size() * 37) / 100, frames.size() - 1};
      picks.erase(std::unique(picks.begin(), picks.end()), picks.end());
      for (const std::size_t k : picks) {
        const double t = frames[k];
        INFO("clip " << clip << " frame " << k << " t = " << t);
        std::vector<PosedPrimitive> posed;
        s = poser.PoseClip(clip, t, fps, &posed);
        INFO(s.message());
        REQUIRE(s.ok());
        const auto three = test::ThreePose(file, clip, t, tmp);
        double diagonal = 0.0;
        const double worst = BakeDifference(poser, posed, three, &diagonal);
        CHECK(diagonal > 0.0);
        CHECK(worst < 1e-5 * diagonal);
        worst_relative = std::max(worst_relative, worst / diagonal);
        if (check_packed) {
          // The quantised file draws each mesh from a child node holding the dequantising
          // matrix (appended after the asset's nodes, in node order): key it by the parent.
          std::map<std::pair<int, int>, std::vector<double>> three_packed;
          std::map<int, int> parent_of;
          for (std::size_t n = 0, child = baked.nodes.size(); n < baked.nodes.size(); ++n) {
            if (baked.nodes[n].mesh >= 0 && baked.nodes[n].skin < 0) {
              parent_of[static_cast<int>(child++)] = static_cast<int>(n);
            }
          }
          for (auto& [key, positions] : test::ThreePose(packed_file, clip, t, tmp)) {
            auto it = parent_of.find(key.first);
            three_packed[{it == parent_of.end() ? key.first : it->second, key.second}] =
                std::move(positions);
          }
          const double packed_worst = BakeDifference(poser, posed, three_packed, &diagonal);
          CHECK(packed_worst < 1e-5 * diagonal + packed.max_position_error);
        }
      }
    }
    // What `dermis animate -o POSED.glb` writes: the static asset of one pose (clip 0 halfway),
    // validator-clean, drawn by three.js where the poser put it.
    {
      const double t = 0.5 * ch.asset.animations[0].Duration();
      INFO("posed asset, clip 0 at t = " << t);
      std::vector<PosedPrimitive> posed;
      s = poser.PoseClip(0, t, fps, &posed);
      INFO(s.message());
      REQUIRE(s.ok());
      Asset still;
      s = BuildPosedAsset(poser, posed, &still);
      INFO(s.message());
      REQUIRE(s.ok());
      const std::string posed_file = tmp.File(std::string("posed_") + DeformerName(kind) + ".glb");
      s = ExportGltf(still, GltfExportOptions{}, posed_file);
      INFO(s.message());
      REQUIRE(s.ok());
      const test::ValidatorReport posed_validation = test::Validate(posed_file, tmp);
      INFO(test::Messages(posed_validation));
      CHECK(posed_validation.errors == 0);
      CHECK(posed_validation.warnings == 0);
      const auto three = test::ThreePose(posed_file, -1, 0.0, tmp);
      double diagonal = 0.0;
      const double worst = BakeDifference(poser, posed, three, &diagonal);
      CHECK(diagonal > 0.0);
      CHECK(worst < 1e-5 * diagonal);
    }
    std::printf(
        "%-18s %-5s %zu clips, %4zu frames, %5zu vertices: %8.3f MB (--quantize --compress "
        "%.3f MB), validator %d errors %d warnings, three.js vs poser max %.2g of the "
        "diagonal\n",
        name.c_str(), DeformerName(kind), report.frames.size(), report.targets, report.vertices,
        static_cast<double>(fs::file_size(file)) / 1e6,
        check_packed ? static_cast<double>(fs::file_size(packed_file)) / 1e6 : 0.0,
        validation.errors, validation.warnings, worst_relative);
  }
}

TEST_CASE("bake: SimpleSkin baked and played by three.js", "[bake][data]") {
  CheckBake("SimpleSkin.gltf");
}
TEST_CASE("bake: RiggedSimple baked and played by three.js", "[bake][data]") {
  CheckBake("RiggedSimple.glb");
}
#if DERMIS_BAKE_EVERY_CHARACTER
// The larger characters in Release only (tests/CMakeLists.txt): the two above run the same
// exporter and player under the sanitizers, and these three took about two minutes of the
// sanitized run's budget (.ci/run).
TEST_CASE("bake: RiggedFigure baked and played by three.js", "[bake][data]") {
  CheckBake("RiggedFigure.glb");
}
TEST_CASE("bake: Fox baked and played by three.js", "[bake][data]") { CheckBake("Fox.glb"); }
TEST_CASE("bake: CesiumMan baked and played by three.js", "[bake][data]") {
  CheckBake("CesiumMan.glb");
}
#endif

}  // namespace
}  // namespace dermis
