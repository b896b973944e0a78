// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The deformer table (deform/deformer_registry.cpp): names, kinds, factories, unknown values.
#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "dermis/deform/deformer.h"

namespace dermis {

TEST_CASE("deformer table: one row per kind, names and kinds both ways") {
  std::size_t count = 0;
  const DeformerInfo* table = DeformerTable(&count);
  REQUIRE(count == 3);
  std::set<std::string> names;
  std::set<int> kinds;
  for (std::size_t i = 0; i < count; ++i) {
    const DeformerInfo& d = table[i];
    INFO(d.name);
    names.insert(d.name);
    kinds.insert(static_cast<int>(d.kind));
    CHECK(static_cast<std::size_t>(d.kind) == i);  // table order is DeformerKind order
    CHECK(FindDeformer(d.kind) == &d);
    CHECK(FindDeformer(std::string_view(d.name)) == &d);
    CHECK(std::string(DeformerName(d.kind)) == d.name);
    DeformerKind kind = DeformerKind::kLbs;
    REQUIRE(DeformerFromName(d.name, &kind).ok());
    CHECK(kind == d.kind);
    CHECK(std::string(d.description).size() > 5);
    CHECK(d.make != nullptr);
  }
  CHECK(names.size() == count);
  CHECK(kinds.size() == count);
  CHECK(DeformerNames() == std::vector<std::string>{"lbs", "dqs", "sweep"});
  CHECK(std::string(DeformerName(DeformerKind::kSweep)) == "sweep");
}

TEST_CASE("deformer table: an unknown name or kind is an error, never a default") {
  DeformerKind kind = DeformerKind::kDqs;
  Status s = DeformerFromName("Sweep", &kind);
  CHECK(s.code() == StatusCode::kInvalidInput);
  CHECK(s.message() == "unknown deformer 'Sweep' (deformers: lbs, dqs, sweep)");
  CHECK(kind == DeformerKind::kDqs);  // untouched
  CHECK_FALSE(DeformerFromName("", &kind).ok());
  CHECK(FindDeformer(std::string_view("twist")) == nullptr);
  const auto bogus = static_cast<DeformerKind>(7);
  CHECK(FindDeformer(bogus) == nullptr);
  CHECK(std::string(DeformerName(bogus)) == "unknown");

  SkinRig rig;
  rig.parents = {-1, 0};
  rig.bind = {glm::dmat4(1.0), glm::translate(glm::dmat4(1.0), {1, 0, 0})};
  const std::vector<Vec3> rest = {{0.5, 0.1, 0}, {1.5, -0.1, 0}};
  std::vector<VertexWeights> weights(2);
  for (VertexWeights& w : weights) {
    w.joints = glm::u16vec4(0, 1, 0, 0);
    w.weights = glm::vec4(0.5f, 0.5f, 0.0f, 0.0f);
  }
  std::unique_ptr<Deformer> deformer;
  s = MakeDeformer(bogus, rig, rest.data(), nullptr, weights.data(), rest.size(), &deformer);
  CHECK(s.code() == StatusCode::kInvalidInput);
  CHECK(s.message() == "unknown deformer 7");
  CHECK(deformer == nullptr);
  // Each row's factory makes its own kind, which reproduces the bind pose.
  for (const std::string& name : DeformerNames()) {
    INFO(name);
    DeformerKind k;
    REQUIRE(DeformerFromName(name, &k).ok());
    REQUIRE(
        MakeDeformer(k, rig, rest.data(), nullptr, weights.data(), rest.size(), &deformer).ok());
    CHECK(deformer->kind() == k);
    const std::vector<glm::dmat4> identity(2, glm::dmat4(1.0));
    REQUIRE(deformer->SetPose(identity.data()).ok());
    std::vector<Vec3> out(rest.size());
    deformer->Deform(0, rest.size(), out.data(), nullptr);
    for (std::size_t i = 0; i < rest.size(); ++i) CHECK(glm::length(out[i] - rest[i]) < 1e-12);
  }
}

}  // namespace dermis
