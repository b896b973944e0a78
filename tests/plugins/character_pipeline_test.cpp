// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The whole character pipeline on the shared Khronos characters (issue 4's acceptance test):
// import (tinygltf) -> FitCharacter -> bound and lod assets -> ExportGltf with and without the
// embedded .dsurf, then judged from outside: the Khronos glTF-Validator (no errors, no warning
// the source did not have), three.js's skinning of every export at sampled clip times against
// our PosePrimitive(), Assimp reading each export with the expected counts, the bound rest pose
// against the source vertices (E1), and the round trip through the embedded .dsurf.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "dermis/asset/asset_pose.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/geometry/mesh_metrics.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/character.h"
#include "support/assimp_counts.h"
#include "support/external_checks.h"

namespace dermis {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

struct Deviation {
  double mean = 0.0, max = 0.0;
  std::size_t vertices = 0;
};

/// |source vertex - exported vertex| over the vertices bound to a fitted part (bind space; the
/// rest pose of both files skins them by the same matrices, so bind space is what differs).
Deviation BoundDeviation(const Asset& source, const Asset& exported, const Character& ch) {
  Deviation d;
  REQUIRE(exported.meshes.size() == source.meshes.size());
  for (std::size_t m = 0; m < source.meshes.size(); ++m) {
    REQUIRE(exported.meshes[m].primitives.size() == source.meshes[m].primitives.size());
    for (std::size_t p = 0; p < source.meshes[m].primitives.size(); ++p) {
      const auto& a = source.meshes[m].primitives[p].positions;
      const auto& b = exported.meshes[m].primitives[p].positions;
      REQUIRE(a.size() == b.size());
      for (std::size_t v = 0; v < a.size(); ++v) {
        if (ch.bindings[m][p][v].part == kInvalidIndex) {
          CHECK(a[v] == b[v]);  // unfitted parts keep their vertices
          continue;
        }
        const double e = glm::length(glm::dvec3(a[v]) - glm::dvec3(b[v]));
        d.mean += e;
        d.max = std::max(d.max, e);
        ++d.vertices;
      }
    }
  }
  if (d.vertices > 0) d.mean /= static_cast<double>(d.vertices);
  return d;
}

double Diagonal(const Asset& asset) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const AssetMesh& m : asset.meshes) {
    for (const AssetPrimitive& p : m.primitives) {
      for (const glm::vec3& x : p.positions) {
        lo = glm::min(lo, glm::dvec3(x));
        hi = glm::max(hi, glm::dvec3(x));
      }
    }
  }
  return glm::length(hi - lo);
}

/// Exports `asset`, judges the file with the validator against the source's warnings, poses it
/// with three.js, reads it with Assimp, and returns what ImportGltf reads back.
Asset ExportAndJudge(const Asset& asset, const std::string& dsurf, const std::string& path,
                     const test::ValidatorReport& source_report, const TempDir& tmp) {
  INFO(path);
  GltfExportOptions options;
  options.dsurf_bytes = dsurf;
  Status s = ExportGltf(asset, options, path);
  INFO(s.message());
  REQUIRE(s.ok());

  const test::ValidatorReport report = test::Validate(path, tmp);
  INFO(test::Messages(report));
  CHECK(report.errors == 0);
  for (const std::string& code : report.warning_codes) {
    INFO("warning " << code);
    CHECK(source_report.warning_codes.count(code) == 1);
  }

  Asset back;
  std::string embedded;
  s = ImportGltf(path, &back, &embedded);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(embedded == dsurf);
  test::CheckThreeMatchesOurPoses(path, back, tmp);
  test::CheckAssimpReads(path, back);
  return back;
}

