// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The runtime and the C API used from several threads at once, as docs/engine-integration.md
// ("threads") allows: characters loaded concurrently, one character shared by instances posed
// on their own threads, one output shared by all, one instance's blocks evaluated on several
// threads, and per-thread error messages. Results must equal the single-threaded ones bit for
// bit. The ThreadSanitizer job of CI runs this file (docs/reliability.md, "Threads").
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "dermis/dermis.h"
#include "support/fixtures.h"

namespace {

constexpr int kThreads = 4;

// Skin matrices of a rigid rotation by `angle` about z for every joint (column-major).
std::vector<float> Palette(std::size_t joints, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  const float m[16] = {c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<float> out;
  for (std::size_t j = 0; j < joints; ++j) out.insert(out.end(), m, m + 16);
  return out;
}

// Poses `inst` at `angle` and evaluates every block of `out` (positions and normals).
bool PoseAndEvaluate(dermis_instance* inst, const dermis_output* out, std::size_t joints,
                     float angle, std::vector<float>* result) {
  const std::vector<float> palette = Palette(joints, angle);
  if (dermis_instance_pose(inst, 0, palette.data(), joints) != DERMIS_OK) return false;
  const std::size_t n = dermis_output_vertex_count(out);
  result->assign(6 * n, 0.0f);
  const std::size_t bytes = 12 * n;  // each of the two arrays: 3 floats per vertex
  return dermis_evaluate(inst, out, 0, SIZE_MAX, result->data(), 12, bytes,
                         result->data() + 3 * n, 12, bytes) == DERMIS_OK;
}

}  // namespace

TEST_CASE("threads: shared character and output, instances posed and evaluated concurrently") {
  const std::string bytes = dermis::test::FixtureBytes("cylinders.dsurf");
  dermis_character* c = nullptr;
  REQUIRE(dermis_character_load_memory(bytes.data(), bytes.size(), "c.dsurf", &c) == DERMIS_OK);
  const std::size_t joints = dermis_character_joint_count(c, 0);
  REQUIRE(joints > 0);
  dermis_output_desc desc;
  dermis_output_desc_init(&desc);
  desc.threads = 2;
  dermis_output* out = nullptr;
  REQUIRE(dermis_output_create(c, 0, &desc, &out) == DERMIS_OK);
  // The single-threaded answers.
  std::vector<std::vector<float>> expect(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    dermis_instance* inst = nullptr;
    REQUIRE(dermis_instance_create(c, DERMIS_DEFORMER_SWEEP, &inst) == DERMIS_OK);
    for (int frame = 0; frame < 3; ++frame) {
      REQUIRE(PoseAndEvaluate(inst, out, joints, 0.3f * static_cast<float>(t), &expect[t]));
    }
    dermis_instance_destroy(inst);
  }
  // Each thread: its own character loaded from the same bytes (concurrent loads), an instance
  // of the shared character, the shared output; a failing call whose message is its own.
  std::vector<std::vector<float>> got(kThreads);
  std::vector<int> ok(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t]() {
      dermis_character* own = nullptr;
      bool good =
          dermis_character_load_memory(bytes.data(), bytes.size(), "own.dsurf", &own) == DERMIS_OK;
      dermis_character_destroy(own);
      const std::string name = "thread" + std::to_string(t) + ".dsurf";
      dermis_character* bad = nullptr;
      good = good && dermis_character_load_memory("junk", 4, name.c_str(), &bad) != DERMIS_OK;
      good = good && std::string(dermis_last_error()).find(name) != std::string::npos;
      dermis_instance* inst = nullptr;
      good = good && dermis_instance_create(c, DERMIS_DEFORMER_SWEEP, &inst) == DERMIS_OK;
      for (int frame = 0; frame < 3 && good; ++frame) {
        good = PoseAndEvaluate(inst, out, joints, 0.3f * static_cast<float>(t), &got[t]);
      }
      dermis_instance_destroy(inst);
      ok[t] = good ? 1 : 0;
    });
  }
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) {
    INFO("thread " << t);
    CHECK(ok[t] == 1);
    CHECK(got[t] == expect[t]);
  }
  // One instance, its blocks split over threads (disjoint ranges): the same bytes.
  dermis_instance* inst = nullptr;
  REQUIRE(dermis_instance_create(c, DERMIS_DEFORMER_LBS, &inst) == DERMIS_OK);
  std::vector<float> whole;
  REQUIRE(PoseAndEvaluate(inst, out, joints, 0.7f, &whole));
  const std::size_t n = dermis_output_vertex_count(out);
  const std::size_t blocks = dermis_output_block_count(out);
  std::vector<float> split(6 * n, 0.0f);
  std::vector<int> split_ok(kThreads, 0);
  threads.clear();
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t]() {
      const std::size_t begin = blocks * static_cast<std::size_t>(t) / kThreads;
      const std::size_t end = blocks * static_cast<std::size_t>(t + 1) / kThreads;
      split_ok[t] = dermis_evaluate(inst, out, begin, end, split.data(), 12, 12 * n,
                                    split.data() + 3 * n, 12, 12 * n) == DERMIS_OK;
    });
  }
  for (std::thread& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) CHECK(split_ok[t] == 1);
  CHECK(split == whole);
  dermis_instance_destroy(inst);
  dermis_output_destroy(out);
  dermis_character_destroy(c);
}
