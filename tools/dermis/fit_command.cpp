// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis fit: dense mesh or point cloud -> control mesh + displacements (.dsurf), with a JSON
// report of the fit's errors and timings (paper section 4, Table 1).

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "character_json.h"
#include "commands.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/fit/surface_fit.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/point_input.h"
#include "importers.h"
#include "progress_bar.h"
#include "report_json.h"

namespace dermis::cli {
namespace {

constexpr const char* kFitCommand = "fit";

struct FitArgs {
  std::string input;
  std::string output;
  std::string control_mesh;
  std::string report;
  int control_vertices = FitOptions{}.control_vertices;
  int levels = DisplacementFitOptions{}.max_levels;
  double density = -1.0;  // < 0 here and below: the library's default for the input kind
  int finest_passes = DisplacementFitOptions{}.finest_passes;
  double smoothing = -1.0;
  int control_fit = -1;  // -1: the library's default for the input kind
  double patch_agreement = FitOptions{}.control_fit.patch_agreement;
  double noisy_ratio = -1.0;  // -1: the library's default for the input kind
  int clean_rounds = FitOptions{}.control_fit_clean_iterations;
  bool no_cover_boundary = !FitOptions{}.cover_boundary;
  std::string method;  // empty: the library's default for the input kind
  double node_weight = -1.0;
  double level_smoothing = -1.0;
  double validation = -1.0;
  double min_improvement = -1.0;
  double residual = -1.0;
  double budget = -1.0;
  double consistency = -1.0;
  double holdout = FitOptions{}.holdout;
  int threads = 0;
  bool quiet = false;
  double control_ratio = CharacterFitOptions{}.vertex_ratio;
  std::string shading_shape = "auto";  ///< "auto" or a shape factor in [0, 1].
  double shading_max_move = CharacterFitOptions{}.shading_max_move;
  double crease_smoothing = CharacterFitOptions{}.crease_smoothing;
  double vertex_weight = CharacterFitOptions{}.vertex_weight;
  bool creases_ignore_shading = false;
  bool creases_closed = false;
  double crease_support = CharacterFitOptions{}.crease_support;
  double input_quads = CharacterFitOptions{}.input_quads;
  double surface_gap = CharacterFitOptions{}.surface_gap;
  double check_points = CharacterFitOptions{}.check_points;
  bool no_check_shading = false;
  int skin_smoothing = CharacterFitOptions{}.skin_smoothing;
  double low_poly_crease_angle = CharacterFitOptions{}.low_poly_crease_angle;
  bool refit = false;
  // Options given on the command line that only one kind of input takes (set at parse time):
  // a fit of the other kind refuses them instead of ignoring them.
  std::vector<std::string> surface_only, character_only;
  // Options that build or move the automatic control mesh, refused with --control-mesh.
  std::vector<std::string> automatic_only;
};

// "--a", "--a and --b", "--a, --b and --c".
std::string ListOptions(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) out += i + 1 == names.size() ? " and " : ", ";
    out += names[i];
  }
  return out;
}

nlohmann::ordered_json ControlMeshJson(const ControlMeshInfo& c) {
  const QuadRemeshReport& q = c.quality;
  nlohmann::ordered_json m;
  m["method"] = c.method;
  m["fallback"] =
      c.fallback.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(c.fallback);
  m["target_vertices"] =
      c.method == "given" ? nlohmann::ordered_json() : nlohmann::ordered_json(q.target_vertices);
  m["vertices"] = q.vertices;
  m["faces"] = q.faces;
  m["interior_vertices"] = q.interior_vertices;
  m["interior_valence4_share"] = q.valence4_share;
  m["max_valence"] = q.max_valence;
  m["min_corner_angle_deg"] = q.min_corner_angle_deg;
  m["max_corner_angle_deg"] = q.max_corner_angle_deg;
  m["corners_60_120_share"] = q.corners_60_120_share;
  m["components"] = q.components;
  m["boundary_loops"] = q.boundary_loops;
  if (c.method == "remesh") {
    m["seed_vertices"] = q.seed_vertices;
    m["triangle_vertices"] = q.triangle_vertices;
    m["quads_paired"] = q.quads_paired;
    m["triangles_unpaired"] = q.triangles_unpaired;
    m["input_quads"] = q.input_quads;
    if (q.input_quads) m["remesh_vertices"] = q.remesh_vertices;
    if (q.crease_edges > 0) {
      m["crease_edges"] = q.crease_edges;
      m["crease_edges_kept"] = q.crease_edges_kept;
      m["crease_chains"] = q.crease_chains;
      m["crease_closed_chains"] = q.crease_closed_chains;
      m["control_crease_edges"] = q.control_crease_edges;
      m["crease_support_loops"] = c.crease_support_loops;
      m["crease_support_vertices"] = c.crease_support_vertices;
      m["crease_cut_edges"] = c.crease_cut_edges;
      m["crease_cut_vertices"] = c.crease_cut_vertices;
    }
    if (q.grown_target > 0) {
      m["grown_target"] = q.grown_target;
      m["deviation_edge_lengths"] = q.deviation;
    }
  }
  // Characters (CharacterFitOptions::surface_gap), whichever method made the control mesh.
  if (c.surface_gap_points > 0) m["surface_gap_points"] = c.surface_gap_points;
  // Characters' check points (CharacterFitOptions::check_points, check_shading).
  if (c.check_points > 0) {
    m["check_points"] = c.check_points;
    m["check_levels_dropped"] = c.check_levels_dropped;
    if (!c.check_angle_deg.empty()) {
      m["check_angle_deg"] = c.check_angle_deg;
      m["shading_levels_dropped"] = c.shading_levels_dropped;
    }
  }
  return m;
}

