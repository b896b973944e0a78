// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The automatic control mesh: a quad remesh of a dense triangle mesh at a target vertex
/// count (adaptive isotropic remeshing, Blossom-Quad pairing, one Catmull-Clark split,
/// relaxation on the surface). docs/fitting.md, "Control mesh".
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"
#include "dermis/offline/build/isotropic_remesh.h"
#include "dermis/offline/build/quad_pairing.h"
#include "dermis/offline/build/quad_relax.h"
#include "dermis/offline/build/sizing_field.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// Options of QuadRemesh().
struct QuadRemeshOptions {
  int target_vertices = 540;  ///< Vertices of the quad mesh.
  /// The count is accepted within max(tolerance x target, 4) of the target.
  double tolerance = 0.01;
  /// If positive, a hard upper bound on the count (the target is lowered to it). A mesh too
  /// small to remesh below it (a closed component needs at least a tetrahedron's split) stays
  /// above; QuadRemeshReport::vertices tells.
  int max_vertices = 0;
  /// If positive: the count needed, not a count asked for. The target is only a start, and
  /// grows by `growth` (at most max_growth_steps times, max_vertices ignored) until the
  /// isotropic triangle mesh and the input are within this many local target edge lengths of
  /// each other, both ways (a leg, ear or tail the mesh lost is many edge lengths away; a
  /// rounded crease a fraction of one). The count the sizing's max_turn forces is not lowered.
  double max_deviation = 0.0;
  double growth = 1.4;
  int max_growth_steps = 8;
  SizingOptions sizing;
  IsotropicRemeshOptions isotropic;
  QuadPairingOptions pairing;
  QuadRelaxOptions relax;
  /// Seed: the input simplified (meshoptimizer) to about seed_factor x the triangle mesh's
  /// vertex count, at least min_seed_triangles triangles (never more than the input).
  double seed_factor = 6.0;
  int min_seed_triangles = 2000;
  /// Creases (crease_chains.h): interior edges whose dihedral angle is at least this (degrees;
  /// 0: none) are kept as control edges the way boundaries are (docs/fitting.md, "Creases").
  /// The seed is then the input itself, so every crease edge starts as an edge.
  double crease_angle_deg = 0.0;
  /// A crease vertex where its chain turns by more than this (degrees) is a fixed corner.
  double corner_turn_deg = 80.0;
  /// Edges of the input that are never creases, whatever their dihedral angle: pairs of vertex
  /// indices into the positions given to QuadRemesh() (either order; BuildControlMesh() takes
  /// them in its input mesh's indices and renumbers them through its weld). A low-poly
  /// character shaded smooth across an edge (the same normals on both sides) means the surface
  /// round there; its facets' kinks are how few triangles approximate it (docs/characters.md,
  /// "Smooth-shaded parts follow their shading").
  std::vector<std::array<std::uint32_t, 2>> smooth_edges;
  /// The input's own quads (docs/fitting.md, "The input's own quads"): a mesh modelled in
  /// quads and exported as triangles pairs back into them. The paired input (crease edges never
  /// a diagonal; leftover triangles made three quads each, edge loops inserted, see
  /// input_quads_edge_factor) replaces the remesh where its share of valence-4 interior
  /// vertices is at least the remesh's, its largest valence at most the remesh's, and its
  /// vertex count at least the remesh's and at most this many times it: the modeller's edge
  /// loops, every input vertex a control vertex. Below 1 (the default: a surface's fit asks
  /// for a count): never; characters set it (CharacterFitOptions::input_quads).
  double input_quads_max_ratio = 0.0;
  /// Edge loops are inserted into the input's own quads across every quad strip whose edges are
  /// more than this many times the remesh's local control edge (half the sizing field's
  /// triangle edge there), so that a long limb span gets rings (a forearm twisted by the sweep
  /// keeps its section: CesiumMan's wrist twisted through 360 degrees, smallest radius 0.899
  /// without loops, 0.975 with; docs/characters.md, "The input's own quads"). Where the quads
  /// with these loops have fewer vertices than the remesh (a box-modelled figure: RiggedFigure's
  /// 130 vertices give 414 against the remesh's 1,586), the loops come closer, at the largest
  /// factor down to a tenth of this one that gives at least the remesh's count, so that each
  /// strip is several quads across too ("Coarse input quads"). <= 0: none.
  double input_quads_edge_factor = 3.0;
};

