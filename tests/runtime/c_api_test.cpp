// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The engine-facing parts of the C API (issue 17, docs/engine-integration.md "C"): versions,
// joint names and the remap from an engine's joint order, checked buffer sizes, memory
// queries. On the fitted two-capsule character (2 joints, tests/support/fixtures.h).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "dermis/dermis.h"
#include "dermis/runtime/runtime.h"
#include "support/fixtures.h"

namespace dermis {
namespace {

struct Loaded {
  dermis_character* c = nullptr;
  dermis_instance* inst = nullptr;
  dermis_output* out = nullptr;
  Loaded() {
    const std::string bytes = test::FixtureBytes("cylinders.dsurf");
    REQUIRE(dermis_character_load_memory(bytes.data(), bytes.size(), "c.dsurf", &c) == DERMIS_OK);
    REQUIRE(dermis_instance_create(c, DERMIS_DEFORMER_DQS, &inst) == DERMIS_OK);
    dermis_output_desc desc;
    dermis_output_desc_init(&desc);
    desc.level = 3;
    REQUIRE(dermis_output_create(c, 0, &desc, &out) == DERMIS_OK);
  }
  ~Loaded() {
    dermis_output_destroy(out);
    dermis_instance_destroy(inst);
    dermis_character_destroy(c);
  }
};

// A pose of joint j: a rotation about z by 0.3 (j + 1) radians and a shift, column-major.
void JointMatrix(std::size_t j, float* m) {
  const float a = 0.3f * static_cast<float>(j + 1);
  std::fill(m, m + 16, 0.0f);
  m[0] = std::cos(a);
  m[1] = std::sin(a);
  m[4] = -std::sin(a);
  m[5] = std::cos(a);
  m[10] = m[15] = 1.0f;
  m[12] = 0.1f * static_cast<float>(j);
  m[13] = -0.05f;
}

TEST_CASE("c api: version macros and the library's version agree") {
  CHECK(dermis_version_number() == static_cast<uint32_t>(DERMIS_VERSION_NUMBER));
  char expected[32];
  std::snprintf(expected, sizeof(expected), "%d.%d.%d", DERMIS_VERSION_MAJOR, DERMIS_VERSION_MINOR,
                DERMIS_VERSION_PATCH);
  CHECK(std::string(dermis_version()) == expected);
}

TEST_CASE("c api: joint names and the remap from an engine's joint order") {
  Loaded l;
  const std::size_t joints = dermis_character_joint_count(l.c, 0);
  REQUIRE(joints == 2);
  const Character& ch = test::CylindersFixture();
  std::vector<std::string> names;
  for (std::size_t j = 0; j < joints; ++j) {
    const char* name = dermis_character_joint_name(l.c, 0, j);
    REQUIRE(name != nullptr);
    // The name of the skin's joint node, independently from the asset.
    const Index node = ch.asset.skins[0].joints[j];
    CHECK(std::string(name) == ch.asset.nodes[static_cast<std::size_t>(node)].name);
    names.push_back(name);
  }
  CHECK(names[0] != names[1]);
  CHECK(dermis_character_joint_name(l.c, 0, joints) == nullptr);
  CHECK(dermis_character_joint_name(l.c, 7, 0) == nullptr);
  CHECK(dermis_character_joint_name(nullptr, 0, 0) == nullptr);

  // The engine lists an extra joint first, then the skin's joints in reverse.
  std::vector<const char*> engine = {"engine_root", names[1].c_str(), names[0].c_str()};
  int32_t remap[2] = {-7, -7};
  REQUIRE(dermis_character_joint_remap(l.c, 0, engine.data(), engine.size(), remap, 2) ==
          DERMIS_OK);
  CHECK(remap[0] == 2);
  CHECK(remap[1] == 1);

  // A joint the engine lacks: named in the error, nothing written.
  int32_t untouched[2] = {-7, -7};
  std::vector<const char*> lacking = {"engine_root", names[1].c_str()};
  CHECK(dermis_character_joint_remap(l.c, 0, lacking.data(), lacking.size(), untouched, 2) ==
        DERMIS_ERROR_INVALID_INPUT);
  CHECK(std::string(dermis_last_error()).find("\"" + names[0] + "\"") != std::string::npos);
  CHECK(untouched[0] == -7);
  CHECK(untouched[1] == -7);
  // A name the engine lists twice, a remap too short, a null name.
  std::vector<const char*> twice = {names[0].c_str(), names[1].c_str(), names[0].c_str()};
  CHECK(dermis_character_joint_remap(l.c, 0, twice.data(), twice.size(), untouched, 2) ==
        DERMIS_ERROR_INVALID_INPUT);
  CHECK(std::string(dermis_last_error()).find("more than once") != std::string::npos);
  CHECK(dermis_character_joint_remap(l.c, 0, engine.data(), engine.size(), untouched, 1) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  std::vector<const char*> null_name = {names[0].c_str(), nullptr};
  CHECK(dermis_character_joint_remap(l.c, 0, null_name.data(), 2, untouched, 2) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(untouched[0] == -7);

  // Posing from the engine's palette through the remap gives the same bytes as posing with
  // the palette in the skin's order.
  std::vector<float> skin_order(16 * joints), engine_order(16 * engine.size(), 0.0f);
  for (std::size_t j = 0; j < joints; ++j) {
    JointMatrix(j, skin_order.data() + 16 * j);
    std::copy(skin_order.begin() + 16 * static_cast<std::ptrdiff_t>(j),
              skin_order.begin() + 16 * static_cast<std::ptrdiff_t>(j + 1),
              engine_order.begin() + 16 * remap[j]);
  }
  const std::size_t n = dermis_output_vertex_count(l.out);
  std::vector<float> a(6 * n), b(6 * n, 1.0f);
  REQUIRE(dermis_instance_pose(l.inst, 0, skin_order.data(), joints) == DERMIS_OK);
  REQUIRE(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, a.data(), 24, a.size() * 4, a.data() + 3, 24,
                          a.size() * 4 - 12) == DERMIS_OK);
  REQUIRE(dermis_instance_pose_remapped(l.inst, 0, engine_order.data(), engine.size(), remap, 2) ==
          DERMIS_OK);
  REQUIRE(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, b.data(), 24, b.size() * 4, b.data() + 3, 24,
                          b.size() * 4 - 12) == DERMIS_OK);
  CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
  // An index outside the engine's palette is refused and the pose stays.
  const int32_t bad[2] = {0, 3};
  CHECK(dermis_instance_pose_remapped(l.inst, 0, engine_order.data(), engine.size(), bad, 2) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(std::string(dermis_last_error()).find("remap[1] = 3") != std::string::npos);
  CHECK(dermis_instance_pose_remapped(l.inst, 0, engine_order.data(), engine.size(), remap, 1) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  std::fill(b.begin(), b.end(), 1.0f);
  REQUIRE(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, b.data(), 24, b.size() * 4, nullptr, 0, 0) ==
          DERMIS_OK);
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(std::memcmp(a.data() + 6 * i, b.data() + 6 * i, 12) == 0);
    if (std::memcmp(a.data() + 6 * i, b.data() + 6 * i, 12) != 0) break;
  }
}

TEST_CASE("c api: undersized buffers are refused and nothing is written") {
  Loaded l;
  const std::size_t n = dermis_output_vertex_count(l.out);
  const std::size_t blocks = dermis_output_block_count(l.out);
  REQUIRE(n > 8);
  // The whole output: its last vertex ends at (n - 1) * stride + 12.
  CHECK(dermis_output_required_bytes(l.out, 0, SIZE_MAX, 24) == (n - 1) * 24 + 12);
  CHECK(dermis_output_required_bytes(l.out, 3, 3, 24) == 0);
  CHECK(dermis_output_required_bytes(nullptr, 0, SIZE_MAX, 24) == 0);
  // A sub-range: the largest output index its lanes write, found independently by evaluating
  // the range into a buffer full of sentinels and looking for the last written vertex.
  const std::size_t half = blocks / 2;
  std::vector<float> probe(3 * n, -1e30f);
  const std::size_t exact = 3 * n * sizeof(float);
  REQUIRE(dermis_evaluate(l.inst, l.out, 0, half, probe.data(), 12, exact, nullptr, 0, 0) ==
          DERMIS_OK);
  std::size_t last = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (probe[3 * i] != -1e30f) last = i;
  }
  CHECK(dermis_output_required_bytes(l.out, 0, half, 12) == last * 12 + 12);

