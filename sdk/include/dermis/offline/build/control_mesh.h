// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Automatic all-quad control mesh from a dense triangle mesh (paper section 4,
/// "Control mesh").
#pragma once

#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/offline/build/quad_remesh.h"
#include "dermis/offline/geometry/polygon_mesh.h"

namespace dermis {

/// How BuildControlMesh() makes the control mesh.
enum class ControlMeshMethod {
  /// Quad remesh (quad_remesh.h): isotropic triangles paired into quads and split once;
  /// mostly regular, well-shaped quads. The default.
  kRemesh,
  /// The previous method: meshoptimizer's simplification, valence flips, and every triangle
  /// split into three quads. Used when the remesh fails (the report says why).
  kSimplify,
};

/// Options of BuildControlMesh().
struct ControlMeshOptions {
  /// Wanted number of control (quad) vertices. The result is the closest count found.
  int target_vertices = 540;
  /// True: a target above the full split (every usable triangle split into three quads) is
  /// lowered to it; false: such a target is an error.
  bool clamp_to_full_split = false;
  ControlMeshMethod method = ControlMeshMethod::kRemesh;
  /// Options of the remesh (its target_vertices is ignored: target_vertices above is used).
  QuadRemeshOptions remesh;
};

/// What BuildControlMesh() did.
struct ControlMeshInfo {
  int welded_vertices = 0;       ///< Vertices merged because they had identical positions.
  int degenerate_triangles = 0;  ///< Input triangles dropped as degenerate after welding.
  int simplified_vertices = 0;   ///< Vertices of the simplified triangle mesh.
  int simplified_triangles = 0;
  int edge_flips = 0;   ///< Flips that evened out the valences.
  int max_valence = 0;  ///< Largest valence of the resulting quad mesh.
  /// "remesh" or "simplify": the method that made the mesh.
  std::string method;
  /// Why the remesh was not used when it was asked for (empty otherwise).
  std::string fallback;
  /// Quality of the result (counts, valence-4 share, corner angles; the remesh's own figures
  /// when it made the mesh).
  QuadRemeshReport quality;
  /// Closed crease loops given support rows, and the control vertices moved towards them
  /// (CharacterFitOptions::crease_support; 0 where none were placed).
  int crease_support_loops = 0;
  int crease_support_vertices = 0;
  /// Control edges cut open along hard creases and the vertices the cut added
  /// (CharacterFitOptions::cut_creases; 0 where nothing was cut).
  int crease_cut_edges = 0;
  int crease_cut_vertices = 0;
  /// Rounds of the control-vertex fit its vertices went through (characters: the parts without
  /// hard creases, CharacterFitOptions::fit; FitReport::control_fit_rounds for a surface).
  int control_fit_rounds = 0;
  /// Characters: the shape factor of the shading surface the part followed
  /// (CharacterFitOptions::shading_shape, chosen per part by default; 0: the flat triangles),
  /// and the mean angle (degrees, by area) of that surface's own normals and of the flat
  /// triangles' from the source's shading normals (ShadingSurface::NormalDeviation; 0 for a
  /// part without normals).
  double shading_shape = 0.0;
  double shading_deviation_deg = 0.0;
  double flat_deviation_deg = 0.0;
  /// Characters: the dihedral angle (degrees) from which the source's hard edges were creases
  /// of this control mesh (CharacterFitOptions::crease_angle, or low_poly_crease_angle where
  /// that fit was kept; 0 where the control mesh keeps no creases by design).
  double crease_angle_deg = 0.0;
  /// Characters: the source points added where the fitted surface left the source, before the
  /// part was fitted again (CharacterFitOptions::surface_gap; 0: none found, the refit not kept,
  /// or not checked).
  int surface_gap_points = 0;
  /// Characters: the check points between the samples (CharacterFitOptions::check_points; 0:
  /// none), and the displacement levels their rule dropped.
  int check_points = 0;
  int check_levels_dropped = 0;
  /// Characters: the displacement levels the check points' shading rule dropped after that
  /// (CharacterFitOptions::check_shading), and the mean angle (degrees) between the surface's
  /// normals and the source's shading normals at the check points with 0, 1, ... of the levels
  /// the distance rule kept (empty: not measured; AdaptiveDisplacementReport::check_angle_deg).
  int shading_levels_dropped = 0;
  std::vector<double> check_angle_deg;
};

/// Builds a control mesh from a polygon mesh (faces are fan-triangulated): welds vertices
/// with identical positions (meshoptimizer's remap), drops degenerate triangles, then
/// - kRemesh (default): QuadRemesh() of the welded triangles at `target_vertices`; if it fails
///   (non-manifold input, a result that would not keep the components or loops), the message
///   goes to `info->fallback` and kSimplify is used instead;
/// - kSimplify: simplifies to the triangle count whose one-split quad mesh has about
///   `target_vertices` vertices (meshopt_simplify, boundaries may slide along themselves but
///   stay open), evens out valences by edge flips, splits every triangle into three quads and
///   moves the new edge and face points onto the input surface.
/// Boundaries and separate components are kept. The result is an all-quad mesh that passes
/// ValidatePolygonMesh(). Fails with a message naming the mesh if the mesh has too few
/// vertices or the target cannot be met.
Status BuildControlMesh(const PolygonMesh& mesh, const ControlMeshOptions& options,
                        PolygonMesh* control, ControlMeshInfo* info = nullptr);

}  // namespace dermis