// The displacement options the command line sets (the others keep `o`'s values).
void ApplyDisplacementArgs(const FitArgs& a, DisplacementFitOptions* o) {
  o->max_levels = a.levels;
  if (a.method == "mba") o->method = DisplacementMethod::kMba;
  if (a.method == "adaptive") o->method = DisplacementMethod::kAdaptive;
  if (a.density >= 0.0) o->density = a.density;
  o->finest_passes = a.finest_passes;
  if (a.smoothing >= 0.0) o->smoothing = a.smoothing;
  if (a.node_weight > 0.0) o->adaptive.min_node_weight = a.node_weight;
  if (a.level_smoothing >= 0.0) o->adaptive.smoothing = a.level_smoothing;
  if (a.validation >= 0.0) o->adaptive.validation = a.validation;
  if (a.min_improvement >= 0.0) o->adaptive.min_improvement = a.min_improvement;
  if (a.residual >= 0.0) o->adaptive.residual_threshold = a.residual;
  if (a.budget >= 0.0) o->adaptive.max_coefficients_per_point = a.budget;
  if (a.consistency >= 0.0) o->adaptive.consistency = a.consistency;
}

/// The options a fit ran with, after the library's defaults for the input kind were applied,
/// keyed by their command-line names (StartReport), so that a report says how to repeat its run.
Json EffectiveOptionsJson(const FitArgs& a, const FitOptions& f) {
  Json o;
  // With a given control mesh the options that only a built one takes are left out, so that
  // the report's options repeat the run (they are refused beside --control-mesh).
  if (a.control_mesh.empty()) {
    o["control-vertices"] = f.control_vertices;
    o["control-fit"] = f.control_fit_iterations;
    o["patch-agreement"] = f.control_fit.patch_agreement;
    o["noisy-ratio"] = f.control_fit_noisy_ratio;
    o["clean-rounds"] = f.control_fit_clean_iterations;
  } else {
    o["control-mesh"] = a.control_mesh;
  }
  o["no-cover-boundary"] = !f.cover_boundary;
  o["holdout"] = f.holdout;
  const DisplacementFitOptions& d = f.displacement;
  o["displacement"] = d.method == DisplacementMethod::kMba ? "mba" : "adaptive";
  o["levels"] = d.max_levels;
  o["density"] = d.density;
  o["finest-passes"] = d.finest_passes;
  o["smoothing"] = d.smoothing;
  o["node-weight"] = d.adaptive.min_node_weight;
  o["level-smoothing"] = d.adaptive.smoothing;
  o["validation"] = d.adaptive.validation;
  o["min-improvement"] = d.adaptive.min_improvement;
  o["residual-threshold"] = d.adaptive.residual_threshold;
  o["coefficients-per-point"] = d.adaptive.max_coefficients_per_point;
  o["consistency"] = d.adaptive.consistency;
  o["threads"] = a.threads;
  return o;
}