void CheckCharacterPipeline(const std::string& name) {
  const std::string source = std::string(test::kSharedGltfDir) + name;
  if (!fs::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return;
  }
  if (!test::JsToolsReady()) return;
  INFO(name);
  TempDir tmp("dermis_pipeline");
  Asset asset;
  Status s = ImportGltf(source, &asset);
  INFO(s.message());
  REQUIRE(s.ok());
  const test::ValidatorReport source_report = test::Validate(source, tmp);
  CHECK(source_report.errors == 0);

  // Fit (what `dermis fit CHARACTER.glb -o OUT.dsurf` runs, with its defaults).
  CharacterFitOptions fit_options;
  fit_options.fit.threads = 2;
  Character ch;
  CharacterFitReport report;
  s = FitCharacter(asset, fit_options, &ch, &report);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(report.parts_fitted >= 1);
  CHECK(report.vertices_bound == report.vertices);  // every source vertex lands on a surface
  const std::string dsurf = SerializeCharacter(ch);

  // bound: the source topology on the displaced surface.
  Asset bound;
  s = BuildBoundAsset(ch, CharacterExportOptions{}, &bound);
  INFO(s.message());
  REQUIRE(s.ok());
  ExportAndJudge(bound, std::string(), tmp.File("bound.glb"), source_report, tmp);
  const Asset bound_back =
      ExportAndJudge(bound, dsurf, tmp.File("bound_embed.glb"), source_report, tmp);
  // The rest pose reproduces the source vertices within the fit's E1 (the glb holds float32
  // positions: allow their rounding).
  const Deviation dev = BoundDeviation(asset, bound_back, ch);
  const double diagonal = Diagonal(asset);
  CHECK(dev.vertices == static_cast<std::size_t>(report.vertices_bound));
  CHECK(dev.mean == Approx(report.e1_mean).margin(1e-6 * diagonal));
  CHECK(dev.max <= report.e1_max + 1e-6 * diagonal);
  std::printf(
      "%-18s vertices %6zu  diagonal %9.4g  E1 mean %.4g max %.4g  bound rest-pose deviation "
      "mean %.4g max %.4g (model units)\n",
      name.c_str(), dev.vertices, diagonal, report.e1_mean, report.e1_max, dev.mean, dev.max);

  // Round trip: the same counts as the source, and the embedded .dsurf comes back bit-exact
  // and parses to a character that serialises to the same bytes.
  test::CheckSameCounts(asset, bound_back);
  Character again;
  s = ParseCharacter(dsurf, "embedded", &again);
  INFO(s.message());
  REQUIRE(s.ok());
  CHECK(SerializeCharacter(again) == dsurf);
  test::CheckSameCounts(asset, again.asset);

  // lod: the tessellated surfaces with transferred weights (morph targets are refused).
  bool has_morphs = false;
  for (const AssetMesh& m : asset.meshes) {
    for (const AssetPrimitive& p : m.primitives) has_morphs |= !p.targets.empty();
  }
  Asset lod;
  std::vector<std::string> notes;
  s = BuildLodAsset(ch, CharacterExportOptions{}, &lod, &notes);
  INFO(s.message());
  if (has_morphs) {
    CHECK(s.code() == StatusCode::kUnsupported);
    return;
  }
  REQUIRE(s.ok());
  REQUIRE(ValidateAsset(lod).ok());
  const Asset lod_back = ExportAndJudge(lod, dsurf, tmp.File("lod_embed.glb"), source_report, tmp);
  test::CheckSameSceneCounts(asset, lod_back);
}

TEST_CASE("pipeline: SimpleSkin fit, exported bound and lod, judged", "[pipeline][data]") {
  CheckCharacterPipeline("SimpleSkin.gltf");
}
TEST_CASE("pipeline: RiggedSimple fit, exported bound and lod, judged", "[pipeline][data]") {
  CheckCharacterPipeline("RiggedSimple.glb");
}
TEST_CASE("pipeline: RiggedFigure fit, exported bound and lod, judged", "[pipeline][data]") {
  CheckCharacterPipeline("RiggedFigure.glb");
}
TEST_CASE("pipeline: Fox fit, exported bound and lod, judged", "[pipeline][data]") {
  CheckCharacterPipeline("Fox.glb");
}
TEST_CASE("pipeline: CesiumMan fit, exported bound and lod, judged", "[pipeline][data][heavy]") {
  CheckCharacterPipeline("CesiumMan.glb");
}

/// Two fits of the shared asset `name`, with the defaults (2 threads) and with `tweak` applied
/// to them; false (with a warning) where ../shared/data is absent.
struct TwoFits {
  Asset asset;
  Character a, b;
  CharacterFitReport ra, rb;
};
// `base` (optional) changes the options of both fits.
bool FitTwice(const std::string& name, const std::function<void(CharacterFitOptions*)>& tweak,
              TwoFits* out, const std::function<void(CharacterFitOptions*)>& base = {}) {
  const std::string source = std::string(test::kSharedGltfDir) + name;
  if (!fs::exists(source)) {
    WARN("skipped: " << source << " is absent (../shared/data)");
    return false;
  }
  REQUIRE(ImportGltf(source, &out->asset).ok());
  CharacterFitOptions with;
  with.fit.threads = 2;
  if (base) base(&with);
  CharacterFitOptions without = with;
  tweak(&without);
  REQUIRE(FitCharacter(out->asset, with, &out->a, &out->ra).ok());
  REQUIRE(FitCharacter(out->asset, without, &out->b, &out->rb).ok());
  REQUIRE(out->ra.part_control_meshes.size() == 1);
  REQUIRE(out->rb.part_control_meshes.size() == 1);
  return true;
}

