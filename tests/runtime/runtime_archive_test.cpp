// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Runtime archives (version-4 .dsurf, docs/file-format.md "Runtime archives") on the fitted
// two-capsule fixture: what survives packing (rig, influences, bindings, surfaces), round
// trips and determinism, the version, the reader's refusal of truncated and corrupted files,
// the C API loading one, and the runtime's level-8 frames of the archive against the fitted
// character's (1e-4 of the diagonal; the shared characters: test
// `runtime archive: shared characters' frames match their fitted .dsurf`).
#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "dermis/asset/asset_io.h"
#include "dermis/dermis.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"
#include "dermis/runtime/runtime.h"
#include "support/fixtures.h"
#include "support/runtime_frames.h"

namespace dermis {
namespace {

// Rewrites the checksum (FNV-1a 64 of every byte before it) after an edit.
void Reseal(std::string* bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::size_t i = 0; i + 8 < bytes->size(); ++i) {
    h ^= static_cast<unsigned char>((*bytes)[i]);
    h *= 0x100000001b3ull;
  }
  for (int i = 0; i < 8; ++i)
    (*bytes)[bytes->size() - 8 + static_cast<std::size_t>(i)] =
        static_cast<char>((h >> (8 * i)) & 0xff);
}

Character Parse(const std::string& bytes, DsurfFileInfo* info = nullptr) {
  Character ch;
  std::uint32_t version = 0;
  const Status s = ParseCharacter(bytes, "a.dsurf", &ch, &version, info);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(version == kRuntimeArchiveVersion);
  return ch;
}

std::string FixtureV2() { return SerializeCharacter(test::CylindersFixture()); }

TEST_CASE("runtime archive: the rig, influences, bindings and surfaces survive packing",
          "[dsurf][archive]") {
  const Character& fitted = test::CylindersFixture();
  const std::string bytes = SerializeRuntimeArchive(fitted, {});
  CHECK(DsurfFileVersion(bytes) == kRuntimeArchiveVersion);
  DsurfFileInfo info;
  const Character ch = Parse(bytes, &info);
  CHECK(ch.source_stripped);
  CHECK(ch.asset.images.empty());
  CHECK(ch.asset.animations.empty());
  CHECK(ch.asset.materials.empty());
  // Every byte is in one section.
  std::uint64_t total = 0;
  for (const auto& section : info.sections) total += section.second;
  CHECK(total == bytes.size());
  CHECK_FALSE(info.archive.quantize_displacements);
  CHECK_FALSE(info.archive.keep_source);
  // The rig as the runtime builds it: the same parents, bind matrices and joint names.
  REQUIRE(ch.asset.skins.size() == fitted.asset.skins.size());
  for (std::size_t s = 0; s < ch.asset.skins.size(); ++s) {
    SkinRig a, b;
    REQUIRE(MakeSkinRig(fitted.asset, static_cast<Index>(s), &a).ok());
    REQUIRE(MakeSkinRig(ch.asset, static_cast<Index>(s), &b).ok());
    CHECK(a.parents == b.parents);
    CHECK(a.names == b.names);
    REQUIRE(a.bind.size() == b.bind.size());
    for (std::size_t j = 0; j < a.bind.size(); ++j) CHECK(a.bind[j] == b.bind[j]);
  }
  REQUIRE(ch.parts.size() == fitted.parts.size());
  for (std::size_t p = 0; p < ch.parts.size(); ++p) {
    const CharacterPart &a = fitted.parts[p], &b = ch.parts[p];
    CHECK(a.mesh == b.mesh);
    CHECK(a.skin == b.skin);
    CHECK(a.control_joints == b.control_joints);
    REQUIRE(a.control_weights.size() == b.control_weights.size());
    for (std::size_t i = 0; i < a.control_weights.size(); ++i) {
      float sum = 0.0f;
      for (int k = 0; k < 4; ++k) {
        CHECK(std::abs(a.control_weights[i][k] - b.control_weights[i][k]) <= 1.0f / 65535.0f);
        sum += b.control_weights[i][k];
      }
      CHECK(sum == Approx(1.0f).margin(1e-6));
    }
    // Control positions and operators in f32, the topology and coefficients exact.
    REQUIRE(a.surface.rest_positions.size() == b.surface.rest_positions.size());
    for (std::size_t v = 0; v < a.surface.rest_positions.size(); ++v) {
      CHECK(glm::length(a.surface.rest_positions[v] - b.surface.rest_positions[v]) <=
            1e-6 * (1.0 + glm::length(a.surface.rest_positions[v])));
    }
    const MeshTopology &ta = a.surface.domain->topology(), &tb = b.surface.domain->topology();
    REQUIRE(ta.num_faces() == tb.num_faces());
    for (Index f = 0; f < ta.num_faces(); ++f) {
      for (int k = 0; k < 4; ++k) CHECK(ta.face_vertex(f, k) == tb.face_vertex(f, k));
    }
    REQUIRE(a.surface.displacement);
    REQUIRE(b.surface.displacement);
    CHECK(a.surface.displacement->data().values == b.surface.displacement->data().values);
    CHECK(a.surface.displacement->data().nodes == b.surface.displacement->data().nodes);
  }
  REQUIRE(ch.bindings.size() == fitted.bindings.size());
  for (std::size_t m = 0; m < ch.bindings.size(); ++m) {
    REQUIRE(ch.bindings[m].size() == fitted.bindings[m].size());
    for (std::size_t q = 0; q < ch.bindings[m].size(); ++q) {
      REQUIRE(ch.bindings[m][q].size() == fitted.bindings[m][q].size());
      for (std::size_t v = 0; v < ch.bindings[m][q].size(); ++v) {
        const VertexBinding &a = fitted.bindings[m][q][v], &b = ch.bindings[m][q][v];
        CHECK(a.part == b.part);
        if (a.part == kInvalidIndex) continue;
        CHECK(a.face == b.face);
        CHECK(std::abs(a.u - b.u) <= 0.5 / 65535.0 + 1e-12);
        CHECK(std::abs(a.v - b.v) <= 0.5 / 65535.0 + 1e-12);
      }
    }
  }
}

TEST_CASE("runtime archive: deterministic, and packing what was read gives the same bytes",
          "[dsurf][archive]") {
  const Character& fitted = test::CylindersFixture();
  RuntimeArchiveError error;
  error.level8_max = 1.5e-7;
  error.diagonal = 3.0;
  const std::string bytes = SerializeRuntimeArchive(fitted, {}, error);
  CHECK(SerializeRuntimeArchive(fitted, {}, error) == bytes);
  DsurfFileInfo info;
  const Character ch = Parse(bytes, &info);
  CHECK(info.archive_error.level8_max == 1.5e-7);
  CHECK(info.archive_error.diagonal == 3.0);
  CHECK(SerializeRuntimeArchive(ch, {}, error) == bytes);
}

TEST_CASE("runtime archive: --keep-source keeps the asset, fit summaries and unfitted parts",
          "[dsurf][archive]") {
  const Character& fitted = test::CylindersFixture();
  RuntimeArchiveOptions options;
  options.keep_source = true;
  const std::string bytes = SerializeRuntimeArchive(fitted, options);
  DsurfFileInfo info;
  const Character ch = Parse(bytes, &info);
  CHECK(info.archive.keep_source);
  CHECK_FALSE(ch.source_stripped);
  CHECK(SerializeAsset(ch.asset) == SerializeAsset(fitted.asset));
  REQUIRE(ch.parts.size() == fitted.parts.size());
  for (std::size_t p = 0; p < ch.parts.size(); ++p) {
    CHECK(ch.parts[p].fit.points == fitted.parts[p].fit.points);
    CHECK(ch.parts[p].fit.e1_max == fitted.parts[p].fit.e1_max);
    CHECK(ch.parts[p].surface.data_points == fitted.parts[p].surface.data_points);
  }
  CHECK(ch.unfitted.size() == fitted.unfitted.size());
  // Smaller without the source.
  CHECK(SerializeRuntimeArchive(fitted, {}).size() < bytes.size());
}

TEST_CASE("runtime archive: 16-bit displacements stay within the tolerance", "[dsurf][archive]") {
  const Character& fitted = test::CylindersFixture();
  RuntimeArchiveOptions options;
  options.quantize_displacements = true;
  const std::string bytes = SerializeRuntimeArchive(fitted, options);
  CHECK(bytes.size() < SerializeRuntimeArchive(fitted, {}).size());
  DsurfFileInfo info;
  const Character ch = Parse(bytes, &info);
  CHECK(info.archive.quantize_displacements);
  for (std::size_t p = 0; p < ch.parts.size(); ++p) {
    const auto& a = fitted.parts[p].surface.displacement->data().values;
    const auto& b = ch.parts[p].surface.displacement->data().values;
    REQUIRE(a.size() == b.size());
    Vec3 lo(1e300), hi(-1e300);
    for (const Vec3& x : fitted.parts[p].surface.rest_positions) {
      lo = glm::min(lo, x);
      hi = glm::max(hi, x);
    }
    // Per coefficient: the tolerance (2e-6 of the part's diagonal), or half a 16-bit step.
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      worst = std::max(worst, std::abs(static_cast<double>(a[i]) - b[i]));
    CHECK(worst > 0.0);  // quantised, not stored exactly
    CHECK(worst <= 2e-6 * glm::length(hi - lo) * 1.01);
  }
}

TEST_CASE("runtime archive: level-8 and bound frames within 1e-4 of the fitted character's",
          "[dsurf][archive]") {
  const std::string fitted = FixtureV2();
  RuntimeArchiveOptions options;
  for (const bool quantize : {false, true}) {
    options.quantize_displacements = quantize;
    const std::string archive = SerializeRuntimeArchive(test::CylindersFixture(), options);
    for (const DeformerKind deformer : {DeformerKind::kLbs, DeformerKind::kSweep}) {
      for (const int level : {8, 0}) {
        INFO("quantised " << quantize << ", deformer " << static_cast<int>(deformer) << ", level "
                          << level);
        const test::FrameDeviation d =
            test::CompareRuntimeFrames(fitted, archive, level, deformer, 2);
        CHECK(d.vertices > 0);
        CHECK(d.diagonal > 0.0);
        CHECK(d.max <= 1e-4 * d.diagonal);
        CHECK(d.mean <= 1e-5 * d.diagonal);
      }
    }
  }
}

TEST_CASE("runtime archive: the C API loads it and reports less memory", "[dsurf][archive]") {
  const std::string v2 = FixtureV2();
  const std::string archive = SerializeRuntimeArchive(test::CylindersFixture(), {});
  dermis_character *a = nullptr, *b = nullptr;
  REQUIRE(dermis_character_load_memory(v2.data(), v2.size(), "c.dsurf", &a) == DERMIS_OK);
  REQUIRE(dermis_character_load_memory(archive.data(), archive.size(), "c.dsurf", &b) == DERMIS_OK);
  REQUIRE(dermis_character_part_count(a) == dermis_character_part_count(b));
  for (size_t p = 0; p < dermis_character_part_count(a); ++p) {
    REQUIRE(dermis_character_joint_count(a, p) == dermis_character_joint_count(b, p));
    for (size_t j = 0; j < dermis_character_joint_count(a, p); ++j)
      CHECK(std::string(dermis_character_joint_name(a, p, j)) ==
            dermis_character_joint_name(b, p, j));
    CHECK(dermis_character_bound_vertex_count(a, p) == dermis_character_bound_vertex_count(b, p));
  }
  CHECK(dermis_character_memory_bytes(b) > 0);
  CHECK(dermis_character_memory_bytes(b) < dermis_character_memory_bytes(a));
  dermis_character_destroy(a);
  dermis_character_destroy(b);
}

TEST_CASE("runtime archive: truncated and corrupted files are refused", "[dsurf][archive]") {
  for (const bool quantize : {false, true}) {
    RuntimeArchiveOptions options;
    options.quantize_displacements = quantize;
    const std::string bytes = SerializeRuntimeArchive(test::CylindersFixture(), options);
    Character ch;
    // Every cut, resealed so that the body's checks (not the checksum) refuse it.
    const std::size_t step = std::max<std::size_t>(1, bytes.size() / 251);
    for (std::size_t n = 24; n + 8 < bytes.size(); n += step) {
      std::string cut = bytes.substr(0, n) + std::string(8, '\0');
      Reseal(&cut);
      const Status s = ParseCharacter(cut, "cut.dsurf", &ch);
      INFO("cut at " << n << ": " << s.message());
      REQUIRE_FALSE(s.ok());
      CHECK(s.message().rfind("cut.dsurf", 0) == 0);
    }
    const auto refused = [&](std::size_t at, std::uint32_t value, int width, const char* what) {
      std::string bad = bytes;
      for (int i = 0; i < width; ++i)
        bad[at + static_cast<std::size_t>(i)] = static_cast<char>((value >> (8 * i)) & 0xff);
      Reseal(&bad);
      const Status s = ParseCharacter(bad, "bad.dsurf", &ch);
      INFO("at " << at << ": " << s.message());
      CHECK(s.code() == StatusCode::kInvalidInput);
      CHECK(s.message().find(what) != std::string::npos);
    };
    // Layout after the 16-byte header: flags u32, 4 x f64 errors, node count u32, node 0's parent.
    refused(16, 0x80, 4, "unknown archive flags");
    refused(52, 0xfffff, 4, "nodes needs");  // more nodes than bytes
    refused(56, 1000, 4, "parent 1000 out of range");
    // The bindings end the body; the first one (u16 part + 1, u16 face, u16 u, u16 v) is bound.
    DsurfFileInfo info;
    Parse(bytes, &info);
    std::uint64_t binding_bytes = 0;
    for (const auto& section : info.sections) {
      if (section.first == "vertex bindings") binding_bytes = section.second;
    }
    const std::size_t first = bytes.size() - 8 - static_cast<std::size_t>(binding_bytes);
    REQUIRE(test::CylindersFixture().bindings[0][0][0].part == 0);
    refused(first, 0x7fff, 2, "names part 32766, which does not exist");
    refused(first + 2, 0xffff, 2, "a vertex binding is out of range");
  }
}

TEST_CASE("runtime archive: the reader of every version says which it reads", "[dsurf][archive]") {
  std::string bytes = SerializeRuntimeArchive(test::CylindersFixture(), {});
  bytes[8] = 5;
  Reseal(&bytes);
  Character ch;
  const Status s = ParseCharacter(bytes, "v.dsurf", &ch);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message() == "v.dsurf: .dsurf version 5 is not supported (this build reads 1..4)");
  DisplacedSurface surface;
  const std::string archive = SerializeRuntimeArchive(test::CylindersFixture(), {});
  CHECK(ParseDsurf(archive, "a.dsurf", &surface).message() ==
        "a.dsurf: a version 4 .dsurf is a character, not a plain surface");
}

}  // namespace
}  // namespace dermis
