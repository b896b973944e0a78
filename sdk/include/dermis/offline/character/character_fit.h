// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Fitting a skinned (or static) character: every mesh is welded by position, split
/// into connected components, and each component becomes a displaced surface (paper section 4,
/// FitSurface()); control vertices get skin weights from the dense mesh and every original
/// vertex is bound to the surface by its fitted parameter.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "dermis/offline/fit/surface_fit.h"
#include "dermis/runtime/character.h"

namespace dermis {

/// Options of FitCharacter().
struct CharacterFitOptions {
  /// Settings of each component's fit. `holdout` is ignored (every vertex is fitted, so each
  /// one gets a parameter); `control_vertices` is ignored when vertex_ratio > 0.
  /// A character's mesh is exact (a game mesh, not a noisy scan) and its vertices are the
  /// bound export's vertices, so its displacements follow the fitted points closely: adaptive
  /// levels with lower node weights, no validation split (levels stop when they lower the
  /// fitted points' error by less than 1%), nodes refined where the error is above the mean,
  /// at most 3 coefficients per fitted point (docs/fitting.md, "Characters"); a scan's light
  /// smoothing (1e-3), except on a control mesh that keeps the creases (crease_smoothing). The
  /// control-vertex fit (2 rounds) runs on the parts without hard creases only, fully
  /// regularised (patch agreement and tangent damping whatever the noise estimate says: a
  /// low-poly part's facets read as noise, and it has few points per control vertex, so it runs
  /// from 2 fitted points per control vertex, vertices and samples together). The domain surface
  /// then follows such a part between the remesh's vertices (CesiumMan: Hausdorff 0.42 % ->
  /// 0.33 %, curvature ratio 1.96 -> 1.76, clean fingertips and head rims). A part with hard
  /// creases keeps its control vertices where the remesh put them: the fit knows nothing of
  /// creases and pulled their vertices off them (RiggedSimple 0.41 % -> 0.60 %, the Fox 0.39 %
  /// -> 0.84 %; docs/characters.md, "The control-vertex fit on parts without hard creases").
  FitOptions fit = [] {
    FitOptions f;
    f.control_fit_iterations = 2;
    f.control_fit_min_points_per_vertex = 2.0;
    f.control_fit_noisy_ratio = 0.0;
    f.displacement.method = DisplacementMethod::kAdaptive;
    f.displacement.adaptive.min_node_weight = 0.15;
    f.displacement.adaptive.consistency = 0.1;
    f.displacement.adaptive.smoothing = 1e-3;
    f.displacement.adaptive.validation = 0.0;
    f.displacement.adaptive.residual_threshold = 1.0;
    f.displacement.adaptive.min_improvement = 0.01;
    f.displacement.adaptive.solver_iterations = 30;  // light smoothing converges slower
    // kMba (--displacement mba): plain MBA at density 2.2, no smoothing spline.
    f.displacement.density = 2.2;
    f.displacement.smoothing = 0.0;
    return f;
  }();
  /// Control vertices per component = welded vertices * vertex_ratio, at least
  /// min_control_vertices, and never more than the component's own welded vertices (the
  /// control mesh is a quad remesh of the component, control_mesh.h; a component too small
  /// to remesh below its vertex count gets more, and the report says so).
  double vertex_ratio = 0.25;
  /// Low-poly game meshes (a few hundred vertices) need a control mesh close to their own
  /// resolution: a coarser one puts the smooth surface far inside sharp features (measured on
  /// the Khronos characters in docs/characters.md).
  int min_control_vertices = 300;
  /// The control mesh grows past that count while its remeshed triangle mesh is further than
  /// this many local edge lengths from the component (a lost leg, ear or tail);
  /// QuadRemeshOptions::max_deviation.
  double max_deviation = 1.0;
  /// Every edge of the remeshed triangle mesh turns the normal by at most about this many
  /// radians (SizingOptions::max_turn), whatever the count: a limb keeps enough edges around.
  /// On a low-poly part (its control mesh at its own resolution or finer) a sliver where the
  /// part curves also gets its samples a turn of max_turn / (2 samples_per_control_edge)
  /// apart, as close as the control edges this makes there (docs/characters.md, "Samples as
  /// close as the control edges along curved slivers"). <= 0: no bound, and no such samples.
  double max_turn = 1.0;
  /// Data points inside the triangles, about the control mesh's mean edge (sqrt(area / control
  /// vertices), the count asked for) divided by this apart: a barycentric grid, or rows along a
  /// sliver (less than a quarter as high as long; closer on a low-poly part's curved slivers,
  /// max_turn), so the surface follows the source between its vertices. 0: vertices only; at
  /// most 64 (FitCharacter refuses more).
  double samples_per_control_edge = 2.0;
  /// Points along the source's edges are spaced like the grid inside its triangles; along its
  /// boundaries and creases (a dihedral angle above crease_angle, radians) crease_samples times
  /// closer (in [0, 64]; below 1 as 1), so the displacement follows the crease the smooth domain
  /// surface rounds.
  double crease_angle = 0.5;
  double crease_samples = 2.0;
  /// Inside a triangle large enough for its own grid of samples, rows of points parallel to
  /// each of its crease and boundary edges fill the gap between the edge and the grid, so
  /// the samples are crease_samples times as dense across a crease as along the grid (the
  /// finest displacement levels otherwise overshoot the crease in that gap).
  bool crease_rows = true;
  /// Each part follows the surface its source's shading normals describe (ShadingSurface:
  /// Phong tessellation, Boubekeur and Alexa 2008, with this shape factor) rather than its flat
  /// triangles: the samples between the vertices lie on it, and the control vertices are moved
  /// onto it from the triangles where the control mesh put them. A smooth-shaded low-poly mesh
  /// is drawn smooth; samples and control vertices on its facets ask the surface for the
  /// facets' kinks, which the domain surface and the displacement can only follow with ripples
  /// (docs/characters.md, "Smooth-shaded parts follow their shading"). Hard edges (normals that
  /// differ across them), boundaries, flat-shaded triangles and primitives without normals stay
  /// straight and flat. The vertices are fitted as they are. 0.5 puts the middle of an edge
  /// whose normals turn evenly on the circle through its ends (to first order; Boubekeur and
  /// Alexa's 0.75 bulges past it); 0: the flat triangles. Negative (the default): each part
  /// takes, of 0, 0.25, 0.5 and 0.75, the shape whose surface's own normals come closest to
  /// its shading normals (ShadingSurface::NormalDeviation; the smaller on a tie): normals
  /// averaged across the bends of long flat facets (a box-modelled figure shaded smooth) make
  /// Phong's surface bumpier than the facets, normals of a round limb make it rounder. Where
  /// that choice is the flat triangles, the part's sharp edges shaded smooth are creases too
  /// (creases_follow_shading). The fit report gives the shape taken
  /// (ControlMeshInfo::shading_shape).
  double shading_shape = -1.0;
  /// The most the shading surface departs from the flat triangles at one edge (its term at the
  /// edge's midpoint), as a fraction of the part's bounding-box diagonal, a third of the 0.75 %
  /// the issue allows: long triangles whose normals lean (RiggedFigure's limbs, 14 % of its
  /// diagonal) would otherwise bulge past the source's silhouette (0.89 % uncapped), while a
  /// limb a few percent of the diagonal across keeps its full rounding. 0: no limit.
  double shading_max_move = 0.0025;
  /// The remeshed control mesh keeps the source's creases (dihedral above crease_angle) as
  /// control edges, as it keeps boundaries (QuadRemeshOptions::crease_angle_deg).
  bool remesh_creases = true;
  /// With remesh_creases: a sharp edge (dihedral above crease_angle) that the source shades
  /// smooth (its two
  /// triangles carry the same NORMAL at each of its ends) is not a crease: neither a control
  /// edge (QuadRemeshOptions::smooth_edges) nor an edge with crease_samples; a part whose sharp
  /// edges are all so gets crease_smoothing and vertex_weight, so its facets' kinks
  /// are rounded, as its renderer draws them, instead of followed with ripples. A hard edge
  /// (normals split across it) and a primitive without normals keep their creases
  /// (docs/characters.md, "Smooth-shaded parts follow their shading"). Only on a part whose
  /// shading surface is curved, or was given (shading_shape >= 0): a part that takes the flat
  /// triangles by the automatic choice follows them, and their sharp edges are its creases
  /// whatever their shading (docs/characters.md, "Folds of a flat-shaded part"). false: every
  /// sharp edge is a crease (before 2026-12-04's seventh session).
  bool creases_follow_shading = true;
  /// The displacement levels' thin-plate weight (AdaptiveDisplacementOptions::smoothing) on a
  /// control mesh that keeps creases, for a part that has some, and on a part whose sharp edges
  /// are all shaded smooth and rounded (creases_follow_shading); < 0: fit.displacement's. There
  /// the creases lie on control edges and the displacement need not carry them, and with the
  /// light smoothing of fit.displacement the finest levels ripple between the samples (a few
  /// per control edge), which the shading shows though no distance does (docs/characters.md,
  /// "Ripples between the samples"). The plain remesh (compare_without_creases) keeps
  /// fit.displacement's: its displacement carries the creases.
  double crease_smoothing = 1e-2;
  /// Check points on a low-poly part (its control mesh at its own resolution or finer, the
  /// test max_turn's closer samples use), and with check_shading on a denser part that has
  /// shading normals (for the shading rule alone): this many per area of the samples' spacing
  /// squared,
  /// spread at random but reproducible places over its triangles on the shading surface, never
  /// fitted (FitInput::check_points). The displacement fit drops the levels after the last one
  /// that brought them 1 % closer, where the levels kept bring them closer than the domain
  /// surface alone (AdaptiveDisplacementOptions::check_improvement): the finest levels follow
  /// the samples' rows and add nothing between them (docs/characters.md, "Levels checked
  /// between the samples"; the Fox: 29,687 -> 21,018 coefficients at the same distances and
  /// normals). At most as many as the part's fitted points (vertices and samples): the rule
  /// compares means, and more would only cost time. In [0, 64]; 0: none, every level the
  /// fitted points' rule keeps.
  double check_points = 1.0;
  /// Where the part has shading normals, the check points carry them too
  /// (FitInput::check_normals): after their distance rule the displacement fit drops the
  /// trailing levels that turn the surface's normals away from the source's shading there
  /// (AdaptiveDisplacementOptions::check_shading_tolerance; docs/characters.md, "Levels
  /// checked by the shading"). false: the distance rule alone.
  bool check_shading = true;
  /// Umbrella steps (each moving a vertex's weights half way to its neighbours' mean) that
  /// smooth the control vertices' skin weights over the control mesh after their transfer from
  /// the source (docs/characters.md, "Skin weights smoothed on the control mesh"). Painted
  /// weights change across single edges, and the domain surface, which interpolates its posed
  /// control vertices, turned such kinks into ripples (CesiumMan's flanks in its walk). The
  /// cost: posed, the bound vertices leave the source's own skinning where its weights were
  /// steep (CesiumMan's armpits, LBS at 0.5 s: up to 0.023 model units, 1.3 % of the
  /// diagonal). In [0, 64]; 0: the transferred weights as they are (before
  /// 2026-12-08).
  int skin_smoothing = 2;
  /// In the same fits (a control mesh that keeps creases, or a part whose sharp edges are all
  /// shaded smooth) and when there are samples between the vertices, the weight of each source
  /// vertex against one sample in the displacement levels' least squares (FitInput::weights):
  /// the vertices are what the bound export reproduces, the samples only hold the surface
  /// between them, and heavier vertices keep the bound export's error where it was under the
  /// lighter smoothing. 8 since the samples lie on the shading surface, which passes through
  /// the vertices (4 before).
  double vertex_weight = 8.0;
  /// On a control mesh that keeps creases: the control vertices beside a closed crease loop (a
  /// cap's rim, a sole's edge; SupportCreaseLoops) are moved towards it, keeping this fraction
  /// of their distance, before the move onto the shading surface, so the smooth domain surface
  /// rounds the crease over a narrower band and the rim comes out clean instead of notched
  /// (docs/characters.md, "Support rows beside crease loops"; RiggedSimple's Hausdorff 0.67 % ->
  /// 0.41 %). Open chains get none: rows beside them rippled RiggedFigure's and the Fox's flat
  /// sides. In (0, 1]; 1: off; anything else is refused by FitCharacter.
  double crease_support = 0.5;
  /// On a control mesh that keeps hard creases: the mesh is cut open along them
  /// (CutAlongCreases), each side a surface with a boundary there, the two boundaries one curve
  /// (the seam patch operators, ComputeSeamPatchFitOperator), so the part keeps its hard edges
  /// as its renderer draws them instead of rounding them with a lip beside each
  /// (docs/characters.md, "Hard edges cut open"). Support rows (crease_support) are not
  /// placed then: there is no rounding for them to narrow. Only with the adaptive displacement
  /// (the default): with fit.displacement's MBA the creases stay closed, with support rows.
  bool cut_creases = true;
  /// A part modelled in quads and exported as triangles gets its own quads back as its control
  /// mesh (QuadRemeshOptions::input_quads_max_ratio): where its triangles pair back into quads
  /// (with edge loops and any leftover triangle made quads) as regular as the remesh, with
  /// between 1 and this many times its vertices. The
  /// domain surface then interpolates the source's own vertices and follows its edge loops, and
  /// the control-vertex fit does not move them (docs/characters.md, "The input's own quads";
  /// CesiumMan: curvature ratio 1.76 -> 1.24, E1 max 1.5e-3 -> 4e-5). 0: off; otherwise >= 1,
  /// anything else is refused by FitCharacter.
  double input_quads = 1.5;
  /// With remesh_creases, also fit each component whose control mesh kept creases on the
  /// remesh without them, and keep the crease-aware fit only where its two-sided Hausdorff
  /// distance is below crease_margin times the other's: creases sharpen low-poly, hard-edged
  /// parts (RiggedSimple, RiggedFigure, the Fox) but their denser control meshes fit organic
  /// parts worse (the demo creature, CesiumMan; docs/characters.md, "Creases or not"). Doubles
  /// the fit time of parts with creases.
  bool compare_without_creases = true;
  double crease_margin = 0.9;
  /// A low-poly part, whose control mesh is at its own resolution or finer (at most
  /// min_control_vertices welded vertices, or vertex_ratio >= 1), is also fitted with its hard
  /// edges (those
  /// not shaded smooth) from this dihedral angle on (radians, in [0, 1.5)) as creases, where
  /// that adds any to crease_angle's, and that fit is kept where it keeps creases and its
  /// two-sided Hausdorff distance is below crease_margin times the other's. Its facets are larger
  /// than the control faces, and its renderer draws every hard edge as a shading step: rounded, a
  /// gentle one shows as a soft band across the facets beside it (the Fox, which has no normals and
  /// so is drawn flat: Hausdorff 0.38 % -> 0.07 %, curvature ratio 1.70 -> 1.17;
  /// docs/characters.md, "Gentle hard edges on low-poly parts"). 0: off. Costs one more fit of such
  /// parts.
  double low_poly_crease_angle = 0.1;
  /// Also fit each component on the simplification's control mesh (ControlMeshMethod::
  /// kSimplify), which keeps the source's crease vertices, and keep that fit where its
  /// two-sided Hausdorff distance is below simplified_margin times the remesh's (box-shaped
  /// parts; docs/characters.md, "Where the distances are"). Doubles the fit time; off since
  /// the remesh keeps creases (remesh_creases), which matches or beats it on every character.
  bool compare_simplified = false;
  double simplified_margin = 0.9;
  /// Once a part's fit is chosen (after the comparisons above), it is checked the other way
  /// round: the fitted surface at 4 x 4 points per control face against the source (its
  /// shading surface); where it is farther than this fraction of the part's bounding-box
  /// diagonal, the source's nearest point is added to the data and the part fitted again, once,
  /// with the same options; the refit is kept unless its two-sided Hausdorff distance is larger.
  /// The fit places the surface at its data's parameters, so a bulge no data point projects onto
  /// (beyond a pointed corner) is seen by none of its errors (docs/characters.md, "Where the
  /// surface leaves the source"; RiggedFigure's Hausdorff 0.38 % -> 0.27 %). 0: off; in [0, 1),
  /// anything else is refused by FitCharacter. Costs one more fit of the parts where it finds
  /// such points (two on a low-poly part whose second fit, low_poly_crease_angle, finds some).
  double surface_gap = 1e-3;
  /// Components with fewer welded vertices are left unfitted ("too small").
  int min_vertices = 8;
  /// Progress (may be empty): called with "mesh M component C: STAGE" (FitOptions::progress's
  /// stages; "..., simplified control mesh" for the compare_simplified fit) and the work done
  /// of the whole character's, in triangles of the source: each component weighs its
  /// triangles, split over its fits by their work units. The total is fixed at the start.
  ProgressCallback progress;
};

/// Totals over the character.
struct CharacterFitReport {
  std::int64_t meshes = 0, components = 0, parts_fitted = 0, parts_unfitted = 0;
  std::int64_t vertices = 0;        ///< Original vertices over all primitives.
  std::int64_t vertices_bound = 0;  ///< Of those, bound to a fitted surface.
  double e1_mean = 0.0;  ///< Mean |p - D(z_p)| over bound original vertices (model units).
  double e1_max = 0.0;
  double seconds = 0.0;
  /// Per fitted part (in Character::parts order): how its control mesh was made, its quality,
  /// and a note when it has more control vertices than the part has welded vertices.
  std::vector<ControlMeshInfo> part_control_meshes;
  std::vector<std::string> part_notes;
};

/// Fits every mesh of `asset` (which must pass ValidateAsset()). The data points of a component
/// are its welded vertices plus samples inside its triangles and along its edges, closer along
/// creases and boundaries (spacing a fraction of the control mesh's edge,
/// CharacterFitOptions::samples_per_control_edge, crease_angle, crease_samples), so the surface
/// follows the source between its vertices; errors (E1) are reported over the vertices. Only
/// triangle primitives (lists, strips, fans) are fitted; points and lines stay as they are. A
/// component that cannot be fitted (too few vertices, degenerate, non-manifold, or a fit error) is
/// recorded in Character::unfitted with the reason and keeps its original geometry.
Status FitCharacter(const Asset& asset, const CharacterFitOptions& options, Character* out,
                    CharacterFitReport* report);

}  // namespace dermis