Json ReportJson(const FitArgs& a, const FitOptions& options, const FitReport& r) {
  Json j;
  StartReport(&j, "dermis.fit/1", EffectiveOptionsJson(a, options));
  j["input"] = a.input;
  j["output"] = a.output;
  j["points"] = r.points;
  j["points_dropped"] = r.points_dropped;
  j["points_fitted"] = r.points_fitted;
  j["points_holdout"] = r.points_holdout;
  j["points_outside"] = r.points_outside;
  j["points_not_converged"] = r.points_not_converged;
  j["points_not_converged_placed"] = r.points_not_converged_placed;
  j["control_vertices"] = r.control_vertices;
  j["control_faces"] = r.control_faces;
  j["control_fit_rounds"] = r.control_fit_rounds;
  j["noise_ratio"] = r.noise_ratio;
  j["control_fit_regularisation"] = r.control_fit_regularisation;
  j["boundary_points_beyond"] = r.boundary_points_beyond;
  j["boundary_largest_excess"] = r.boundary_largest_excess;
  j["boundary_vertices_moved"] = r.boundary_vertices_moved;
  j["control_mesh"] = ControlMeshJson(r.control_mesh);
  j["coefficients"] = r.coefficients;
  j["coefficients_per_point"] = r.coefficients_per_point;
  j["finest_coefficients"] = r.finest_coefficients;
  j["level_coefficients"] = r.level_coefficients;
  if (!r.displacement_fit.trial.empty()) {
    // The adaptive fit's stopping rule: its trial levels (errors in the unit above).
    nlohmann::ordered_json trial = nlohmann::ordered_json::array();
    for (const AdaptiveLevelReport& l : r.displacement_fit.trial) {
      nlohmann::ordered_json t;
      t["level"] = l.level;
      t["nodes"] = l.nodes;
      t["fitted_mean"] = l.train_mean / r.scale;
      t["validation_mean"] = l.validation_mean / r.scale;
      t["kept"] = l.level < r.displacement_fit.levels;
      trial.push_back(t);
    }
    j["displacement_levels"] = trial;
  }
  if (!r.displacement_fit.stopped_by.empty()) {
    j["displacement_stopped_by"] = r.displacement_fit.stopped_by;
  }
  j["levels"] = r.max_levels;
  j["threads"] = r.threads;
  j["unit"] = "data scaled so its bounding box's largest side is 1";
  j["scale"] = r.scale;
  nlohmann::ordered_json e;
  e["mean"] = r.error.mean;
  e["rms"] = r.error.rms;
  e["max"] = r.error.max;
  e["unoptimized_mean"] = r.error.unoptimized_mean;
  e["closest_mean"] = r.error.closest_mean;
  e["holdout_mean"] = r.error.holdout_mean;
  e["holdout_max"] = r.error.holdout_max;
  if (r.error.has_hausdorff) {
    e["hausdorff"] = r.error.hausdorff;
    e["hausdorff_percent_diagonal"] = r.error.hausdorff_percent_diagonal;
  } else {
    e["hausdorff"] = nullptr;
    e["hausdorff_percent_diagonal"] = nullptr;
  }
  j["error"] = e;
  nlohmann::ordered_json t;
  t["control_mesh"] = r.seconds.control_mesh;
  t["projection_optimization"] = r.seconds.projection_optimization;
  t["displacement"] = r.seconds.displacement;
  t["total"] = r.seconds.total;
  t["metrics"] = r.seconds.metrics;
  j["seconds"] = t;
  return j;
}

Json CharacterReportJson(const FitArgs& a, const CharacterFitOptions& options, const Character& ch,
                         const CharacterFitReport& r) {
  Json options_json = EffectiveOptionsJson(a, options.fit);
  // A character's control meshes follow --control-ratio, and every vertex is fitted.
  for (const char* key : {"control-vertices", "holdout"}) options_json.erase(key);
  options_json["control-ratio"] = options.vertex_ratio;
  if (options.shading_shape < 0.0) {
    options_json["shading-shape"] = "auto";
  } else {
    options_json["shading-shape"] = options.shading_shape;
  }
  options_json["shading-max-move"] = options.shading_max_move;
  options_json["low-poly-crease-angle"] = options.low_poly_crease_angle;
  options_json["crease-smoothing"] = options.crease_smoothing;
  options_json["vertex-weight"] = options.vertex_weight;
  options_json["creases-ignore-shading"] = !options.creases_follow_shading;
  options_json["crease-support"] = options.crease_support;
  options_json["creases-closed"] = !options.cut_creases;
  options_json["input-quads"] = options.input_quads;
  options_json["surface-gap"] = options.surface_gap;
  options_json["check-points"] = options.check_points;
  options_json["no-check-shading"] = !options.check_shading;
  options_json["skin-smoothing"] = options.skin_smoothing;
  options_json["refit"] = a.refit;
  Json j;
  StartReport(&j, "dermis.fit-character/1", std::move(options_json));
  j["input"] = a.input;
  j["output"] = a.output;
  j["meshes"] = r.meshes;
  j["components"] = r.components;
  j["parts_fitted"] = r.parts_fitted;
  j["parts_unfitted"] = r.parts_unfitted;
  j["vertices"] = r.vertices;
  j["vertices_bound"] = r.vertices_bound;
  j["unit"] = "model units";
  j["e1_mean"] = r.e1_mean;
  j["e1_max"] = r.e1_max;
  // Per part and unfitted: the same description as `dermis inspect` gives.
  const Json c = DescribeCharacter(ch);
  j["parts"] = c["parts"];
  j["unfitted"] = c["unfitted"];
  // How each part's control mesh was made, in part order.
  Json meshes = Json::array();
  for (std::size_t p = 0; p < r.part_control_meshes.size(); ++p) {
    nlohmann::ordered_json m = ControlMeshJson(r.part_control_meshes[p]);
    const ControlMeshInfo& cm = r.part_control_meshes[p];
    m["control_fit_rounds"] = cm.control_fit_rounds;
    // The shading surface the part followed (CharacterFitOptions::shading_shape).
    m["shading_shape"] = cm.shading_shape;
    m["shading_normal_deviation_deg"] = cm.shading_deviation_deg;
    m["flat_normal_deviation_deg"] = cm.flat_deviation_deg;
    m["crease_angle_deg"] = cm.crease_angle_deg;
    const std::string note = p < r.part_notes.size() ? r.part_notes[p] : std::string();
    m["note"] = note.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(note);
    meshes.push_back(m);
  }
  j["control_meshes"] = meshes;
  j["seconds"] = r.seconds;
  return j;
}

