// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "character_json.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <vector>

#include "dermis/surface/bspline_displacement.h"

namespace dermis::cli {

Json DescribeSurface(const DisplacedSurface& surface) {
  Json j;
  const Index vertices = surface.domain ? surface.domain->num_vertices() : 0;
  j["control_vertices"] = vertices;
  j["charts"] = vertices;  // one chart per control vertex
  j["faces"] = surface.domain ? surface.domain->num_faces() : 0;
  if (surface.displacement) {
    const BsplineDisplacementData& data = surface.displacement->data();
    Json d;
    d["storage"] = data.form == BsplineLevelForm::kAdditive ? "sparse levels" : "merged lattices";
    d["max_levels"] = surface.displacement->max_levels();
    d["coefficients"] = surface.displacement->num_coefficients();
    // Stored coefficients per level over all charts (merged lattices: each level's lattice).
    std::vector<std::int64_t> per_level;
    for (int k = 0; k < surface.displacement->max_levels(); ++k) {
      per_level.push_back(surface.displacement->level_coefficients(k));
    }
    d["level_coefficients"] = per_level;
    if (surface.data_points > 0) {
      d["data_points"] = surface.data_points;
      d["coefficients_per_point"] = static_cast<double>(surface.displacement->num_coefficients()) /
                                    static_cast<double>(surface.data_points);
    } else {
      d["data_points"] = nullptr;
      d["coefficients_per_point"] = nullptr;
    }
    std::vector<std::int64_t> charts_by_levels(
        static_cast<std::size_t>(surface.displacement->max_levels()) + 1, 0);
    for (const std::uint8_t levels : data.num_levels)
      if (levels < charts_by_levels.size()) ++charts_by_levels[levels];
    d["charts_by_levels"] = charts_by_levels;  // index = levels, value = charts
    j["displacement"] = d;
  } else {
    j["displacement"] = nullptr;
  }
  return j;
}

Json DescribeCharacter(const Character& ch) {
  Json j;
  std::int64_t vertices = 0, bound = 0;
  for (const auto& mesh : ch.bindings) {
    for (const auto& prim : mesh) {
      for (const VertexBinding& b : prim) {
        ++vertices;
        if (b.part != kInvalidIndex) ++bound;
      }
    }
  }
  j["vertices"] = vertices;
  j["vertices_bound"] = bound;
  Json parts = Json::array();
  for (const CharacterPart& part : ch.parts) {
    Json p;
    p["mesh"] = part.mesh;
    p["component"] = part.component;
    p["skin"] = part.skin == kInvalidIndex ? Json() : Json(part.skin);
    p["surface"] = DescribeSurface(part.surface);
    const PartFitSummary& f = part.fit;
    Json fit;
    fit["points"] = f.points;
    fit["triangles"] = f.triangles;
    fit["points_outside"] = f.points_outside;
    fit["points_not_converged"] = f.points_not_converged;
    // PartFitSummary holds paper units (the part's largest side is 1): report model units
    // and percent of that side.
    fit["scale"] = f.scale;
    fit["unit"] = "model units";
    fit["e1_mean"] = f.e1_mean * f.scale;
    fit["e1_max"] = f.e1_max * f.scale;
    fit["hausdorff"] = f.hausdorff * f.scale;
    fit["e1_mean_percent"] = 100.0 * f.e1_mean;
    fit["e1_max_percent"] = 100.0 * f.e1_max;
    fit["hausdorff_percent"] = 100.0 * f.hausdorff;
    fit["coefficients"] = f.coefficients;
    // Per data point fitted (the welded vertices and the samples on the triangles, as the
    // part's surface records them; older files: per welded vertex).
    const std::int64_t fitted = part.surface.data_points > 0 ? part.surface.data_points : f.points;
    fit["data_points"] = fitted;
    fit["coefficients_per_point"] =
        fitted > 0 ? Json(static_cast<double>(f.coefficients) / static_cast<double>(fitted))
                   : Json();
    fit["levels"] = f.levels;
    p["fit"] = fit;
    parts.push_back(p);
  }
  j["parts"] = parts;
  Json unfitted = Json::array();
  for (const UnfittedPart& u : ch.unfitted) {
    Json q;
    q["mesh"] = u.mesh;
    q["component"] = u.component;
    q["vertices"] = u.vertices;
    q["triangles"] = u.triangles;
    q["reason"] = u.reason;
    unfitted.push_back(q);
  }
  j["unfitted"] = unfitted;
  return j;
}

}  // namespace dermis::cli
