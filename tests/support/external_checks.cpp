// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/external_checks.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <fstream>
#include <glm/glm.hpp>
#include <iterator>
#include <limits>
#include <sstream>

#include "dermis/asset/asset_pose.h"

namespace dermis {
namespace test {

namespace fs = std::filesystem;
using nlohmann::json;

int Run(const std::string& command) {
  const int rc = std::system(command.c_str());
  if (rc == -1 || !WIFEXITED(rc)) return -1;
  return WEXITSTATUS(rc);
}

bool JsToolsReady() {
  std::string missing;
  if (Run("node --version >/dev/null 2>&1") != 0) {
    missing = "node is not installed";
  } else if (!fs::exists("tests/js/node_modules/gltf-validator/package.json") ||
             !fs::exists("tests/js/node_modules/three/package.json")) {
    missing = "tests/js/node_modules is missing";
  }
  if (missing.empty()) return true;
  if (std::getenv("CI") != nullptr) {
    FAIL(missing << " (CI is set: run scripts/setup_js.sh before the tests)");
  }
  WARN("skipped: run scripts/setup_js.sh (" << missing << ")");
  return false;
}

ValidatorReport Validate(const std::string& file, const TempDir& tmp) {
  const std::string out = tmp.File("validator.json"), err = tmp.File("validator.err");
  const int rc =
      Run("node tests/js/validate.js '" + file + "' --json >'" + out + "' 2>'" + err + "'");
  INFO("validate.js stderr: " << ReadFile(err));
  REQUIRE((rc == 0 || rc == 1));
  ValidatorReport report;
  report.raw = json::parse(ReadFile(out));
  report.errors = report.raw["issues"]["numErrors"].get<int>();
  report.warnings = report.raw["issues"]["numWarnings"].get<int>();
  for (const json& m : report.raw["issues"]["messages"]) {
    const int severity = m["severity"].get<int>();
    if (severity == 0) report.error_codes.insert(m["code"].get<std::string>());
    if (severity == 1) report.warning_codes.insert(m["code"].get<std::string>());
  }
  CHECK(rc == (report.errors > 0 ? 1 : 0));
  return report;
}

std::string Messages(const ValidatorReport& report) {
  std::string text;
  for (const json& m : report.raw["issues"]["messages"]) {
    text += std::to_string(m["severity"].get<int>()) + " " + m["code"].get<std::string>() + " " +
            m.value("pointer", std::string()) + " " + m["message"].get<std::string>() + "\n";
  }
  return text;
}

std::map<std::pair<int, int>, std::vector<double>> ThreePose(const std::string& gltf, int clip,
                                                             double time, const TempDir& tmp) {
  const std::string out = tmp.File("pose.json"), err = tmp.File("pose.err");
  std::ostringstream cmd;
  cmd.precision(17);
  cmd << "node tests/js/three_pose.js '" << gltf << "' '" << out << "'";
  if (clip >= 0) cmd << " --clip " << clip << " --time " << time;
  cmd << " 2>'" << err << "'";
  const int rc = Run(cmd.str());
  INFO("three_pose.js stderr: " << ReadFile(err));
  REQUIRE(rc == 0);
  const json doc = json::parse(ReadFile(out));
  std::map<std::pair<int, int>, std::vector<double>> result;
  for (const json& m : doc["meshes"]) {
    result[{m["node"].get<int>(), m["primitive"].get<int>()}] =
        m["positions"].get<std::vector<double>>();
  }
  return result;
}

double PoseDifference(const Asset& asset, int clip, double time,
                      const std::map<std::pair<int, int>, std::vector<double>>& three,
                      double* diagonal) {
  AssetPose pose;
  if (clip >= 0) {
    SamplePose(asset, clip, time, &pose);
  } else {
    RestPose(asset, &pose);
  }
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(asset, pose, &world);
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  double worst = 0.0;
  std::size_t drawn = 0;
  for (std::size_t n = 0; n < asset.nodes.size(); ++n) {
    const Index mesh = asset.nodes[n].mesh;
    if (mesh < 0) continue;
    const auto& primitives = asset.meshes[static_cast<std::size_t>(mesh)].primitives;
    for (std::size_t p = 0; p < primitives.size(); ++p) {
      const auto it = three.find({static_cast<int>(n), static_cast<int>(p)});
      INFO("node " << n << " primitive " << p);
      REQUIRE(it != three.end());
      ++drawn;
      std::vector<glm::dvec3> ours;
      PosePrimitive(asset, pose, world, static_cast<Index>(n), primitives[p], &ours, nullptr);
      REQUIRE(it->second.size() == 3 * ours.size());
      for (std::size_t v = 0; v < ours.size(); ++v) {
        const glm::dvec3 theirs(it->second[3 * v], it->second[3 * v + 1], it->second[3 * v + 2]);
        worst = std::max(worst, glm::length(theirs - ours[v]));
        lo = glm::min(lo, ours[v]);
        hi = glm::max(hi, ours[v]);
      }
    }
  }
  CHECK(drawn == three.size());
  *diagonal = glm::length(hi - lo);
  return worst;
}

void CheckThreeMatchesOurPoses(const std::string& gltf, const Asset& asset, const TempDir& tmp) {
  INFO(gltf);
  for (int clip = -1; clip < static_cast<int>(asset.animations.size()); ++clip) {
    const double duration =
        clip < 0 ? 0.0 : asset.animations[static_cast<std::size_t>(clip)].Duration();
    for (const double fraction : {0.0, 0.37, 1.0}) {
      if (clip < 0 && fraction > 0.0) break;
      const double t = fraction * duration;
      INFO("clip " << clip << " at t = " << t);
      const auto three = ThreePose(gltf, clip, t, tmp);
      double diagonal = 0.0;
      const double worst = PoseDifference(asset, clip, t, three, &diagonal);
      CHECK(diagonal > 0.0);
      CHECK(worst < 1e-4 * diagonal);
    }
  }
}

void CheckSameSceneCounts(const Asset& a, const Asset& b) {
  CHECK(a.nodes.size() == b.nodes.size());
  REQUIRE(a.skins.size() == b.skins.size());
  for (std::size_t s = 0; s < a.skins.size(); ++s) CHECK(a.skins[s].joints == b.skins[s].joints);
  REQUIRE(a.animations.size() == b.animations.size());
  for (std::size_t i = 0; i < a.animations.size(); ++i) {
    CHECK(a.animations[i].channels.size() == b.animations[i].channels.size());
    CHECK(a.animations[i].samplers.size() == b.animations[i].samplers.size());
  }
  CHECK(a.materials.size() == b.materials.size());
  CHECK(a.textures.size() == b.textures.size());
  REQUIRE(a.images.size() == b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) CHECK(a.images[i].bytes == b.images[i].bytes);
}

void CheckSameCounts(const Asset& a, const Asset& b) {
  CheckSameSceneCounts(a, b);
  REQUIRE(a.meshes.size() == b.meshes.size());
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    REQUIRE(a.meshes[m].primitives.size() == b.meshes[m].primitives.size());
    for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
      CHECK(a.meshes[m].primitives[p].positions.size() ==
            b.meshes[m].primitives[p].positions.size());
      CHECK(a.meshes[m].primitives[p].indices == b.meshes[m].primitives[p].indices);
    }
  }
}

}  // namespace test
}  // namespace dermis