int RunFitCharacter(const FitArgs& a) {
  ImportedAsset imported;
  Status s = Importers().ImportAsset(a.input, &imported);
  if (!s.ok()) return Fail(kFitCommand, s);
  const Asset& asset = imported.asset;
  const std::string& embedded = imported.embedded_dsurf;
  MakeParentFolder(a.output);
  if (!embedded.empty() && !a.refit) {
    // A Dermis export with the .dsurf embedded: take it back as it was (lossless).
    Character check;
    s = ParseCharacter(embedded, a.input + ": extension DERMIS_displaced_surface", &check);
    if (!s.ok()) return Fail(kFitCommand, s);
    s = WriteFileAtomically(a.output, embedded);
    if (!s.ok()) return Fail(kFitCommand, s);
    if (!a.quiet) {
      std::fprintf(stderr,
                   "dermis fit: %s carries a Dermis surface (DERMIS_displaced_surface); wrote it "
                   "unchanged to %s (use --refit to fit again)\n",
                   a.input.c_str(), a.output.c_str());
    }
    return kExitOk;
  }
  CharacterFitOptions options;
  options.vertex_ratio = a.control_ratio;
  // Checked by the option's validator: "auto" or a number in [0, 1].
  options.shading_shape =
      a.shading_shape == "auto" ? -1.0 : std::strtod(a.shading_shape.c_str(), nullptr);
  options.shading_max_move = a.shading_max_move;
  options.low_poly_crease_angle = a.low_poly_crease_angle;
  options.crease_smoothing = a.crease_smoothing;
  options.vertex_weight = a.vertex_weight;
  options.creases_follow_shading = !a.creases_ignore_shading;
  options.cut_creases = !a.creases_closed;
  options.crease_support = a.crease_support;
  options.input_quads = a.input_quads;
  options.surface_gap = a.surface_gap;
  options.check_points = a.check_points;
  options.check_shading = !a.no_check_shading;
  options.skin_smoothing = a.skin_smoothing;
  ApplyDisplacementArgs(a, &options.fit.displacement);
  if (a.control_fit >= 0) options.fit.control_fit_iterations = a.control_fit;
  options.fit.control_fit_clean_iterations = a.clean_rounds;
  options.fit.control_fit.patch_agreement = a.patch_agreement;
  if (a.noisy_ratio >= 0.0) options.fit.control_fit_noisy_ratio = a.noisy_ratio;
  options.fit.cover_boundary = !a.no_cover_boundary;
  options.fit.threads = a.threads;
  ProgressBar progress(kFitCommand, a.quiet);
  options.progress = progress.Callback();
  Character ch;
  CharacterFitReport report;
  s = FitCharacter(asset, options, &ch, &report);
  progress.Clear();
  if (!s.ok()) return Fail(kFitCommand, s);
  s = WriteFileAtomically(a.output, SerializeCharacter(ch));
  if (!s.ok()) return Fail(kFitCommand, s);
  if (!a.report.empty()) {
    MakeParentFolder(a.report);
    s = WriteFileAtomically(a.report,
                            CharacterReportJson(a, options, ch, report)
                                    .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
                                "\n");
    if (!s.ok()) return Fail(kFitCommand, s);
  }
  if (!a.quiet) {
    std::fprintf(
        stderr,
        "dermis fit: %s: %lld meshes, %lld components: %lld fitted, %lld left as "
        "meshes\n  %lld of %lld vertices bound, E1 mean %.3g max %.3g (model units), "
        "%.2f s\n",
        a.input.c_str(), static_cast<long long>(report.meshes),
        static_cast<long long>(report.components), static_cast<long long>(report.parts_fitted),
        static_cast<long long>(report.parts_unfitted),
        static_cast<long long>(report.vertices_bound), static_cast<long long>(report.vertices),
        report.e1_mean, report.e1_max, report.seconds);
    for (const UnfittedPart& u : ch.unfitted) {
      std::fprintf(stderr, "  not fitted: mesh %d component %d (%lld vertices): %s\n", u.mesh,
                   u.component, static_cast<long long>(u.vertices), u.reason.c_str());
    }
    for (const std::string& note : report.part_notes) {
      if (!note.empty()) std::fprintf(stderr, "  note: %s\n", note.c_str());
    }
    for (const ControlMeshInfo& c : report.part_control_meshes) {
      if (!c.fallback.empty()) {
        std::fprintf(stderr, "  note: control mesh by simplification: %s\n", c.fallback.c_str());
      }
    }
    std::fprintf(stderr, "wrote %s\n", a.output.c_str());
  }
  return kExitOk;
}