TEST_CASE("pipeline: RiggedSimple's cap rims get support rows and the surface follows them",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Support rows beside crease loops"): its two
  // cap rims are hard crease loops kept as control edges; with the default support rows the
  // part's two-sided Hausdorff distance (level 8 against its triangles) falls from 0.67 % to
  // 0.41 % of the bounding-box diagonal (bench_fit --rows characters --creases-closed). The
  // rims kept closed: cut open (the default) they need no support rows.
  TwoFits t;
  if (!FitTwice(
          "RiggedSimple.glb", [](CharacterFitOptions* o) { o->crease_support = 1.0; }, &t,
          [](CharacterFitOptions* o) { o->cut_creases = false; })) {
    return;
  }
  const Asset& asset = t.asset;
  const Character &a = t.a, &b = t.b;
  const CharacterFitReport &ra = t.ra, &rb = t.rb;
  CHECK(ra.part_control_meshes[0].crease_support_loops == 2);
  CHECK(ra.part_control_meshes[0].crease_support_vertices >= 32);
  CHECK(rb.part_control_meshes[0].crease_support_vertices == 0);
  CHECK(ra.part_control_meshes[0].control_fit_rounds == 0);  // hard creases: none
  const double ha = a.parts[0].fit.hausdorff, hb = b.parts[0].fit.hausdorff;
  INFO("Hausdorff (of the part's scale): with support rows " << ha << ", without " << hb);
  CHECK(ha < 0.75 * hb);
  // The bound export's error stays small against the part (E1 max, model units; diagonal 9.6):
  // measured 0.0044 since the check points' shading rule drops the finest level, which turned
  // the normals away from the source's shading (docs/characters.md, "Levels checked by the
  // shading"; 0.0022 with every level, `--no-check-shading`; 0.0003 when the tube's sliver
  // triangles had seven times as many samples, before 2026-12-05: the budget of 3 coefficients
  // per fitted point then allowed 8 levels where it now allows 5).
  CHECK(ra.e1_max < 6e-4 * Diagonal(asset));
}