  std::vector<float> buf(3 * n, 42.0f);
  const std::size_t need = dermis_output_required_bytes(l.out, 0, SIZE_MAX, 12);
  CHECK(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, buf.data(), 12, need - 1, nullptr, 0, 0) ==
        DERMIS_ERROR_INVALID_ARGUMENT);
  const std::string message = dermis_last_error();
  CHECK(message.find("holds " + std::to_string(need - 1) + " bytes") != std::string::npos);
  CHECK(message.find("need " + std::to_string(need)) != std::string::npos);
  CHECK(message.find("nothing written") != std::string::npos);
  CHECK(std::all_of(buf.begin(), buf.end(), [](float x) { return x == 42.0f; }));
  // An undersized normal buffer likewise; the exact sizes pass.
  std::vector<float> normals(3 * n, 42.0f);
  CHECK(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, buf.data(), 12, need, normals.data(), 12,
                        need - 4) == DERMIS_ERROR_INVALID_ARGUMENT);
  CHECK(std::all_of(buf.begin(), buf.end(), [](float x) { return x == 42.0f; }));
  CHECK(dermis_evaluate(l.inst, l.out, 0, SIZE_MAX, buf.data(), 12, need, normals.data(), 12,
                        need) == DERMIS_OK);
  CHECK(std::none_of(normals.begin(), normals.end(), [](float x) { return x == 42.0f; }));
}