int RunFit(const FitArgs& a) {
  // A file a scan importer takes is one surface; anything else is a character.
  const bool character = Importers().Find(a.input, ImportKind::kScan) == nullptr;
  const std::vector<std::string>& refused = character ? a.surface_only : a.character_only;
  if (!refused.empty()) {
    const char* verb = refused.size() == 1 ? " applies" : " apply";
    return Usage(
        kFitCommand,
        character ? ListOptions(refused) + verb + " to a surface (.obj, .ply), and " + a.input +
                        " is read as a character (glTF, or a format Assimp reads): its "
                        "control meshes follow --control-ratio"
                  : ListOptions(refused) + verb + " to a character (.glb, .gltf, .fbx, ...), and " +
                        a.input + " is a surface");
  }
  // A given control mesh is used as is: the options that build or move one do not apply.
  if (!a.control_mesh.empty() && !a.automatic_only.empty()) {
    const char* verb = a.automatic_only.size() == 1 ? " applies" : " apply";
    return Usage(kFitCommand, ListOptions(a.automatic_only) + verb +
                                  " to the automatic control mesh, and --control-mesh gives one, "
                                  "used as is");
  }
  if (character) return RunFitCharacter(a);
  PolygonMesh mesh;
  Index dropped = 0;
  Status s = ReadFitInput(a.input, &mesh, &dropped, &Importers());
  if (!s.ok()) return Fail(kFitCommand, s);
  PolygonMesh control;
  if (!a.control_mesh.empty()) {
    s = ReadObj(a.control_mesh, &control);
    if (!s.ok()) return Fail(kFitCommand, s);
  } else if (mesh.num_faces() == 0) {
    return Fail(kFitCommand,
                Status::InvalidInput(a.input + ": a point cloud (no faces) needs --control-mesh"));
  }
  FitInput input;
  input.points = mesh.positions;
  input.mesh = mesh.num_faces() > 0 ? &mesh : nullptr;
  input.control = a.control_mesh.empty() ? nullptr : &control;
  input.points_dropped = dropped;
  FitOptions options;
  options.control_vertices = a.control_vertices;
  ApplyDisplacementArgs(a, &options.displacement);
  if (a.control_fit >= 0) options.control_fit_iterations = a.control_fit;
  options.control_fit_clean_iterations = a.clean_rounds;
  options.control_fit.patch_agreement = a.patch_agreement;
  if (a.noisy_ratio >= 0.0) options.control_fit_noisy_ratio = a.noisy_ratio;
  options.cover_boundary = !a.no_cover_boundary;
  options.holdout = a.holdout;
  options.threads = a.threads;
  ProgressBar progress(kFitCommand, a.quiet);
  options.progress = progress.Callback();
  FittedSurface fitted;
  FitReport report;
  s = FitSurface(input, options, &fitted, &report);
  progress.Clear();
  if (!s.ok()) return Fail(kFitCommand, s);
  const std::string bytes =
      SerializeDsurf(*fitted.surface.domain, fitted.surface.control.positions.data(),
                     fitted.displacement.get(), report.points);
  MakeParentFolder(a.output);
  s = WriteFileAtomically(a.output, bytes);
  if (!s.ok()) return Fail(kFitCommand, s);
  if (!a.report.empty()) {
    MakeParentFolder(a.report);
    s = WriteFileAtomically(a.report,
                            ReportJson(a, options, report)
                                    .dump(2, ' ', false, nlohmann::json::error_handler_t::replace) +
                                "\n");
    if (!s.ok()) return Fail(kFitCommand, s);
  }
  if (!a.quiet && !report.control_mesh.fallback.empty()) {
    std::fprintf(stderr, "dermis fit: note: control mesh by simplification: %s\n",
                 report.control_mesh.fallback.c_str());
  }
  if (!a.quiet) {
    std::fprintf(stderr,
                 "dermis fit: %s: %lld points (%lld dropped, %lld held out), %lld control "
                 "vertices, %lld coefficients (%.2f per point)\n"
                 "  E1 mean %.3g rms %.3g max %.3g (unoptimized %.3g), held-out mean %.3g, "
                 "Hausdorff %.3g%% of diagonal\n"
                 "  %.2f s (control mesh %.2f, projection+optimisation %.2f, displacement %.2f)"
                 "\nwrote %s\n",
                 a.input.c_str(), static_cast<long long>(report.points),
                 static_cast<long long>(report.points_dropped),
                 static_cast<long long>(report.points_holdout),
                 static_cast<long long>(report.control_vertices),
                 static_cast<long long>(report.coefficients), report.coefficients_per_point,
                 report.error.mean, report.error.rms, report.error.max,
                 report.error.unoptimized_mean, report.error.holdout_mean,
                 report.error.hausdorff_percent_diagonal, report.seconds.total,
                 report.seconds.control_mesh, report.seconds.projection_optimization,
                 report.seconds.displacement, a.output.c_str());
  }
  return kExitOk;
}

