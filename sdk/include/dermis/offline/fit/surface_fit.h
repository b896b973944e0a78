// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The whole fit of paper section 4: a dense mesh or point cloud to a control mesh, its
/// manifold domain and per-chart multilevel B-spline displacements, with error metrics
/// (docs/notes/fit.md section 3: E1, held-out E2, two-sided Hausdorff E3).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dermis/core/progress.h"
#include "dermis/core/status.h"
#include "dermis/offline/build/control_mesh.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/fit/control_fit.h"
#include "dermis/offline/fit/displacement_fit.h"
#include "dermis/offline/fit/point_fit.h"
#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/surface/bspline_displacement.h"

namespace dermis {

/// Options of FitSurface().
struct FitOptions {
  /// Wanted control vertices when the control mesh is built from the data.
  int control_vertices = 540;
  /// How the control mesh is built from the data (control_mesh.h), and the remesher's options.
  ControlMeshMethod control_method = ControlMeshMethod::kRemesh;
  QuadRemeshOptions remesh;
  /// True: a control_vertices target above what splitting the whole mesh gives is lowered to
  /// that count; false: it is an error (the CLI's --control-vertices).
  bool clamp_control_vertices = false;
  DomainOptions domain;
  /// Rounds of projection + control-vertex least squares (control_fit.h) applied to a control
  /// mesh built from the data (never to a given one); 0 keeps the simplified positions. Skipped
  /// where the data is too sparse to determine the positions: fewer than
  /// control_fit_min_points_per_vertex points (not held out) per control vertex.
  int control_fit_iterations = 2;
  double control_fit_min_points_per_vertex = 16.0;
  /// The control-vertex fit's options: ControlFitOptions' defaults with the patches' agreement
  /// at 1 (docs/fitting.md, "Noise-adaptive control fit"; scaled with the noise below).
  ControlFitOptions control_fit = [] {
    ControlFitOptions c;
    c.patch_agreement = 1.0;
    return c;
  }();
  /// The control-vertex fit's regularisation follows the data's noise (docs/fitting.md,
  /// "Noise-adaptive control fit"). With a mesh, its noise is estimated
  /// (EstimateVertexNoise's median_ratio: over sampled vertices, the median of a vertex's
  /// leave-one-out distance from a quadric through its two-ring over its mean edge; held-out
  /// vertices count too): at or above control_fit_noisy_ratio (a scan)
  /// the fit is regularised as control_fit says (tangent_damping, patch_agreement) over
  /// control_fit_iterations rounds; at or below control_fit_clean_ratio (an exact
  /// tessellation of a smooth surface, whose residual is the quadric's truncation error) the
  /// vertices slide along the surface with only control_fit.damping and no patch agreement,
  /// over max(control_fit_iterations, control_fit_clean_iterations) rounds; in between,
  /// linearly. control_fit_noisy_ratio <= 0 always regularises in full. The ratio depends on
  /// the resolution as well (a coarse exact tessellation reads noisier than a fine one).
  /// Measured: the bunny scan 0.021, the torus tessellated at level 12 0.0014.
  double control_fit_clean_ratio = 0.003;
  double control_fit_noisy_ratio = 0.01;
  int control_fit_clean_iterations = 6;
  /// After the control-vertex fit's rounds (so only where they ran): move the boundary control
  /// vertices out along the surface, one pass, towards a domain surface whose boundary curve
  /// covers the data mesh's boundary vertices that are not held out (boundary_cover.h;
  /// docs/fitting.md, "Covering the data's boundary"). Nothing changes for data without a
  /// boundary.
  bool cover_boundary = true;
  /// Levels of the displacement functions (max_levels is --levels; threads is ignored).
  DisplacementFitOptions displacement;
  /// Fraction of the points held out of the fit and used only to measure (E2), in [0, 1).
  double holdout = 0.1;
  std::uint64_t holdout_seed = 0x44657266u;
  int threads = 0;  ///< 0: hardware concurrency. Results do not depend on it.
  /// Progress (may be empty): called with the stage ("control mesh", "control-vertex fit",
  /// "projection and optimisation", "displacement functions", "error metrics") and the work
  /// done of the whole fit's, in units of one data point projected once: each stage weighs
  /// what it measured to cost per point (docs/fitting.md, "Progress"). The total is fixed at
  /// the start, so done / total is the fit's fraction; a stage that is skipped is jumped.
  ProgressCallback progress;
  /// Called on a control mesh built from the data (not a given one) before its domain surface
  /// is made; may move its vertices, not change its faces or their count (refused). Empty:
  /// none. FitCharacter sets it on every part with a curved shading surface, moving the
  /// vertices onto it (CharacterFitOptions::shading_shape), and on a crease-keeping control
  /// mesh with closed crease loops, moving the vertices beside them towards them first
  /// (CharacterFitOptions::crease_support); a hook the caller set runs after both. The
  /// report's control-mesh quality is measured before the moves.
  std::function<void(PolygonMesh* control)> place_control_vertices;
  /// Called on a control mesh built from the data before place_control_vertices; may change
  /// its faces (all quads) and add vertices, and fills `seam` with CutAlongCreases()'s marks
  /// (one per vertex: 0 off the cut, 1 inside a crease chain, 2 at a junction or the
  /// boundary; empty: none), which BuildControlSurface() turns into seam charts and operators
  /// and ZeroDisplacementOnSeams() into displacements vanishing on the cut. Empty: none.
  /// FitCharacter sets it on a part whose control mesh keeps hard creases, cutting the mesh open
  /// along them (CharacterFitOptions::cut_creases). With a cut, the control-vertex fit and the
  /// boundary cover do not run (they would move the copies of a cut vertex apart), the
  /// displacement must be adaptive (InvalidInput otherwise), and place_control_vertices must
  /// move coincident copies alike.
  std::function<Status(PolygonMesh* control, std::vector<std::uint8_t>* seam)> cut_control_mesh;
};

/// What to fit.
struct FitInput {
  /// The data points (model units). For a mesh input: the vertices its faces use.
  std::vector<Vec3> points;
  /// The dense mesh over `points` (same vertex order), or null for a point cloud. Needed to
  /// build a control mesh and for the two-sided Hausdorff distance.
  const PolygonMesh* mesh = nullptr;
  /// A given control mesh (used as is), or null to build one from `mesh`.
  const PolygonMesh* control = nullptr;
  /// Input vertices no face used (dropped before the fit), for the report.
  std::int64_t points_dropped = 0;
  /// Per point (same order as `points`), the weight of its squared error in the adaptive
  /// displacement fit's least squares (> 0; a character's vertices weigh more than the samples
  /// between them, CharacterFitOptions::vertex_weight), or empty: every point 1. The other
  /// stages and the errors reported do not use it.
  std::vector<double> weights;
  /// Check points (model units): points on the data's surface between `points`, projected and
  /// optimised as they are but never fitted; with check_distances the adaptive displacement
  /// fit drops the levels after the last one that brought them closer
  /// (AdaptiveDisplacementOptions::check_improvement). A character's low-poly part gets them
  /// between its samples, a denser part with shading normals for the shading rule alone
  /// (CharacterFitOptions::check_points, check_shading). Other displacement methods ignore them.
  std::vector<Vec3> check_points;
  /// Per check point (same order), the source's shading normal there (unit, or a zero vector:
  /// none; another length is refused), or empty. With them the adaptive displacement fit then
  /// drops the trailing levels that turn the surface's normals away from these
  /// (AdaptiveDisplacementOptions::check_shading_tolerance; docs/characters.md, "Levels checked
  /// by the shading").
  std::vector<Vec3> check_normals;
  /// Whether the check points' distances decide levels (the rule above); false: only their
  /// normals do (a denser character part, whose distance rule kept every level).
  bool check_distances = true;
};

/// Distances in the paper's unit: the data scaled so that its bounding box's largest side is 1.
struct FitErrors {
  double mean = 0.0, rms = 0.0, max = 0.0;  ///< E1: |p - D(z_p)| at the fitted parameter.
  double unoptimized_mean = 0.0;  ///< E1 of a fit from the projection alone (paper's "without").
  double closest_mean = 0.0;      ///< Mean true point-to-surface distance of the fitted points.
  double holdout_mean = 0.0, holdout_max = 0.0;  ///< E2: point-to-surface, held-out points.
  bool has_hausdorff = false;  ///< False for a point cloud (no mesh to compare with).
  double hausdorff = 0.0;      ///< E3, two-sided against the input mesh.
  double hausdorff_percent_diagonal = 0.0;
};

/// Wall-clock seconds per stage.
struct FitSeconds {
  double control_mesh = 0.0;  ///< Building the control mesh, domain, patches, control fit.
  double projection_optimization = 0.0;  ///< FitPoints() on the fitted points.
  double displacement = 0.0;             ///< MBA of every chart.
  double total = 0.0;                    ///< The three above plus bookkeeping.
  double metrics = 0.0;                  ///< Error measurement (not part of total).
};

/// The fit's report (written as JSON by `dermis fit --report`).
struct FitReport {
  std::int64_t points = 0;                ///< Data points (after dropping unused vertices).
  std::int64_t points_dropped = 0;        ///< Vertices no face used.
  std::int64_t points_fitted = 0;         ///< Used in the fit.
  std::int64_t points_holdout = 0;        ///< Held out.
  std::int64_t points_outside = 0;        ///< Left every chart in projection (not fitted).
  std::int64_t points_not_converged = 0;  ///< Fitted from their projection only (folds).
  /// Of those, the ones whose parameter became their closest point on the fitted surface
  /// (PlaceLostPoints: closer than the projection's parameter).
  std::int64_t points_not_converged_placed = 0;
  std::int64_t control_vertices = 0, control_faces = 0;
  /// How the control mesh was built and its quality (method "given" for a given one).
  ControlMeshInfo control_mesh;
  std::int64_t control_fit_rounds = 0;  ///< Control-vertex fit rounds done (FitOptions).
  /// The data's noise over its spacing (EstimateVertexNoise's median_ratio; 0 when not
  /// estimated or when no control-vertex fit ran) and the share of the control fit's
  /// regularisation it gave (1: full, FitOptions::control_fit_noisy_ratio).
  double noise_ratio = 0.0;
  double control_fit_regularisation = 1.0;
  /// FitOptions::cover_boundary: the data mesh's boundary vertices (not held out) found beyond
  /// the domain surface's boundary curve before the move, the farthest of them (in the unit of
  /// FitErrors), and the boundary control vertices moved out.
  std::int64_t boundary_points_beyond = 0;
  double boundary_largest_excess = 0.0;
  std::int64_t boundary_vertices_moved = 0;
  std::int64_t coefficients = 0;         ///< Stored displacement coefficients, all levels.
  double coefficients_per_point = 0.0;   ///< coefficients / points.
  std::int64_t finest_coefficients = 0;  ///< Those of each chart's finest level only.
  /// Stored coefficients per level (all charts), level 0 first.
  std::vector<std::int64_t> level_coefficients;
  int max_levels = 0;  ///< Levels of the deepest chart.
  /// The adaptive displacement fit's stopping rule and final level sizes
  /// (DisplacementMethod::kAdaptive; empty otherwise).
  AdaptiveDisplacementReport displacement_fit;
  int threads = 1;
  double scale = 1.0;  ///< Largest side of the data's bounding box (model units).
  FitErrors error;
  FitSeconds seconds;
};

/// A fitted displaced surface.
struct FittedSurface {
  PolygonMesh control_mesh;  ///< As given or as built (all quads).
  ControlSurface surface;    ///< Domain and rest patches.
  std::unique_ptr<BsplineDisplacement> displacement;
  /// One per fitted point, in input order without the held-out points (all of them when
  /// FitOptions::holdout is 0): the surface parameter each point was fitted at.
  std::vector<PointFit> point_fits;
};

/// Runs the fit: control mesh (given or built), projection and optimisation of the fitted
/// points, displacement fitting, then the error metrics. Bad input (no points, non-finite
/// coordinates, no control mesh for a point cloud, too many control vertices) gives an error
/// naming the source.
Status FitSurface(const FitInput& input, const FitOptions& options, FittedSurface* out,
                  FitReport* report);

/// Whether point i is held out (a fixed hash of i and the seed, so the split is reproducible).
bool IsHeldOut(std::size_t i, double fraction, std::uint64_t seed);

}  // namespace dermis