TEST_CASE("pipeline: RiggedFigure's hard edges cut open stay sharp and closed through its clip",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Hard edges cut open"): its 81 crease chains
  // (its box head, feet and limbs) are control edges of its crease-keeping control mesh (its
  // own quads with loops, "Coarse input quads"); cut open, each side is flat up to the crease
  // instead of rounded with a lip. Both fits on that control mesh (closed, the control mesh
  // without creases fits better and would be kept). Measured (bench_fit --rows characters
  // [--creases-closed], where the closed creases lose to the mesh without them): Hausdorff
  // 0.38 % against 0.62 %, shading normals (area) 5.6 / 15.4 degrees mean / p95 against
  // 10.8 / 37.8.
  TwoFits t;
  if (!FitTwice(
          "RiggedFigure.glb", [](CharacterFitOptions* o) { o->cut_creases = false; }, &t,
          [](CharacterFitOptions* o) { o->compare_without_creases = false; })) {
    return;
  }
  const Character &a = t.a, &b = t.b;
  const CharacterFitReport &ra = t.ra, &rb = t.rb;
  // Its own quads with closer loops (their 130 vertices, 414 with the default loops, are fewer
  // than the 1,586 its remesh needs).
  CHECK(ra.part_control_meshes[0].quality.input_quads);
  CHECK(rb.part_control_meshes[0].quality.input_quads);
  CHECK(ra.part_control_meshes[0].quality.vertices >=
        ra.part_control_meshes[0].quality.remesh_vertices);
  // The report says why it has more control vertices than the source has vertices.
  REQUIRE(ra.part_notes.size() == 1);
  INFO(ra.part_notes[0]);
  CHECK(ra.part_notes[0].find("its own quads, with edge loops, stand in for its remesh of " +
                              std::to_string(ra.part_control_meshes[0].quality.remesh_vertices) +
                              " vertices") != std::string::npos);
  CHECK(ra.part_notes[0].find("with " +
                              std::to_string(ra.part_control_meshes[0].crease_cut_vertices) +
                              " vertices added") != std::string::npos);
  CHECK(ra.part_control_meshes[0].crease_cut_edges > 0);
  CHECK(ra.part_control_meshes[0].crease_cut_vertices > 0);
  CHECK(rb.part_control_meshes[0].crease_cut_edges == 0);
  CHECK(a.parts[0].surface.rest_positions.size() ==
        b.parts[0].surface.rest_positions.size() +
            static_cast<std::size_t>(ra.part_control_meshes[0].crease_cut_vertices));
  const double ha = a.parts[0].fit.hausdorff, hb = b.parts[0].fit.hausdorff;
  INFO("Hausdorff (of the part's scale): cut " << ha << ", closed " << hb);
  CHECK(ha < hb);
  // Closed: the lod surface's vertices along a cut are pairs, one per side, at one position
  // (the sides' domain surfaces meet exactly and the displacement vanishes there); posed
  // through the clip by the sweep (the two copies of a crease vertex carry the same weights)
  // they stay together, to float rounding.
  CharacterPoseOptions po;
  po.mode = CharacterPoseMode::kLod;
  po.level = 4;
  CharacterPoser poser;
  REQUIRE(CharacterPoser::Build(a, po, &poser).ok());
  std::vector<PosedPrimitive> rest, posed;
  REQUIRE(poser.PoseClip(-1, 0.0, kDefaultPoseStepsPerSecond, &rest).ok());
  REQUIRE(rest.size() == 1);
  const std::vector<Vec3>& x = rest[0].positions;
  std::vector<std::size_t> order(x.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto less = [&](std::size_t i, std::size_t j) {
    return std::tie(x[i].x, x[i].y, x[i].z) < std::tie(x[j].x, x[j].y, x[j].z);
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t k = 0; k + 1 < order.size(); ++k) {
    if (x[order[k]] == x[order[k + 1]]) pairs.emplace_back(order[k], order[k + 1]);
  }
  Vec3 lo = x[0], hi = x[0];
  for (const Vec3& p : x) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double diagonal = glm::length(hi - lo);
  INFO(pairs.size() << " lod vertices on the cuts, in pairs");
  CHECK(pairs.size() > 500);
  double worst = 0.0;
  REQUIRE(!a.asset.animations.empty());
  const double duration = a.asset.animations[0].Duration();
  for (const double time : {0.25 * duration, 0.5 * duration}) {
    REQUIRE(poser.PoseClip(0, time, kDefaultPoseStepsPerSecond, &posed).ok());
    for (const auto& [i, j] : pairs) {
      worst = std::max(worst, glm::length(posed[0].positions[i] - posed[0].positions[j]));
    }
  }
  INFO("posed: the pairs at most " << worst / diagonal << " of the diagonal apart");
  CHECK(worst < 1e-6 * diagonal);
}

TEST_CASE(
    "pipeline: CesiumMan's smooth-shaded part gets the control-vertex fit and the surface "
    "follows it closer",
    "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "The control-vertex fit on parts without hard
  // creases"): every sharp edge of CesiumMan is shaded smooth, so its part has no hard crease
  // and runs the default 2 rounds; without them (rounds 0) its two-sided Hausdorff distance is
  // 0.42 % of the diagonal, with them 0.33 % (bench_fit --rows characters --input-quads 0). The
  // control mesh is the same (2,058 vertices): the remesh, since its own quads, which replace it
  // by default, are not moved by the fit (the next test).
  // The control-vertex fit's effect alone: both without the refit where the surface leaves the
  // source (CharacterFitOptions::surface_gap), which narrows the difference (measured with it:
  // 0.00359 against 0.00382 of the part's scale).
  TwoFits t;
  if (!FitTwice(
          "CesiumMan.glb", [](CharacterFitOptions* o) { o->fit.control_fit_iterations = 0; }, &t,
          [](CharacterFitOptions* o) {
            o->input_quads = 0.0;
            o->surface_gap = 0.0;
          })) {
    return;
  }
  CHECK_FALSE(t.ra.part_control_meshes[0].quality.input_quads);
  const Character &a = t.a, &b = t.b;
  const CharacterFitReport &ra = t.ra, &rb = t.rb;
  REQUIRE(a.parts.size() == 1);
  REQUIRE(b.parts.size() == 1);
  CHECK(a.parts[0].surface.rest_positions.size() == b.parts[0].surface.rest_positions.size());
  CHECK(ra.part_control_meshes[0].quality.crease_edges_kept == 0);
  CHECK(ra.part_control_meshes[0].control_fit_rounds == 2);
  CHECK(rb.part_control_meshes[0].control_fit_rounds == 0);
  const double ha = a.parts[0].fit.hausdorff, hb = b.parts[0].fit.hausdorff;
  INFO("Hausdorff (of the part's scale): with the control-vertex fit " << ha << ", without " << hb);
  CHECK(ha < 0.85 * hb);
  CHECK(ra.e1_max <= 1.05 * rb.e1_max);  // the bound export no worse
  // The control vertices' skin weights come from the source at their positions after the fit
  // (TransferSkin): the moved vertices keep their weights, not those of a nearby stretch of the
  // part (a finger, the other thigh). Measured (on the remesh, before the weights were smoothed
  // over the control mesh): at most 0.17 of weight moves between joints (half the L1
  // distance), 0.004 on average; the 11 of 2,058 vertices whose largest weight changes joint
  // are ties within 0.02.
  const CharacterPart &pa = a.parts[0], &pb = b.parts[0];
  REQUIRE(pa.control_joints.size() == pb.control_joints.size());
  double worst = 0.0, sum = 0.0;
  for (std::size_t v = 0; v < pa.control_joints.size(); ++v) {
    std::map<int, double> w;
    for (int j = 0; j < 4; ++j) {
      w[pa.control_joints[v][j]] += pa.control_weights[v][j];
      w[pb.control_joints[v][j]] -= pb.control_weights[v][j];
    }
    double l1 = 0.0;
    for (const auto& [joint, d] : w) l1 += std::abs(d);
    worst = std::max(worst, 0.5 * l1);
    sum += 0.5 * l1;
  }
  const double mean = sum / static_cast<double>(pa.control_joints.size());
  CHECK(worst < 0.3);
  CHECK(mean < 0.02);
}

/// The integral of |mean curvature| over the level-8 lod surface, at rest (clip -1) or posed at
/// `time` seconds of `clip` by `deformer` (AbsMeanCurvatureIntegral: (1/2) sum over its edges
/// of |dihedral| x length, Cohen-Steiner and Morvan 2003; bench_fit's curvature ratio is this
/// over the source's at rest), its primitives' seam vertices welded on a grid of 1e-7 of
/// `diagonal`. Every ripple or lump adds to it, though the check points never see the
/// tessellation.
double LodAbsMeanCurvature(const Character& ch, double diagonal, int clip = -1, double time = 0.0,
                           DeformerKind deformer = DeformerKind::kSweep) {
  CharacterPoseOptions po;
  po.mode = CharacterPoseMode::kLod;
  po.level = 8;
  po.deformer = deformer;
  CharacterPoser poser;
  REQUIRE(CharacterPoser::Build(ch, po, &poser).ok());
  std::vector<PosedPrimitive> rest;
  REQUIRE(poser.PoseClip(clip, time, kDefaultPoseStepsPerSecond, &rest).ok());
  std::vector<Vec3> positions;
  std::vector<std::uint32_t> triangles;
  for (std::size_t k = 0; k < rest.size(); ++k) {
    const DrawnPrimitive& d = poser.drawn()[k];
    const AssetPrimitive& prim = poser.asset()
                                     .meshes[static_cast<std::size_t>(d.mesh)]
                                     .primitives[static_cast<std::size_t>(d.primitive)];
    const auto base = static_cast<std::uint32_t>(positions.size());
    positions.insert(positions.end(), rest[k].positions.begin(), rest[k].positions.end());
    for (std::uint32_t i : PrimitiveTriangles(prim)) triangles.push_back(base + i);
  }
  return AbsMeanCurvatureIntegral(positions, triangles, 1e-7 * diagonal);
}

TEST_CASE("pipeline: RiggedFigure's box limbs shaded smooth stay flat instead of bumped",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Which shading surface"): its limbs are
  // long flat boxes whose corner normals are averaged across the bends at the joints, up to
  // 25 degrees along a side. Phong's surface of those normals bulges each long triangle by a
  // parabola of its own (blotches along the arms); its normals are further from the shading
  // normals (3.60 degrees at 0.5) than the flat triangles' (3.24), so by default the part
  // follows the flat triangles. Measured (bench_fit --rows characters, --shading-shape 0.5 for
  // the right-hand figures), on its own quads (docs/characters.md, "Coarse input quads"):
  // curvature ratio 1.33 against 1.42, shading normals (area) mean / p95 5.6 / 15.4 against
  // 6.0 / 15.8 degrees, Hausdorff 0.38 % for both; on the remesh before that 1.48 against 1.56,
  // 5.6 / 14.9 against 6.0 / 15.3, 0.51 %.
  TwoFits t;
  if (!FitTwice(
          "RiggedFigure.glb", [](CharacterFitOptions* o) { o->shading_shape = 0.5; }, &t)) {
    return;
  }
  const ControlMeshInfo &ca = t.ra.part_control_meshes[0], &cb = t.rb.part_control_meshes[0];
  INFO("normals from the shading normals (degrees): flat "
       << ca.flat_deviation_deg << ", Phong at 0.5 " << cb.shading_deviation_deg);
  CHECK(ca.shading_shape == 0.0);
  CHECK(cb.shading_shape == 0.5);
  CHECK(cb.flat_deviation_deg == ca.flat_deviation_deg);
  CHECK(cb.shading_deviation_deg > ca.flat_deviation_deg);
  const double diagonal = Diagonal(t.asset);
  const double ha = LodAbsMeanCurvature(t.a, diagonal), hb = LodAbsMeanCurvature(t.b, diagonal);
  INFO("integral of |H| of the lod surface: flat " << ha << ", Phong " << hb);
  CHECK(ha < 0.97 * hb);
  CHECK(t.a.parts[0].fit.hausdorff < 1.05 * t.b.parts[0].fit.hausdorff);
}

TEST_CASE("pipeline: the Fox keeps its gentle hard edges as creases and comes out faceted",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Gentle hard edges on low-poly parts"): it
  // has no normals, so it is drawn flat, every edge a shading step; 290 welded vertices, so
  // its control mesh is at its own resolution or finer. Its edges from 0.1 rad on are kept
  // as creases (cut open) and that fit is kept. Measured (bench_fit --rows characters,
  // --low-poly-crease-angle 0 for the right-hand figures): lod Hausdorff 0.07 % against 0.38 %
  // of the diagonal,
  // curvature ratio 1.17 against 1.70, E1 max 0.049 against 0.39 model units.
  TwoFits t;
  if (!FitTwice(
          "Fox.glb", [](CharacterFitOptions* o) { o->low_poly_crease_angle = 0.0; }, &t)) {
    return;
  }
  const ControlMeshInfo &ca = t.ra.part_control_meshes[0], &cb = t.rb.part_control_meshes[0];
  CHECK(ca.crease_angle_deg == Approx(0.1 * 180.0 / 3.14159265358979323846).epsilon(1e-12));
  CHECK(cb.crease_angle_deg == Approx(0.5 * 180.0 / 3.14159265358979323846).epsilon(1e-12));
  CHECK(ca.quality.crease_edges_kept > cb.quality.crease_edges_kept);
  const double ha = t.a.parts[0].fit.hausdorff, hb = t.b.parts[0].fit.hausdorff;
  INFO("Hausdorff (of the part's scale): gentle edges kept " << ha << ", rounded " << hb);
  CHECK(ha < 0.5 * hb);
  INFO("E1 max (model units): " << t.ra.e1_max << " against " << t.rb.e1_max);
  CHECK(t.ra.e1_max < 0.5 * t.rb.e1_max);
  const double diagonal = Diagonal(t.asset);
  const double ka = LodAbsMeanCurvature(t.a, diagonal), kb = LodAbsMeanCurvature(t.b, diagonal);
  INFO("integral of |H| of the lod surface: " << ka << " against " << kb);
  CHECK(ka < 0.85 * kb);
}

TEST_CASE("pipeline: no data point is fitted to a distant root beside the Fox's cuts",
          "[data][heavy]") {
  // With its hard edges from 0.05 rad on cut open, the Fox's control mesh has corner charts
  // whose patch projections could end on a distant part of the surface: a root of Yoon's
  // projection 1.5 to 3.1 model units from the point where the surface passes within 1e-4 (three
  // samples of its head; the fit's own Hausdorff distance read 2 % of its size, and the
  // low-poly refit was refused for it). The point fit now starts again from the closest
  // surface point where a fit is further from the point than the closest control face by more
  // than a twentieth of that face (point_fit.cpp).
  TwoFits t;
  if (!FitTwice(
          "Fox.glb", [](CharacterFitOptions* o) { o->low_poly_crease_angle = 0.1; }, &t,
          [](CharacterFitOptions* o) { o->low_poly_crease_angle = 0.05; })) {
    return;
  }
  const ControlMeshInfo& c = t.ra.part_control_meshes[0];
  INFO("Hausdorff (of the part's scale) " << t.a.parts[0].fit.hausdorff << ", crease angle "
                                          << c.crease_angle_deg);
  CHECK(c.crease_angle_deg == Approx(0.05 * 180.0 / 3.14159265358979323846).epsilon(1e-12));
  // The fit's own Hausdorff distance (of the part's size, largest side 1): measured 3.4e-4,
  // 2e-2 before; at the default 0.1 rad 8.4e-4 (the lod surface against the source, as
  // bench_fit measures it: 0.03 % and 0.07 % of the diagonal).
  CHECK(t.a.parts[0].fit.hausdorff < 1e-3);
  CHECK(t.b.parts[0].fit.hausdorff < 1e-3);
  CHECK(t.ra.e1_max < 0.05);
}

TEST_CASE("pipeline: CesiumMan's finest levels that ripple its hips are dropped by the shading",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Levels checked by the shading"): its finest
  // displacement levels pinned the surface to each ring of vertices round the hips and left
  // ridges between them, which every distance measured passed (they improve the check points'
  // mean distance at every level). The check points' shading normals see them: a level that
  // turns the surface's normals away from the source's shading there is dropped.
  TwoFits t;
  if (!FitTwice(
          "CesiumMan.glb", [](CharacterFitOptions* o) { o->check_shading = false; }, &t)) {
    return;
  }
  const ControlMeshInfo &ca = t.ra.part_control_meshes[0], &cb = t.rb.part_control_meshes[0];
  // A part denser than the low-poly rule gets check points for the shading rule alone.
  CHECK(ca.check_points > 1000);
  CHECK(cb.check_points == 0);
  CHECK(cb.check_angle_deg.empty());
  REQUIRE(ca.shading_levels_dropped >= 1);
  // Its angles: with no level, and with each level the distance rule kept.
  const int kept = static_cast<int>(ca.check_angle_deg.size()) - 1 - ca.shading_levels_dropped;
  REQUIRE(kept >= 1);
  const auto& angle = ca.check_angle_deg;
  CHECK(angle[static_cast<std::size_t>(kept)] < angle[0]);  // the levels kept help the shading
  for (std::size_t l = static_cast<std::size_t>(kept) + 1; l < angle.size(); ++l) {
    CHECK(angle[l] > angle[l - 1]);  // each dropped level turned the normals away
  }
  const PartFitSummary &fa = t.a.parts[0].fit, &fb = t.b.parts[0].fit;
  // Measured independently on the lod tessellation (not at the check points): the integral of
  // its |mean curvature| falls as the ridges go; the surface stays as close (Hausdorff
  // 0.35 % against 0.27 % of the diagonal, issue 15's goal 0.75 %) with a third of the
  // coefficients.
  const double na = LodAbsMeanCurvature(t.a, Diagonal(t.asset)),
               nb = LodAbsMeanCurvature(t.b, Diagonal(t.asset));
  INFO("angles at the check points "
       << angle[static_cast<std::size_t>(kept)] << " kept, " << angle.back()
       << " with every level; lod |H| integral " << na << " against " << nb << "; coefficients "
       << fa.coefficients << " against " << fb.coefficients << "; Hausdorff " << fa.hausdorff
       << " against " << fb.hausdorff);
  CHECK(na < 0.95 * nb);
  CHECK(2 * fa.coefficients < fb.coefficients);
  CHECK(fa.hausdorff < 1.5 * fb.hausdorff);
}

TEST_CASE("pipeline: CesiumMan, modelled in quads, gets its own quads as its control mesh",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "The input's own quads"): its triangles pair
  // back into quads over its 2,338 welded vertices; edge loops across its long strips (the
  // forearms, the shins) bring them to 2,498, more regular than the remesh's 2,058-vertex
  // control mesh and less than 1.5 times its count, so they are the control mesh. The domain
  // surface then interpolates the source's vertices, so the bound export reproduces them far
  // closer, and the control-vertex fit leaves them there.
  TwoFits t;
  if (!FitTwice(
          "CesiumMan.glb", [](CharacterFitOptions* o) { o->input_quads = 0.0; }, &t)) {
    return;
  }
  const Character &a = t.a, &b = t.b;
  const CharacterFitReport &ra = t.ra, &rb = t.rb;
  const QuadRemeshReport &qa = ra.part_control_meshes[0].quality,
                         &qb = rb.part_control_meshes[0].quality;
  REQUIRE(qa.input_quads);
  CHECK_FALSE(qb.input_quads);
  CHECK(qa.remesh_vertices == qb.vertices);
  CHECK(qa.triangles_unpaired == 0);
  CHECK(qa.quads_paired < qa.faces);  // the loops split some of them
  CHECK(qa.valence4_share >= qb.valence4_share);
  CHECK(ra.part_control_meshes[0].control_fit_rounds == 0);
  CHECK(rb.part_control_meshes[0].control_fit_rounds == 2);
  // Shaded smooth as a round body: its shading surface (Phong) follows its normals far better
  // than its facets (4.75 against 9.09 degrees), and the part takes it.
  CHECK(ra.part_control_meshes[0].shading_shape > 0.0);
  CHECK(ra.part_control_meshes[0].shading_deviation_deg <
        0.6 * ra.part_control_meshes[0].flat_deviation_deg);
  // Every source vertex position (mesh space) is a control vertex; the rest are the inserted
  // edge loops' (on the forearms and shins, where the modeller's quads are longest).
  auto less = [](const Vec3& p, const Vec3& q) {
    return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
  };
  std::vector<Vec3> cv = a.parts[0].surface.rest_positions;
  std::sort(cv.begin(), cv.end(), less);
  const AssetPrimitive& prim =
      t.asset.meshes[static_cast<std::size_t>(a.parts[0].mesh)].primitives[0];
  std::vector<Vec3> source;
  for (const auto& p : prim.positions) source.push_back(Vec3(p));
  std::sort(source.begin(), source.end(), less);
  source.erase(std::unique(source.begin(), source.end()), source.end());
  std::size_t kept = 0;
  for (const Vec3& x : source) kept += std::binary_search(cv.begin(), cv.end(), x, less) ? 1 : 0;
  CHECK(kept == source.size());
  CHECK(cv.size() > source.size());
  CHECK(static_cast<double>(cv.size()) <= 1.5 * static_cast<double>(qb.vertices));
  // Closer to the source both ways, and the bound export's largest error a third of the
  // remesh's (measured: Hausdorff 0.0041 against 0.0044 of the part's scale, E1 max 9.7e-4
  // against 2.8e-3 model units; before the check points' shading rule dropped CesiumMan's
  // finest levels, which pinned the surface to each ring of vertices and rippled it between
  // them, 0.29 % against 0.33 % of the diagonal and 5.9e-5 against 1.5e-3).
  const double ha = a.parts[0].fit.hausdorff, hb = b.parts[0].fit.hausdorff;
  INFO("Hausdorff (of the part's scale): own quads " << ha << ", remesh " << hb << "; E1 max "
                                                     << ra.e1_max << " against " << rb.e1_max);
  CHECK(ha < hb);
  CHECK(ra.e1_max < 0.5 * rb.e1_max);
}