// A default as --help shows it, read from the library's options (so that the help cannot drift
// from them): "default X", or "default X for a surface, Y for a character" where they differ.
std::string DefaultText(double surface, double character) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  if (surface == character) return "default " + num(surface);
  return "default " + num(surface) + " for a surface, " + num(character) + " for a character";
}

}  // namespace

void AddFitCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<FitArgs>();
  const FitOptions surface;
  const FitOptions character = CharacterFitOptions{}.fit;
  const AdaptiveDisplacementOptions& sa = surface.displacement.adaptive;
  const AdaptiveDisplacementOptions& ca = character.displacement.adaptive;
  CLI::App* cmd = app->add_subcommand(
      "fit", "Fit a displaced manifold surface to a dense mesh or point cloud; write .dsurf.");
  cmd->add_option("INPUT", args->input,
                  "Dense mesh or point cloud (.obj, .ply), or a character: .glb, .gltf, or any "
                  "format Assimp reads (.fbx, .dae, ...)")
      ->required();
  cmd->add_option("-o,--output", args->output, "Output .dsurf")->required();
  cmd->add_option("--control-vertices", args->control_vertices,
                  "Surfaces: control vertices of the automatic control mesh")
      ->check(CLI::Range(8, 10000000))
      ->capture_default_str();
  cmd->add_option("--control-mesh", args->control_mesh,
                  "Surfaces: use this polygon OBJ as the control mesh (as is)");
  cmd->add_option("--levels", args->levels, "Most displacement levels per chart")
      ->check(CLI::Range(1, kMaxBsplineLevels))
      ->capture_default_str();
  cmd->add_option("--displacement", args->method,
                  "How displacements are fitted: adaptive (levels refined where the data "
                  "support them, as many as a validation split finds useful; the default) or "
                  "mba (dense per-chart lattices, the paper's method)")
      ->check(CLI::IsMember({"adaptive", "mba"}));
  cmd->add_option("--node-weight", args->node_weight,
                  "adaptive: points a lattice node needs under its support (density criterion; " +
                      DefaultText(sa.min_node_weight, ca.min_node_weight) + ")")
      ->check(CLI::Range(1e-3, 1e3));
  cmd->add_option("--level-smoothing", args->level_smoothing,
                  "adaptive: thin-plate weight of every level (" +
                      DefaultText(sa.smoothing, ca.smoothing) +
                      "; a character's parts on a control mesh that keeps creases, or whose "
                      "sharp edges are all shaded smooth, take --crease-smoothing)")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--validation", args->validation,
                  "adaptive: fraction of the points that decides how many levels to keep (" +
                      DefaultText(sa.validation, ca.validation) +
                      "; with 0 levels stop when they improve the fitted points by less than "
                      "--min-improvement)")
      ->check(CLI::Range(0.0, 0.9));
  cmd->add_option("--min-improvement", args->min_improvement,
                  "adaptive: a level is kept if it lowers the validation error by this fraction "
                  "(" +
                      DefaultText(sa.min_improvement, ca.min_improvement) + ")")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--residual-threshold", args->residual,
                  "adaptive: a node of a finer level needs a residual above this multiple of "
                  "the mean error (residual criterion; 0: off; " +
                      DefaultText(sa.residual_threshold, ca.residual_threshold) + ")")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--coefficients-per-point", args->budget,
                  "adaptive: at most this many displacement coefficients per fitted point (0: "
                  "no limit; " +
                      DefaultText(sa.max_coefficients_per_point, ca.max_coefficients_per_point) +
                      ")")
      ->check(CLI::Range(0.0, 1e4));
  cmd->add_option("--consistency", args->consistency,
                  "adaptive: weight of every chart's agreement with the fitted displacement, "
                  "next to the surface error (" +
                      DefaultText(sa.consistency, ca.consistency) + ")")
      ->check(CLI::Range(0.0, 1e3));
  cmd->add_option("--density", args->density,
                  "mba: finest lattice cells per side per sqrt(points in the chart); 0: all "
                  "charts get --levels (" +
                      DefaultText(surface.displacement.density, character.displacement.density) +
                      ")")
      ->check(CLI::Range(0.0, 64.0));
  cmd->add_option("--finest-passes", args->finest_passes,
                  "mba: BA passes at each chart's finest displacement level")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option(
         "--smoothing", args->smoothing,
         "mba: thin-plate weight of each chart's finest displacement level (0: plain "
         "MBA; " +
             DefaultText(surface.displacement.smoothing, character.displacement.smoothing) + ")")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option(
         "--control-fit", args->control_fit,
         "Rounds of fitting the built control mesh's vertices to the data (0: keep "
         "them on the data; " +
             DefaultText(surface.control_fit_iterations, character.control_fit_iterations) +
             "; a --control-mesh is always used as is; characters: on parts without hard "
             "creases only)")
      ->check(CLI::Range(0, 16));
  cmd->add_option("--patch-agreement", args->patch_agreement,
                  "Control-vertex fit: weight of the corner patches' agreement with each other "
                  "(makes the fit without per-point optimisation closer, the domain surface "
                  "farther; docs/fitting.md)")
      ->check(CLI::Range(0.0, 1e3))
      ->capture_default_str();
  cmd->add_option(
         "--noisy-ratio", args->noisy_ratio,
         "Control-vertex fit: the data's estimated noise, over its spacing, at which the "
         "fit is regularised in full (--patch-agreement and the tangent damping); less "
         "noisy data slides more freely, over more rounds (0: always in full; " +
             DefaultText(surface.control_fit_noisy_ratio, character.control_fit_noisy_ratio) +
             "; docs/fitting.md, \"Noise-adaptive control fit\")")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--clean-rounds", args->clean_rounds,
                  "Control-vertex fit: rounds on data below the clean noise ratio (an exact "
                  "tessellation); noisy data runs --control-fit rounds, data between the two "
                  "ratios a blend, never fewer than --control-fit (docs/fitting.md)")
      ->check(CLI::Range(0, 100))
      ->capture_default_str();
  cmd->add_flag("--no-cover-boundary", args->no_cover_boundary,
                "Leave the built control mesh's boundary where the control-vertex fit puts it "
                "(default: move its boundary vertices out so that the surface covers the data's "
                "boundary, docs/fitting.md)");
  cmd->add_option("--holdout", args->holdout,
                  "Surfaces: fraction of points held out to measure error (a character fits "
                  "every vertex)")
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  AddThreadsOption(cmd, &args->threads);
  cmd->add_option("--control-ratio", args->control_ratio,
                  "Characters: control vertices per welded mesh vertex")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--shading-shape", args->shading_shape,
                  "Characters: the surface the fit follows between the source's vertices is "
                  "the Phong tessellation of its shading normals with this shape factor (0: "
                  "the flat triangles; auto: per part, the one of 0, 0.25, 0.5 and 0.75 whose "
                  "surface's normals come closest to the shading normals): the samples and the "
                  "control vertices lie on it; hard edges and flat-shaded triangles stay flat. "
                  "Where auto takes 0, the part's sharp edges shaded smooth are creases too; a "
                  "number given keeps them rounded (docs/characters.md, \"Folds of a "
                  "flat-shaded part\")")
      ->check([](const std::string& v) -> std::string {
        if (v == "auto") return "";
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(x >= 0.0 && x <= 1.0)) {
          return "'auto' or a number in [0, 1], not '" + v + "'";
        }
        return "";
      })
      ->capture_default_str();
  cmd->add_option("--low-poly-crease-angle", args->low_poly_crease_angle,
                  "Characters: a low-poly part (its control mesh at its own resolution or "
                  "finer) is also fitted with its hard edges from this dihedral angle on "
                  "(radians) as creases, and that fit is kept where it is clearly closer (0: "
                  "off; docs/characters.md)")
      ->check([](const std::string& v) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(x >= 0.0 && x < 1.5)) {
          return "a number in [0, 1.5) (radians), not '" + v + "'";
        }
        return "";
      })
      ->capture_default_str();
  cmd->add_option("--shading-max-move", args->shading_max_move,
                  "Characters: the most that surface departs from the flat triangles at one "
                  "edge, as a fraction of the part's bounding-box diagonal (0: no limit)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--crease-smoothing", args->crease_smoothing,
                  "Characters: thin-plate weight of the levels of a part whose control mesh keeps "
                  "its creases, or whose sharp edges are all shaded smooth (docs/characters.md, "
                  "\"Ripples between the samples\")")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--vertex-weight", args->vertex_weight,
                  "Characters: weight of each source vertex against one sample in those parts' "
                  "displacement fit (the bound export's error)")
      ->check(CLI::Range(1e-3, 1e6))
      ->capture_default_str();
  cmd->add_flag("--creases-ignore-shading", args->creases_ignore_shading,
                "Characters: every edge sharper than the crease angle is a crease, even where the "
                "source shades it smooth (by default such an edge is rounded as its renderer "
                "draws it on a part whose shading surface is curved or given by --shading-shape; "
                "docs/characters.md, \"Smooth-shaded parts follow their shading\")");
  cmd->add_flag("--creases-closed", args->creases_closed,
                "Characters: keep hard creases closed (rounded by the smooth surface, with support "
                "rows beside closed loops) instead of cutting the control mesh open along them "
                "(docs/characters.md, \"Hard edges cut open\")");
  cmd->add_option("--crease-support", args->crease_support,
                  "Characters: the control vertices beside a closed crease loop (a cap's rim) "
                  "move towards it, keeping this fraction of their distance, so the rim comes "
                  "out clean (1: off; docs/characters.md, \"Support rows beside crease loops\")")
      ->check(CLI::Range(0.01, 1.0))
      ->capture_default_str();
  cmd->add_option("--input-quads", args->input_quads,
                  "Characters: a part modelled in quads gets its own quads back as its control "
                  "mesh (edge loops added where they are long) where they are as regular as the "
                  "remesh and number 1 to this many times its vertices (0: off; "
                  "docs/characters.md, \"The input's own quads\")")
      ->check(CLI::Validator(
          [](std::string& value) {
            double r = -1.0;
            try {
              r = std::stod(value);
            } catch (...) {
            }
            return r == 0.0 || (r >= 1.0 && r <= 1e6) ? std::string()
                                                      : std::string("must be 0 or in [1, 1e6]");
          },
          "0|R>=1"))
      ->capture_default_str();
  cmd->add_option("--surface-gap", args->surface_gap,
                  "Characters: where the fitted surface is farther than this fraction of a "
                  "part's diagonal from the source, the source's nearest points join the data "
                  "and the part is fitted again, once, kept unless its Hausdorff distance is "
                  "larger (0: off; docs/characters.md, \"Where the surface leaves the source\")")
      ->check(CLI::Range(0.0, 0.999))
      ->capture_default_str();
  cmd->add_option("--check-points", args->check_points,
                  "Characters: check points on a low-poly part's triangles, this many per area "
                  "of its samples' spacing squared, never fitted: the displacement levels after "
                  "the last one that brought them 1% closer are dropped (0: none; "
                  "docs/characters.md, \"Levels checked between the samples\")")
      ->check(CLI::Range(0.0, 64.0))
      ->capture_default_str();
  cmd->add_flag("--no-check-shading", args->no_check_shading,
                "Characters: the check points do not carry the source's shading normals (by "
                "default, where a part has them, the trailing displacement levels that turn the "
                "surface's normals away from them are dropped, and a denser part gets check "
                "points for that alone; docs/characters.md, \"Levels checked by the shading\")");
  cmd->add_option("--skin-smoothing", args->skin_smoothing,
                  "Characters: steps that smooth the control vertices' skin weights over the "
                  "control mesh, each half way to the neighbours' mean, so that weights painted "
                  "to change across one edge do not ripple the posed surface (0: the weights as "
                  "transferred from the source; docs/characters.md, \"Skin weights smoothed on "
                  "the control mesh\")")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_flag("--refit", args->refit,
                "Characters: fit again even if the glTF carries an embedded Dermis surface");
  cmd->add_option("--report", args->report, "Write a JSON report of errors and timings");
  AddQuietFlag(cmd, &args->quiet);
  SetRunWithOutputs(
      cmd, run, kFitCommand,
      [args] {
        return std::vector<std::string>{args->output, args->report};
      },
      [args] { return RunFit(*args); },
      [args, cmd] {
        args->surface_only.clear();
        args->character_only.clear();
        args->automatic_only.clear();
        for (const char* name : {"--control-vertices", "--control-mesh", "--holdout"}) {
          if (cmd->count(name) > 0) args->surface_only.push_back(name);
        }
        for (const char* name :
             {"--control-ratio", "--shading-shape", "--shading-max-move", "--crease-smoothing",
              "--vertex-weight", "--crease-support", "--input-quads", "--low-poly-crease-angle",
              "--surface-gap", "--check-points", "--skin-smoothing"}) {
          if (cmd->count(name) > 0) args->character_only.push_back(name);
        }
        if (args->refit) args->character_only.push_back("--refit");  // --refit=false is fine
        if (args->creases_ignore_shading) {
          args->character_only.push_back("--creases-ignore-shading");
        }
        if (args->creases_closed) args->character_only.push_back("--creases-closed");
        if (args->no_check_shading) args->character_only.push_back("--no-check-shading");
        for (const char* name : {"--control-vertices", "--control-fit", "--patch-agreement",
                                 "--noisy-ratio", "--clean-rounds"}) {
          if (cmd->count(name) > 0) args->automatic_only.push_back(name);
        }
        // --no-cover-boundary=false asks for nothing.
        if (args->no_cover_boundary) args->automatic_only.push_back("--no-cover-boundary");
      });
}

}  // namespace dermis::cli