TEST_CASE("c api: memory queries count what each object holds") {
  Loaded l;
  const Character& ch = test::CylindersFixture();
  const CharacterPart& part = ch.parts[0];
  const std::size_t cv = part.surface.rest_positions.size();
  // Lower bounds from independently known sizes: the character holds at least its control
  // vertices (double), displacement coefficients (float), and every bound vertex's location.
  std::size_t bound = 0;
  for (const auto& mesh : ch.bindings)
    for (const auto& prim : mesh) bound += prim.size();
  std::size_t floor = 0;
  for (const CharacterPart& p : ch.parts) {
    floor += p.surface.rest_positions.size() * sizeof(Vec3);
    if (p.surface.displacement)
      floor += static_cast<std::size_t>(p.surface.displacement->num_coefficients()) * 4;
  }
  floor += bound * sizeof(VertexBinding);
  const std::size_t character = dermis_character_memory_bytes(l.c);
  CHECK(character > floor);
  CHECK(character < 4 * floor + (1u << 20));  // and nothing absurd
  // An output: its plan (blocks and block floats) and triangles, exactly.
  const void* blocks = nullptr;
  const float* data = nullptr;
  std::size_t block_bytes = 0, data_bytes = 0;
  REQUIRE(dermis_output_plan(l.out, &blocks, &block_bytes, &data, &data_bytes) == DERMIS_OK);
  const std::size_t output = dermis_output_memory_bytes(l.out);
  const std::size_t triangles = 3 * dermis_output_triangle_count(l.out) * sizeof(uint32_t);
  CHECK(output >= block_bytes + data_bytes + triangles);
  CHECK(output <= block_bytes + data_bytes + triangles + 1024);
  // An instance: per control vertex at least its position, local patch and packed patch.
  const std::size_t instance = dermis_instance_memory_bytes(l.inst);
  CHECK(instance >= cv * (sizeof(Vec3) + sizeof(LocalPatch) + kPackedPatchStride * 4));
  CHECK(dermis_character_memory_bytes(nullptr) == 0);
  CHECK(dermis_output_memory_bytes(nullptr) == 0);
  CHECK(dermis_instance_memory_bytes(nullptr) == 0);
}

}  // namespace
}  // namespace dermis