TEST_CASE("pipeline: CesiumMan's skin weights smoothed on its control mesh keep its walk unrippled",
          "[data][heavy]") {
  // The Khronos asset itself (docs/characters.md, "Skin weights smoothed on the control mesh"):
  // its painted weights change across single edges (0.82 to 0.46 on the arm at the shoulders),
  // and the domain surface, which interpolates its posed control vertices, rippled the flanks
  // and chest in its walk under every deformer. The weights are smoothed over the control mesh
  // (two umbrella steps by default); the fit itself does not change.
  TwoFits t;
  if (!FitTwice(
          "CesiumMan.glb", [](CharacterFitOptions* o) { o->skin_smoothing = 0; }, &t)) {
    return;
  }
  const double diagonal = Diagonal(t.asset);
  // At rest the two are the same surface (the bind pose reproduces it to rounding).
  const double rest = LodAbsMeanCurvature(t.a, diagonal);
  CHECK(rest == Approx(LodAbsMeanCurvature(t.b, diagonal)).epsilon(1e-6));
  // Posed, the integral of |mean curvature| rises by the bends and by the ripples; measured:
  // the rise is 0.41-0.56 of the transferred weights' (rest 18.98; sweep at 0.4 / 0.8 /
  // 1.2 s 21.61 / 21.80 / 20.73 against 23.69 / 24.66 / 22.82, LBS 21.35 / 21.20 / 20.82
  // against 23.80 / 24.40 / 23.13).
  for (const DeformerKind deformer : {DeformerKind::kSweep, DeformerKind::kLbs}) {
    for (const double time : {0.4, 0.8, 1.2}) {
      const double na = LodAbsMeanCurvature(t.a, diagonal, 0, time, deformer),
                   nb = LodAbsMeanCurvature(t.b, diagonal, 0, time, deformer);
      INFO(DeformerName(deformer) << " at " << time << " s: lod |H| integral " << na
                                  << " smoothed, " << nb << " as transferred, " << rest
                                  << " at rest");
      CHECK(na - rest < 0.7 * (nb - rest));
    }
  }
}

}  // namespace

}  // namespace dermis