/// Quality of a quad remesh (written to the fit report).
struct QuadRemeshReport {
  int target_vertices = 0;
  int vertices = 0, faces = 0;
  int seed_vertices = 0;      ///< Vertices of the simplified seed.
  int triangle_vertices = 0;  ///< Vertices of the isotropic triangle mesh.
  int quads_paired = 0;       ///< Triangle pairs merged into quads.
  int triangles_unpaired = 0;
  int interior_vertices = 0;
  int interior_valence4 = 0;    ///< Interior vertices with 4 quads.
  double valence4_share = 0.0;  ///< interior_valence4 / interior_vertices.
  int max_valence = 0;
  double min_corner_angle_deg = 0.0, max_corner_angle_deg = 0.0;
  /// Share of quad corners between 60 and 120 degrees.
  double corners_60_120_share = 0.0;
  int components = 0;      ///< Of the input and of the result (they are equal).
  int boundary_loops = 0;  ///< Of the input and of the result (they are equal).
  int relax_rejected = 0;  ///< Relaxation moves undone (they would have turned a face over).
  /// With max_deviation: the target reached by growth, and the triangle mesh's deviation
  /// (in local target edge lengths) there.
  int grown_target = 0;
  double deviation = 0.0;
  /// The result is the input's own quads (QuadRemeshOptions::input_quads_max_ratio); the
  /// remesh it replaced had remesh_vertices vertices (0 when it was kept).
  bool input_quads = false;
  int remesh_vertices = 0;
  /// Creases of the input (crease_angle_deg > 0): its crease edges and chains (closed ones
  /// among them), the input's crease edges that the control mesh keeps (each one's midpoint
  /// within a quarter of the local target edge length of a control crease edge), and the
  /// control edges on creases.
  int crease_edges = 0, crease_chains = 0, crease_closed_chains = 0;
  int crease_edges_kept = 0;
  int control_crease_edges = 0;
};

/// Remeshes a dense triangle mesh (welded positions, counter-clockwise triangles without
/// repeated indices; manifold and consistently oriented) into an all-quad mesh of about
/// `options.target_vertices` vertices, on the input surface:
///  1. seed: meshoptimizer's simplification (borders locked), checked to keep the components
///     and boundary loops (else a larger seed, at worst the input);
///  2. sizing field on the seed (curvature, short loops, graded; sizing_field.h) scaled so the
///     final count meets the target;
///  3. adaptive isotropic remeshing with back-projection (isotropic_remesh.h), its scale
///     corrected from the count actually reached, then a few single splits or collapses;
///  4. triangles paired into quads by maximum weight matching (quad_pairing.h);
///  5. one Catmull-Clark style split (quads into 4, unpaired triangles into 3), new points
///     projected onto the surface, then relaxation (quad_relax.h);
///  6. the input's own quads instead, where they pair back and are as regular and about as
///     dense (QuadRemeshOptions::input_quads_max_ratio).
/// The result passes ValidatePolygonMesh() and keeps the input's components and boundary loops.
/// Fails with a message naming `name` for non-manifold or unusable input, or when the result
/// would not keep them. Deterministic.
Status QuadRemesh(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
                  const std::string& name, const QuadRemeshOptions& options, PolygonMesh* out,
                  QuadRemeshReport* report = nullptr);

/// Fills the quality fields of `report` (vertices, faces, valences, corner angles) for a quad
/// mesh.
void MeasureQuadMesh(const PolygonMesh& quads, QuadRemeshReport* report);

}  // namespace dermis
