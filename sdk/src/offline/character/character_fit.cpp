// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Character fitting: weld each mesh by position, split it into connected components, fit each
// component (paper section 4 via FitSurface), transfer skin weights to the control vertices and
// bind every original vertex to its fitted parameter (paper Eq. 4: the vertex is D(z_p)).
#include "dermis/offline/character/character_fit.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <numeric>
#include <string>

#include "area_samples.h"
#include "check_points.h"
#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/crease_cut.h"
#include "dermis/offline/build/crease_support.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/fit/surface_projection.h"
#include "dermis/offline/geometry/shading_surface.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/surface/surface_evaluator.h"
#include "skin_smoothing.h"
#include "surface_gap_points.h"

namespace dermis {
namespace {

/// A vertex of an original primitive.
struct VertexRef {
  Index primitive;
  Index vertex;
};

std::array<std::uint32_t, 3> PositionKey(const glm::vec3& p) {
  std::array<std::uint32_t, 3> key{};
  for (int c = 0; c < 3; ++c) {
    const float x = p[c] + 0.0f;  // -0 and +0 weld
    std::memcpy(&key[static_cast<std::size_t>(c)], &x, 4);
  }
  return key;
}

Index Find(std::vector<Index>* parent, Index x) {
  while ((*parent)[x] != x) {
    (*parent)[x] = (*parent)[(*parent)[x]];
    x = (*parent)[x];
  }
  return x;
}

/// Reason a component cannot be fitted, or empty.
std::string CheckComponent(const PolygonMesh& mesh, int min_vertices) {
  if (mesh.num_vertices() < min_vertices) {
    return "too small: " + std::to_string(mesh.num_vertices()) + " vertices (at least " +
           std::to_string(min_vertices) + " needed)";
  }
  std::map<std::pair<Index, Index>, int> edges;
  double area = 0.0;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    const Vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]], &c = mesh.positions[v[2]];
    area += 0.5 * glm::length(glm::cross(b - a, c - a));
    for (int k = 0; k < 3; ++k) {
      Index x = v[k], y = v[(k + 1) % 3];
      ++edges[{std::min(x, y), std::max(x, y)}];
    }
  }
  for (const auto& e : edges) {
    if (e.second > 2) {
      return "non-manifold: edge (" + std::to_string(e.first.first) + ", " +
             std::to_string(e.first.second) + ") is shared by " + std::to_string(e.second) +
             " triangles";
    }
  }
  Vec3 lo(mesh.positions[0]), hi(lo);
  for (const Vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double d = glm::length(hi - lo);
  if (!(area > 1e-12 * d * d)) return "degenerate: the triangles have no area";
  return {};
}

/// The parameter of the surface point closest to p, for a vertex the projection lost: start
/// from the control face whose centre sample is nearest, then Gauss-Newton.
VertexBinding ClosestBinding(const DisplacedSurface& s, const std::vector<LocalPatch>& patches,
                             const std::vector<Vec3>& centres, const Vec3& p) {
  Index best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (std::size_t f = 0; f < centres.size(); ++f) {
    const double d = glm::dot(centres[f] - p, centres[f] - p);
    if (d < bd) bd = d, best = static_cast<Index>(f);
  }
  Index face = best;
  Vec2 uv(0.5);
  ClosestPointOnSurface(*s.domain, patches.data(), s.displacement.get(), p, &face, &uv);
  VertexBinding b;
  b.face = face;
  b.u = uv.x;
  b.v = uv.y;
  return b;
}

/// The remesher's own crease test (CreaseChains on a ReferenceSurface, at the remesh options'
/// angles) on `mesh` (a triangle mesh), built once: whether it finds any crease ignoring
/// remesh.smooth_edges (`sharp`), and whether any is left once they are excluded (`hard`; then
/// `chains` holds those, on `ref`, for the support rows). Both false where the mesh cannot be a
/// reference surface (the remesh then falls back and keeps none either).
struct CreaseTest {
  bool sharp = false, hard = false;
  std::size_t hard_edges = 0;  ///< Source edges that are creases (not shaded smooth).
  std::shared_ptr<const ReferenceSurface> ref;
  std::shared_ptr<const CreaseChains> chains;
};
CreaseTest TestCreases(const PolygonMesh& mesh, const QuadRemeshOptions& remesh) {
  std::vector<std::uint32_t> triangles(mesh.face_vertices.begin(), mesh.face_vertices.end());
  auto ref = std::make_shared<ReferenceSurface>();
  CreaseTest t;
  if (!ref->Build(mesh.positions, triangles, "crease test").ok()) return t;
  auto creases = std::make_shared<CreaseChains>();
  creases->Build(*ref, remesh.crease_angle_deg, remesh.corner_turn_deg);
  t.sharp = !creases->edges().empty();
  if (t.sharp) {
    creases->Build(*ref, remesh.crease_angle_deg, remesh.corner_turn_deg, remesh.smooth_edges);
    t.hard = !creases->edges().empty();
    t.hard_edges = creases->edges().size();
  }
  if (t.hard) t.ref = std::move(ref), t.chains = std::move(creases);
  return t;
}

// Points per control-face edge at which a kept fit's surface is checked against the source
// (SurfaceGapPoints): 16 per face, about as many as the fit has data points per face.
constexpr int kSurfaceGapSamplesPerEdge = 4;
// The check points' fixed seed (CheckPoints): the same points on every run.
constexpr std::uint64_t kCheckPointSeed = 0x636865636bull;

/// The length of the bounding box's diagonal of `x` (0 if empty).
double Diagonal(const std::vector<Vec3>& x) {
  if (x.empty()) return 0.0;
  Vec3 lo = x[0], hi = x[0];
  for (const Vec3& p : x) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

double Area(const PolygonMesh& mesh) {
  double area = 0.0;
  for (Index f = 0; f < mesh.num_faces(); ++f) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[f]];
    area += 0.5 * glm::length(glm::cross(mesh.positions[v[1]] - mesh.positions[v[0]],
                                         mesh.positions[v[2]] - mesh.positions[v[0]]));
  }
  return area;
}

/// A mesh welded by exact position over all its primitives (glTF splits vertices at UV and
/// normal seams), numbered by first use.
struct WeldedMesh {
  std::vector<Vec3> positions;
  std::vector<VertexRef> representative;   ///< An original vertex of each welded one.
  std::vector<std::vector<Index>> welded;  ///< [primitive][vertex] -> welded vertex, or none.
  std::vector<std::uint32_t> triangles;    ///< Non-degenerate, in welded vertices.
  /// The primitive's shading normal at each corner of `triangles` (unit), or 0 where the
  /// primitive has none.
  std::vector<Vec3> corner_normals;
};

WeldedMesh WeldMesh(const AssetMesh& mesh) {
  WeldedMesh w;
  std::map<std::array<std::uint32_t, 3>, Index> weld;
  w.welded.resize(mesh.primitives.size());
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const AssetPrimitive& prim = mesh.primitives[p];
    w.welded[p].assign(prim.positions.size(), kInvalidIndex);
    const std::vector<std::uint32_t> tris = PrimitiveTriangles(prim);
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      std::uint32_t tri[3];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = tris[t + static_cast<std::size_t>(k)];
        if (w.welded[p][v] == kInvalidIndex) {
          auto ins =
              weld.emplace(PositionKey(prim.positions[v]), static_cast<Index>(w.positions.size()));
          if (ins.second) {
            w.positions.push_back(Vec3(prim.positions[v]));
            w.representative.push_back({static_cast<Index>(p), static_cast<Index>(v)});
          }
          w.welded[p][v] = ins.first->second;
        }
        tri[k] = static_cast<std::uint32_t>(w.welded[p][v]);
      }
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
      w.triangles.insert(w.triangles.end(), {tri[0], tri[1], tri[2]});
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = tris[t + static_cast<std::size_t>(k)];
        Vec3 n(0.0);
        if (prim.normals.size() == prim.positions.size()) {
          n = Vec3(prim.normals[v]);
          const double l = glm::length(n);
          n = l > 0.0 && std::isfinite(l) ? n / l : Vec3(0.0);
        }
        w.corner_normals.push_back(n);
      }
    }
  }
  return w;
}

/// Connected components of a welded mesh (union-find), numbered by their first triangle.
struct Components {
  std::vector<Index> of_vertex;                     ///< Component of each welded vertex, or none.
  std::vector<std::vector<std::size_t>> triangles;  ///< Offsets into WeldedMesh::triangles.
};

Components SplitComponents(const WeldedMesh& w) {
  std::vector<Index> parent(w.positions.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t t = 0; t < w.triangles.size(); t += 3) {
    for (int k = 1; k < 3; ++k) {
      const Index a = Find(&parent, static_cast<Index>(w.triangles[t])),
                  b = Find(&parent,
                           static_cast<Index>(w.triangles[t + static_cast<std::size_t>(k)]));
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  Components c;
  std::map<Index, Index> component_of_root;
  c.of_vertex.assign(w.positions.size(), kInvalidIndex);
  for (std::size_t t = 0; t < w.triangles.size(); t += 3) {
    const Index root = Find(&parent, static_cast<Index>(w.triangles[t]));
    auto ins = component_of_root.emplace(root, static_cast<Index>(c.triangles.size()));
    if (ins.second) c.triangles.emplace_back();
    c.triangles[static_cast<std::size_t>(ins.first->second)].push_back(t);
  }
  for (std::size_t v = 0; v < w.positions.size(); ++v) {
    auto it = component_of_root.find(Find(&parent, static_cast<Index>(v)));
    if (it != component_of_root.end()) c.of_vertex[v] = it->second;
  }
  return c;
}

/// One component as a dense mesh with local vertex numbers (in welded order): `local` maps
/// welded to local vertices, `global` local to welded.
struct ComponentMesh {
  PolygonMesh dense;
  std::vector<Index> local, global;
  std::vector<Vec3> corner_normals;  ///< 3 per face of `dense` (WeldedMesh::corner_normals).
};

ComponentMesh MakeComponentMesh(const WeldedMesh& w, const Components& components, std::size_t c,
                                const std::string& name) {
  ComponentMesh cm;
  cm.local.assign(w.positions.size(), kInvalidIndex);
  for (std::size_t v = 0; v < w.positions.size(); ++v) {
    if (components.of_vertex[v] == static_cast<Index>(c)) {
      cm.local[v] = static_cast<Index>(cm.global.size());
      cm.global.push_back(static_cast<Index>(v));
    }
  }
  cm.dense.source_name = name;
  for (Index g : cm.global) cm.dense.positions.push_back(w.positions[g]);
  for (std::size_t t : components.triangles[c]) {
    cm.dense.AddFace(
        {cm.local[w.triangles[t]], cm.local[w.triangles[t + 1]], cm.local[w.triangles[t + 2]]});
    cm.corner_normals.insert(cm.corner_normals.end(),
                             w.corner_normals.begin() + static_cast<std::ptrdiff_t>(t),
                             w.corner_normals.begin() + static_cast<std::ptrdiff_t>(t + 3));
  }
  return cm;
}

/// Fits one component's surface (paper section 4): its vertices first (so point_fits[i] is
/// vertex i's), then samples on its triangles; a control-vertex count from the vertex ratio;
/// the simplification's control mesh instead of the remesh where it fits clearly better (then
/// `kept_simplified` says so). Returns an empty string or why the component stays unfitted.
/// `part_progress`, if set, gets the stage and the fraction of the component's work done.
std::string FitComponent(const PolygonMesh& dense, const std::vector<Vec3>& corner_normals,
                         const CharacterFitOptions& options,
                         const std::function<void(const std::string&, double)>& part_progress,
                         FittedSurface* fitted, FitReport* fr, std::string* kept_simplified) {
  std::string reason = CheckComponent(dense, options.min_vertices);
  if (!reason.empty()) return reason;
  FitOptions fo = options.fit;
  fo.holdout = 0.0;
  if (options.vertex_ratio > 0.0) {
    fo.control_vertices =
        std::max(options.min_control_vertices,
                 static_cast<int>(std::lround(options.vertex_ratio * dense.num_vertices())));
  }
  // No more control vertices than the component has vertices (its own resolution), and
  // never more than the full split of its own triangles.
  fo.control_vertices = std::max(8, std::min(fo.control_vertices, dense.num_vertices()));
  fo.remesh.max_vertices = dense.num_vertices();
  // ... unless its thin parts need more: the count grows until the remeshed triangle
  // mesh follows the component within max_deviation of its diagonal.
  fo.remesh.max_deviation = options.max_deviation;
  fo.remesh.sizing.max_turn = options.max_turn;
  // The part follows its shading surface (CharacterFitOptions::shading_shape), and the edges
  // the source shades smooth are neither creases of the control mesh nor sharp edges of the
  // samples (creases_follow_shading).
  // A negative shape factor (the default) takes, of 0 (the flat triangles), 0.25, 0.5 and
  // 0.75, the one whose surface's own normals come closest to the shading normals
  // (ShadingSurface::NormalDeviation; the smaller on a tie, so a part without normals stays
  // flat).
  const double diagonal = Diagonal(dense.positions);
  const double max_move = options.shading_max_move * diagonal;
  ShadingSurface shading;
  shading.Build(dense, corner_normals, 0.0, max_move);
  const double flat_deviation = shading.NormalDeviation();
  double shape = 0.0, deviation = flat_deviation;
  std::vector<double> trials;
  if (options.shading_shape < 0.0) {
    trials = {0.25, 0.5, 0.75};
  } else if (options.shading_shape > 0.0) {
    trials = {options.shading_shape};  // taken whatever it measures
  }
  for (const double trial : trials) {
    ShadingSurface candidate;
    candidate.Build(dense, corner_normals, trial, max_move);
    const double d = candidate.NormalDeviation();
    if (options.shading_shape >= 0.0 || d < deviation) {
      shading = std::move(candidate);
      shape = trial;
      deviation = d;
    }
  }
  // A smooth-shaded sharp edge is rounded only where the shading describes a curved surface:
  // where the automatic choice took the flat triangles (no curved surface's normals come
  // closer to the shading normals), the fit follows the flat triangles, whose sharp edges are
  // then its creases whatever their shading (RiggedFigure's shoulders, elbows, wrists and
  // knees, folds of 30-38 degrees across box limbs: rounded, they dented the faces beside them;
  // docs/characters.md, "Folds of a flat-shaded part"). A shape the caller gave keeps the smooth
  // edges rounded.
  const bool round_smooth_edges = shape > 0.0 || options.shading_shape >= 0.0;
  const std::vector<std::array<std::uint32_t, 2>> no_edges;
  const std::vector<std::array<std::uint32_t, 2>>& smooth_edges =
      options.creases_follow_shading && round_smooth_edges ? shading.smooth_edges() : no_edges;
  // Whether the part turns sharply anywhere (shaded smooth or not), and whether a hard crease
  // is left (the remesher's test, whatever remesh_creases says); `creases` is that where the
  // control mesh keeps them.
  const double crease_angle_deg = options.crease_angle * 180.0 / 3.14159265358979323846;
  CreaseTest part_creases;
  if (options.remesh_creases || fo.control_fit_iterations > 0) {
    QuadRemeshOptions test = fo.remesh;
    test.crease_angle_deg = crease_angle_deg;
    test.smooth_edges = smooth_edges;
    part_creases = TestCreases(dense, test);
  }
  fo.remesh.input_quads_max_ratio = options.input_quads;
  if (options.remesh_creases) {
    fo.remesh.crease_angle_deg = crease_angle_deg;
    fo.remesh.smooth_edges = smooth_edges;
  }
  const CreaseTest creases = options.remesh_creases ? part_creases : CreaseTest();
  // A low-poly part (its control mesh at its own resolution or finer: at most
  // min_control_vertices welded vertices, or vertex_ratio >= 1) whose hard edges from
  // low_poly_crease_angle on add creases is fitted a second time with them (at the end).
  bool low_poly_refit = false;
  const double low = options.low_poly_crease_angle;
  if (low > 0.0 && low < options.crease_angle && options.remesh_creases &&
      fo.control_vertices >= dense.num_vertices() &&
      fo.control_method == ControlMeshMethod::kRemesh) {
    QuadRemeshOptions test = fo.remesh;
    test.crease_angle_deg = low * 180.0 / 3.14159265358979323846;
    test.smooth_edges = smooth_edges;
    low_poly_refit = TestCreases(dense, test).hard_edges > part_creases.hard_edges;
  }
  // With the refit, the first fits are the first half of the part's work.
  std::function<void(const std::string&, double)> first_progress = part_progress;
  if (low_poly_refit && part_progress) {
    first_progress = [&](const std::string& st, double f) { part_progress(st, 0.5 * f); };
  }
  fo.clamp_control_vertices = true;
  // The control-vertex fit (options.fit's rounds) runs on a part without hard creases
  // (organic, or every sharp edge shaded smooth) only: it knows nothing of creases and pulls a
  // crease-keeping control mesh's vertices off them (docs/characters.md, "The control-vertex
  // fit on parts without hard creases"). A part with hard creases runs it in none of its fits:
  // not on the crease-keeping control mesh, nor on the plain remesh compared with it or fitted
  // instead of it (with the rounds, those lost to the crease-keeping fits without them on
  // RiggedSimple and the Fox), nor with remesh_creases off.
  if (part_creases.hard) fo.control_fit_iterations = 0;
  // Support rows beside the part's closed crease loops (CharacterFitOptions::crease_support),
  // on the crease-keeping control mesh only.
  // The cut needs the adaptive displacement, whose levels ZeroDisplacementOnSeams makes vanish
  // on the cut.
  const bool cut = creases.hard && options.cut_creases &&
                   fo.displacement.method == DisplacementMethod::kAdaptive;
  const bool supported = creases.hard && options.crease_support < 1.0 && !cut;
  // The part's triangles, for the moves of its control vertices and the surface gaps below.
  auto tree = std::make_shared<TriangleDistanceTree>();
  if (shading.curved() || supported || options.surface_gap > 0.0) {
    std::vector<std::uint32_t> triangles(dense.face_vertices.begin(), dense.face_vertices.end());
    if (!tree->Build(dense.positions, triangles)) tree.reset();
  }
  // Every fit of the part follows its shading surface: the samples between the vertices lie
  // on it, and the control vertices are moved onto it from the flat triangles where the
  // control mesh put them (the domain surface interpolates them, and would keep the facets).
  if (shading.curved() && tree) {
    // A hook the caller gave runs after the move.
    std::function<void(PolygonMesh*)> then = options.fit.place_control_vertices;
    fo.place_control_vertices = [tree, &shading, then](PolygonMesh* control) {
      for (Vec3& x : control->positions) {
        const ClosestPoint cp = tree->Query(x);
        if (cp.triangle == kInvalidIndex) continue;
        const double w[3] = {cp.barycentric.x, cp.barycentric.y, cp.barycentric.z};
        x = shading.Point(cp.triangle, w);
      }
      if (then) then(control);
    };
  }
  // The fits on control meshes without creases (the plain remesh, the simplification) keep
  // options.fit's smoothing and every point at weight 1.
  const FitOptions plain_options = fo;
  // The support rows run first, on the remesh's own positions (its crease vertices on the
  // chains, everything on the flat triangles); the move onto the shading surface and the
  // caller's hook follow.
  auto support = std::make_shared<CreaseSupportResult>();
  if (supported && tree) {
    // Crease vertices of the remesh lie on the chains to rounding (CreaseChains::Between).
    const double tolerance = 1e-7 * diagonal;
    const double keep = options.crease_support;
    std::function<void(PolygonMesh*)> then = fo.place_control_vertices;
    fo.place_control_vertices = [ref = creases.ref, chains = creases.chains, tree, then, tolerance,
                                 keep, support](PolygonMesh* control) {
      auto project = [&](const Vec3& y) {
        const ClosestPoint cp = tree->Query(y);
        return cp.triangle == kInvalidIndex ? y : cp.point;
      };
      (void)ref;  // the chains' surface, kept alive with them
      // keep and the tolerance are checked by FitCharacter, and the remesh's faces name its
      // vertices: this cannot fail.
      (void)SupportCreaseLoops(*chains, keep, tolerance, project, control, support.get());
      if (then) then(control);
    };
  }
  // The cut runs on the remesh's own positions (its crease vertices on the chains), before
  // any move.
  auto cut_result = std::make_shared<CreaseCutResult>();
  if (cut) {
    const double tolerance = 1e-7 * diagonal;
    fo.cut_control_mesh = [ref = creases.ref, chains = creases.chains, tolerance, cut_result](
                              PolygonMesh* control, std::vector<std::uint8_t>* seam) {
      (void)ref;  // the chains' surface, kept alive with them
      Status s = CutAlongCreases(*chains, tolerance, control, cut_result.get());
      if (s.ok()) *seam = cut_result->seam;
      return s;
    };
  }
  FitInput input;
  input.points = dense.positions;  // first, so point_fits[i] is vertex i's
  if (options.samples_per_control_edge > 0.0) {
    const double edge = std::sqrt(Area(dense) / fo.control_vertices);
    // A low-poly part (its control mesh at its own resolution or finer): a long facet spans
    // several control edges, and where the part curves the remesh's sizing keeps each within
    // a turn of about max_turn / 2 (SizingOptions::max_turn, then the split into quads), shorter
    // than the count's edge. A curved sliver's samples then come as many per such control edge
    // as the spacing gives per mean edge (docs/characters.md, "Samples as close as the control
    // edges along curved slivers"). On a denser part the facets' angles are its detail, finer
    // than the control mesh, and say nothing of its sizing. The samples come before the control
    // mesh is built: the input's own quads, if the part ends with them, cross a long facet with
    // their inserted loops, about as close. Low-poly here is at most min_control_vertices welded
    // vertices by default, any part with vertex_ratio >= 1 (each sliver's points capped by the
    // sampler).
    const bool low_poly = fo.control_vertices >= dense.num_vertices();
    const double turn = options.max_turn > 0.0 && low_poly
                            ? options.max_turn / (2.0 * options.samples_per_control_edge)
                            : 0.0;
    const std::vector<Vec3> extra = character::AreaSamples(
        dense, shading, smooth_edges, edge / options.samples_per_control_edge, options.crease_angle,
        options.crease_samples, options.crease_rows, turn);
    input.points.insert(input.points.end(), extra.begin(), extra.end());
    // Check points between the samples (CharacterFitOptions::check_points), with the source's
    // shading normals there (CharacterFitOptions::check_shading). On a low-poly part always.
    // On a denser one the levels follow its vertices and the distance rule confirms every
    // level (CesiumMan and the demo creature: the same levels, 1.5 s more on the creature), so
    // there they serve the shading rule alone: only where the part has shading normals
    // (CesiumMan's hips: the finest levels pinned the surface to each ring of vertices and
    // left ridges between them; docs/characters.md, "Levels checked by the shading").
    if (options.check_points > 0.0 && (low_poly || options.check_shading)) {
      // At most as many as the points fitted: the rule compares means.
      input.check_points = character::CheckPoints(
          dense, shading, edge / options.samples_per_control_edge, options.check_points,
          kCheckPointSeed, static_cast<double>(input.points.size()),
          options.check_shading ? &input.check_normals : nullptr);
      bool normals = false;
      for (const Vec3& n : input.check_normals) normals = normals || glm::dot(n, n) > 0.0;
      if (!normals) input.check_normals.clear();
      if (!low_poly && input.check_normals.empty()) input.check_points.clear();
      input.check_distances = low_poly;
    }
  }
  input.mesh = &dense;
  FitInput plain_input = input;
  // On a control mesh that keeps the part's creases: smoother levels, and (when there are
  // samples between the vertices) heavier vertices. The same where every sharp edge of the
  // part is shaded smooth: no crease is left for the displacement to carry, and its facets'
  // kinks are to be rounded, as its renderer draws them, not followed.
  const bool crease_fit = creases.hard;
  if (creases.sharp) {
    if (options.crease_smoothing >= 0.0) {
      fo.displacement.adaptive.smoothing = options.crease_smoothing;
    }
    if (options.vertex_weight != 1.0 && input.points.size() > dense.positions.size()) {
      input.weights.assign(input.points.size(), 1.0);
      std::fill(input.weights.begin(),
                input.weights.begin() + static_cast<std::ptrdiff_t>(dense.positions.size()),
                options.vertex_weight);
    }
  }
  // With the simplification's fit to compare, each fit is half of the component's work.
  const bool compare =
      options.compare_simplified && fo.control_method == ControlMeshMethod::kRemesh;
  // With creases kept, the plain remesh's fit is compared too (each fit a share of the work;
  // a part without creases is fitted once and its bar jumps over the second share).
  const bool plain = options.remesh_creases && options.compare_without_creases &&
                     fo.control_method == ControlMeshMethod::kRemesh;
  const double share = 1.0 / ((compare ? 2.0 : 1.0) * (plain ? 2.0 : 1.0));
  if (first_progress) {
    fo.progress = [&](const char* st, std::size_t done, std::size_t total) {
      first_progress(
          st, total > 0 ? share * static_cast<double>(done) / static_cast<double>(total) : 0.0);
    };
  }
  Status s = FitSurface(input, fo, fitted, fr);
  if (!s.ok()) return s.message();
  // The input and options of the fit kept so far (for the surface gaps' refit, below).
  const FitInput* kept_input = &input;
  FitOptions kept_options = fo;
  fr->control_mesh.crease_support_loops = support->loops;
  fr->control_mesh.crease_support_vertices = support->moved;
  fr->control_mesh.crease_cut_edges = cut_result->cut_edges;
  fr->control_mesh.crease_cut_vertices = cut_result->new_vertices;
  const bool kept_creases =
      fr->control_mesh.method == "remesh" && fr->control_mesh.quality.crease_edges_kept > 0;
  if (crease_fit && !kept_creases) {
    // The control mesh kept no crease after all (the remesh fell back, or kept none): fit
    // again as a part without creases.
    s = FitSurface(plain_input, plain_options, fitted, fr);
    if (!s.ok()) return s.message();
    kept_input = &plain_input, kept_options = plain_options;
  }
  if (plain && kept_creases) {
    // Keeping every crease as control edges sharpens low-poly, hard-edged parts but makes
    // denser control meshes that can fit organic parts worse (docs/characters.md, "Creases or
    // not"): fit the plain remesh too and keep the crease-aware one only where its two-sided
    // Hausdorff distance is clearly lower.
    FitOptions po = plain_options;
    po.remesh.crease_angle_deg = 0.0;
    po.progress = nullptr;
    if (first_progress) {
      po.progress = [&](const char* st, std::size_t done, std::size_t total) {
        first_progress(
            std::string(st) + ", control mesh without creases",
            share +
                (total > 0 ? share * static_cast<double>(done) / static_cast<double>(total) : 0.0));
      };
    }
    FittedSurface alt;
    FitReport alt_report;
    if (FitSurface(plain_input, po, &alt, &alt_report).ok() &&
        !(fr->error.hausdorff < options.crease_margin * alt_report.error.hausdorff)) {
      char note[200];
      std::snprintf(note, sizeof(note),
                    "the control mesh without creases was kept: Hausdorff %.3g against %.3g "
                    "keeping %d crease edges (of the part's scale)",
                    alt_report.error.hausdorff, fr->error.hausdorff,
                    fr->control_mesh.quality.crease_edges_kept);
      kept_input = &plain_input, kept_options = po;
      *fitted = std::move(alt);
      *fr = std::move(alt_report);
      *kept_simplified = note;
    }
  }
  if (compare && fr->control_mesh.method == "remesh") {
    // The remesh moves the source's crease vertices off its creases; a simplification keeps
    // them. Fit on both and keep the simplification's only where its two-sided Hausdorff
    // distance (E3, level 8 against the component's triangles) is clearly lower.
    FitOptions so = plain_options;
    so.control_method = ControlMeshMethod::kSimplify;
    so.progress = nullptr;
    if (first_progress) {
      so.progress = [&](const char* st, std::size_t done, std::size_t total) {
        first_progress(
            std::string(st) + ", simplified control mesh",
            0.5 + (total > 0 ? 0.5 * static_cast<double>(done) / static_cast<double>(total) : 0.0));
      };
    }
    FittedSurface alt;
    FitReport alt_report;
    if (FitSurface(plain_input, so, &alt, &alt_report).ok() &&
        alt_report.error.hausdorff < options.simplified_margin * fr->error.hausdorff) {
      char note[160];
      std::snprintf(note, sizeof(note),
                    "the simplification's control mesh was kept: Hausdorff %.3g against the "
                    "remesh's %.3g (of the part's scale)",
                    alt_report.error.hausdorff, fr->error.hausdorff);
      kept_input = &plain_input, kept_options = so;
      *fitted = std::move(alt);
      *fr = std::move(alt_report);
      *kept_simplified = note;
    }
  }
  // The kept fit checked against the source the other way round (CharacterFitOptions::
  // surface_gap, SurfaceGapPoints): where its surface leaves the source by more than
  // surface_gap of the diagonal, the source's nearest points join the data and the part is
  // fitted again with the same input and options, once, without progress (the bar has passed
  // that fit); the refit is kept unless its two-sided Hausdorff distance is larger. After the
  // comparisons above (they keep their decisions), before the low-poly refit's (whose own fit
  // takes this step too).
  const double gap = options.surface_gap * diagonal;
  if (gap > 0.0 && tree) {
    const std::vector<Vec3> more =
        character::SurfaceGapPoints(*fitted, *tree, shading, gap, kSurfaceGapSamplesPerEdge);
    if (!more.empty()) {
      FitInput again = *kept_input;
      again.points.insert(again.points.end(), more.begin(), more.end());
      if (!again.weights.empty()) again.weights.resize(again.points.size(), 1.0);
      kept_options.progress = nullptr;
      FittedSurface refit;
      FitReport refit_report;
      // Hausdorff distances in model units: each fit's unit is its own points' size, and the
      // added points (on a curved shading surface) can lie outside the first fit's box.
      if (FitSurface(again, kept_options, &refit, &refit_report).ok() &&
          !(refit_report.error.hausdorff * refit_report.scale > fr->error.hausdorff * fr->scale)) {
        // What this function adds to the report (the cut, the support rows) is the same.
        const ControlMeshInfo& was = fr->control_mesh;
        ControlMeshInfo& now = refit_report.control_mesh;
        now.crease_support_loops = was.crease_support_loops;
        now.crease_support_vertices = was.crease_support_vertices;
        now.crease_cut_edges = was.crease_cut_edges;
        now.crease_cut_vertices = was.crease_cut_vertices;
        now.surface_gap_points = static_cast<int>(more.size());
        *fitted = std::move(refit);
        *fr = std::move(refit_report);
      }
    }
  }
  fr->control_mesh.control_fit_rounds = static_cast<int>(fr->control_fit_rounds);
  {
    const AdaptiveDisplacementReport& d = fr->displacement_fit;
    fr->control_mesh.check_points = static_cast<int>(d.check_points);
    fr->control_mesh.check_levels_dropped =
        d.check_mean.empty()
            ? 0
            : static_cast<int>(d.check_mean.size()) - 1 - d.levels - d.shading_levels_dropped;
    fr->control_mesh.shading_levels_dropped = d.shading_levels_dropped;
    fr->control_mesh.check_angle_deg = d.check_angle_deg;
  }
  fr->control_mesh.shading_shape = shape;
  fr->control_mesh.shading_deviation_deg = glm::degrees(deviation);
  fr->control_mesh.flat_deviation_deg = glm::degrees(flat_deviation);
  // The angle from which the kept control mesh's creases were taken (none: 0).
  fr->control_mesh.crease_angle_deg =
      fr->control_mesh.method == "remesh" && fr->control_mesh.quality.crease_edges_kept > 0
          ? crease_angle_deg
          : 0.0;
  if (low_poly_refit) {
    // A low-poly part is also fitted with its gentler hard edges as creases
    // (CharacterFitOptions::low_poly_crease_angle), and keeps that fit where it kept creases
    // and is clearly closer.
    CharacterFitOptions lo = options;
    lo.crease_angle = options.low_poly_crease_angle;
    lo.low_poly_crease_angle = 0.0;
    lo.compare_without_creases = false;
    lo.compare_simplified = false;
    std::function<void(const std::string&, double)> lo_progress;
    if (part_progress) {
      lo_progress = [&](const std::string& st, double f) {
        part_progress(st + ", gentle hard edges as creases", 0.5 + 0.5 * f);
      };
    }
    FittedSurface alt;
    FitReport alt_report;
    std::string alt_note;
    if (FitComponent(dense, corner_normals, lo, lo_progress, &alt, &alt_report, &alt_note)
            .empty() &&
        alt_report.control_mesh.quality.crease_edges_kept > 0 &&
        alt_report.error.hausdorff < options.crease_margin * fr->error.hausdorff) {
      char note[200];
      std::snprintf(note, sizeof(note),
                    "a low-poly part: its hard edges from %.3g degrees on were kept as creases "
                    "(Hausdorff %.3g against %.3g, of the part's scale, for the fit it replaced",
                    alt_report.control_mesh.crease_angle_deg, alt_report.error.hausdorff,
                    fr->error.hausdorff);
      *kept_simplified = kept_simplified->empty()
                             ? std::string(note) + ")"
                             : std::string(note) + ", where " + *kept_simplified + ")";
      *fitted = std::move(alt);
      *fr = std::move(alt_report);
    }
  }
  return std::string();
}

/// The parameters of a component's vertices: the fitted one, or the closest point for the few
/// the projection lost.
std::vector<VertexBinding> VertexParameters(const DisplacedSurface& surf,
                                            const std::vector<LocalPatch>& patches,
                                            const std::vector<PointFit>& point_fits,
                                            const PolygonMesh& dense) {
  std::vector<Vec3> centres;
  std::vector<VertexBinding> param(static_cast<std::size_t>(dense.num_vertices()));
  for (std::size_t i = 0; i < param.size(); ++i) {
    const PointFit& f = point_fits[i];
    if (f.status != PointFitStatus::kOutside) {
      param[i].face = f.face;
      param[i].u = f.uv.x;
      param[i].v = f.uv.y;
      continue;
    }
    if (centres.empty()) {
      for (Index f2 = 0; f2 < surf.domain->num_faces(); ++f2) {
        SurfacePoint sp;
        EvaluateSurface(*surf.domain, patches.data(), surf.displacement.get(), f2, Vec2(0.5), &sp);
        centres.push_back(sp.position);
      }
    }
    param[i] = ClosestBinding(surf, patches, centres, dense.positions[i]);
  }
  return param;
}

/// Skin weights of a part's control vertices from the dense mesh's nearest surface point,
/// then `smoothing` umbrella steps over the control mesh (CharacterFitOptions::skin_smoothing).
void TransferSkin(const AssetMesh& mesh, const WeldedMesh& w, const Components& components,
                  std::size_t c, const ComponentMesh& cm, int smoothing, CharacterPart* part) {
  TriangleDistanceTree tree;
  std::vector<std::uint32_t> tris;
  for (std::size_t t : components.triangles[c]) {
    for (int k = 0; k < 3; ++k) {
      tris.push_back(
          static_cast<std::uint32_t>(cm.local[w.triangles[t + static_cast<std::size_t>(k)]]));
    }
  }
  tree.Build(cm.dense.positions, tris);
  std::vector<std::vector<Influence>> influences(cm.global.size());
  for (std::size_t i = 0; i < cm.global.size(); ++i) {
    const VertexRef& r = w.representative[static_cast<std::size_t>(cm.global[i])];
    influences[i] =
        VertexInfluences(mesh.primitives[r.primitive], static_cast<std::size_t>(r.vertex));
  }
  const DisplacedSurface& surf = part->surface;
  const std::size_t nc = surf.rest_positions.size();
  part->control_joints.resize(nc);
  part->control_weights.resize(nc);
  for (std::size_t v = 0; v < nc; ++v) {
    const ClosestPoint cp = tree.Query(surf.rest_positions[v]);
    const std::size_t t = static_cast<std::size_t>(cp.triangle) * 3;
    BlendInfluences(influences[tris[t]], influences[tris[t + 1]], influences[tris[t + 2]],
                    cp.barycentric, &part->control_joints[v], &part->control_weights[v]);
  }
  character::SmoothSkinWeights(surf.domain->topology(), surf.rest_positions, smoothing, 0.5,
                               &part->control_joints, &part->control_weights);
}

/// |D(z_b) - p|: the distance from p to the surface point of binding b.
double Distance(const DisplacedSurface& surf, const std::vector<LocalPatch>& patches,
                const VertexBinding& b, const Vec3& p) {
  SurfacePoint sp;
  EvaluateSurface(*surf.domain, patches.data(), surf.displacement.get(), b.face, Vec2(b.u, b.v),
                  &sp);
  return glm::length(sp.position - p);
}

/// The fit summary of a part, with the mean and largest distance of its welded vertices
/// (model units) divided by the fit's scale.
PartFitSummary Summary(const PolygonMesh& dense, const FitReport& fr, double mean, double max) {
  PartFitSummary f;
  f.points = dense.num_vertices();
  f.triangles = dense.num_faces();
  f.points_outside = fr.points_outside;
  f.points_not_converged = fr.points_not_converged;
  f.scale = fr.scale;
  f.e1_mean = mean / fr.scale;
  f.e1_max = max / fr.scale;
  f.hausdorff = fr.error.hausdorff;
  f.coefficients = fr.coefficients;
  f.levels = fr.max_levels;
  return f;
}

/// The skin of the first node that draws mesh m with one, or none.
Index MeshSkin(const Asset& asset, std::size_t m) {
  for (const AssetNode& node : asset.nodes) {
    if (node.mesh == static_cast<Index>(m) && node.skin != kInvalidIndex) return node.skin;
  }
  return kInvalidIndex;
}

}  // namespace

Status FitCharacter(const Asset& asset, const CharacterFitOptions& options, Character* out,
                    CharacterFitReport* report) {
  if (!(options.crease_support > 0.0 && options.crease_support <= 1.0)) {
    return Status::InvalidInput("character fit: crease_support must be in (0, 1], not " +
                                std::to_string(options.crease_support));
  }
  if (!(options.input_quads == 0.0 ||
        (options.input_quads >= 1.0 && std::isfinite(options.input_quads)))) {
    return Status::InvalidInput("character fit: input_quads must be 0 (off) or at least 1, not " +
                                std::to_string(options.input_quads));
  }
  if (!(options.shading_shape < 0.0 ||
        (options.shading_shape >= 0.0 && options.shading_shape <= 1.0))) {
    return Status::InvalidInput(
        "character fit: shading_shape must be negative (chosen per part) or in [0, 1], not " +
        std::to_string(options.shading_shape));
  }
  if (!(options.check_points >= 0.0 && options.check_points <= 64.0)) {
    return Status::InvalidInput("character fit: check_points must be in [0, 64] (0: none), not " +
                                std::to_string(options.check_points));
  }
  if (options.skin_smoothing < 0 || options.skin_smoothing > 64) {
    return Status::InvalidInput("character fit: skin_smoothing must be in [0, 64] (0: off), not " +
                                std::to_string(options.skin_smoothing));
  }
  if (!(options.surface_gap >= 0.0 && options.surface_gap < 1.0)) {
    return Status::InvalidInput("character fit: surface_gap must be in [0, 1) (0: off), not " +
                                std::to_string(options.surface_gap));
  }
  // The samples' densities: a spacing thousands of times finer than the control mesh's edge
  // (or not a number) would ask for more points than any fit can hold.
  if (!(options.samples_per_control_edge >= 0.0 && options.samples_per_control_edge <= 64.0)) {
    return Status::InvalidInput(
        "character fit: samples_per_control_edge must be in [0, 64] (0: vertices only), not " +
        std::to_string(options.samples_per_control_edge));
  }
  if (!(options.crease_samples >= 0.0 && options.crease_samples <= 64.0)) {
    return Status::InvalidInput("character fit: crease_samples must be in [0, 64], not " +
                                std::to_string(options.crease_samples));
  }
  if (!(options.low_poly_crease_angle >= 0.0 && options.low_poly_crease_angle < 1.5)) {
    return Status::InvalidInput(
        "character fit: low_poly_crease_angle must be in [0, 1.5) radians (0: off), not " +
        std::to_string(options.low_poly_crease_angle));
  }
  const auto t0 = std::chrono::steady_clock::now();
  Character ch;
  ch.asset = asset;
  CharacterFitReport rep;
  rep.meshes = static_cast<std::int64_t>(asset.meshes.size());
  double e1_sum = 0.0;
  // Progress: the character's work in triangles of the source; mesh m's start at
  // mesh_start[m], each component's at its first triangle's count.
  std::vector<std::size_t> mesh_start(asset.meshes.size() + 1, 0);
  if (options.progress) {
    for (std::size_t m = 0; m < asset.meshes.size(); ++m) {
      std::size_t triangles = 0;
      for (const AssetPrimitive& prim : asset.meshes[m].primitives) {
        triangles += PrimitiveTriangles(prim).size() / 3;
      }
      mesh_start[m + 1] = mesh_start[m] + triangles;
    }
  }
  const std::size_t work_total = mesh_start.back();
  ch.bindings.resize(asset.meshes.size());
  for (std::size_t m = 0; m < asset.meshes.size(); ++m) {
    const AssetMesh& mesh = asset.meshes[m];
    ch.bindings[m].resize(mesh.primitives.size());
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      ch.bindings[m][p].resize(mesh.primitives[p].positions.size());
      rep.vertices += static_cast<std::int64_t>(mesh.primitives[p].positions.size());
    }
    const Index skin = MeshSkin(asset, m);
    const WeldedMesh w = WeldMesh(mesh);
    if (w.triangles.empty()) {
      // Nothing to fit, but never silently: a mesh with triangles that all collapse (repeated
      // or coincident vertices) is listed as unfitted with the reason.
      std::int64_t triangles = 0;
      for (const AssetPrimitive& prim : mesh.primitives) {
        triangles += static_cast<std::int64_t>(PrimitiveTriangles(prim).size() / 3);
      }
      if (triangles == 0) continue;  // points or lines only: not a surface
      UnfittedPart unfitted;
      unfitted.mesh = static_cast<Index>(m);
      unfitted.component = 0;
      unfitted.vertices = static_cast<std::int64_t>(w.positions.size());
      unfitted.triangles = triangles;
      unfitted.reason = "degenerate: every triangle has two vertices at the same position";
      ch.unfitted.push_back(unfitted);
      ++rep.parts_unfitted;
      continue;
    }
    const Components components = SplitComponents(w);
    rep.components += static_cast<std::int64_t>(components.triangles.size());
    for (std::size_t c = 0; c < components.triangles.size(); ++c) {
      const ComponentMesh cm = MakeComponentMesh(
          w, components, c,
          asset.source + ": mesh " + std::to_string(m) + " component " + std::to_string(c));
      const PolygonMesh& dense = cm.dense;
      const std::string stage = "mesh " + std::to_string(m) + " component " + std::to_string(c);
      UnfittedPart unfitted;
      unfitted.mesh = static_cast<Index>(m);
      unfitted.component = static_cast<Index>(c);
      unfitted.vertices = dense.num_vertices();
      unfitted.triangles = dense.num_faces();
      FittedSurface fitted;
      FitReport fr;
      std::string kept_simplified;
      std::function<void(const std::string&, double)> part_progress;
      if (options.progress) {
        std::size_t start = mesh_start[m];
        for (std::size_t c2 = 0; c2 < c; ++c2) start += components.triangles[c2].size();
        const std::size_t triangles = components.triangles[c].size();
        part_progress = [&options, &stage, start, triangles, work_total](const std::string& st,
                                                                         double fraction) {
          const auto done = start + static_cast<std::size_t>(
                                        std::floor(fraction * static_cast<double>(triangles)));
          const std::string what = stage + ": " + st;
          options.progress(what.c_str(), std::min(done, work_total), work_total);
        };
      }
      unfitted.reason = FitComponent(dense, cm.corner_normals, options, part_progress, &fitted, &fr,
                                     &kept_simplified);
      if (!unfitted.reason.empty()) {
        ch.unfitted.push_back(unfitted);
        ++rep.parts_unfitted;
        continue;
      }
      CharacterPart part;
      part.mesh = static_cast<Index>(m);
      part.component = static_cast<Index>(c);
      part.skin = skin;
      part.surface.domain = std::move(fitted.surface.domain);
      part.surface.rest_positions = fitted.surface.control.positions;
      part.surface.displacement = std::move(fitted.displacement);
      // The points fitted: the welded vertices, the samples on the triangles and any points
      // added where the surface left the source (CharacterFitOptions::surface_gap).
      part.surface.data_points = fr.points;
      const DisplacedSurface& surf = part.surface;
      const std::vector<LocalPatch>& patches = fitted.surface.patches;
      std::vector<VertexBinding> param = VertexParameters(surf, patches, fitted.point_fits, dense);
      const Index part_index = static_cast<Index>(ch.parts.size());
      double part_sum = 0.0, part_max = 0.0;
      for (std::size_t i = 0; i < cm.global.size(); ++i) {
        param[i].part = part_index;
        const double e = Distance(surf, patches, param[i], dense.positions[i]);
        part_sum += e, part_max = std::max(part_max, e);
      }
      // Every original vertex of the component takes its welded vertex's parameter.
      for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
        for (std::size_t v = 0; v < w.welded[p].size(); ++v) {
          const Index wv = w.welded[p][v];
          if (wv == kInvalidIndex || components.of_vertex[wv] != static_cast<Index>(c)) continue;
          const VertexBinding& b = param[static_cast<std::size_t>(cm.local[wv])];
          ch.bindings[m][p][v] = b;
          const double e = Distance(surf, patches, b, Vec3(mesh.primitives[p].positions[v]));
          e1_sum += e, rep.e1_max = std::max(rep.e1_max, e);
          ++rep.vertices_bound;
        }
      }
      if (skin != kInvalidIndex) {
        TransferSkin(mesh, w, components, c, cm, options.skin_smoothing, &part);
      }
      part.fit = Summary(dense, fr, part_sum / static_cast<double>(cm.global.size()), part_max);
      rep.part_control_meshes.push_back(fr.control_mesh);
      std::string note;
      if (fr.control_vertices > dense.num_vertices()) {
        const QuadRemeshReport& q = fr.control_mesh.quality;
        char deviation[64], turn[64];
        std::snprintf(deviation, sizeof(deviation), "%.2g", q.deviation);
        std::snprintf(turn, sizeof(turn), "%.3g", options.max_turn);
        const std::string why =
            q.grown_target > q.target_vertices
                ? "its thin parts need them (the remesh follows the part within " +
                      std::string(deviation) + " edge lengths only from " +
                      std::to_string(q.grown_target) + " vertices on)"
                : "its remesh cannot be coarser: every edge of the remeshed triangle "
                  "mesh may turn the surface normal by at most " +
                      std::string(turn) +
                      " radians, and each of its triangles becomes 3 or 4 quads";
        // The input's own quads stand in for a remesh of at most as many vertices
        // (QuadRemeshOptions::input_quads_max_ratio), which the reason is about.
        note = "part " + std::to_string(ch.parts.size()) + " (" + stage + ") has " +
               std::to_string(fr.control_vertices) + " control vertices for " +
               std::to_string(dense.num_vertices()) + " vertices: " +
               (q.input_quads ? "its own quads, with edge loops, stand in for its remesh of " +
                                    std::to_string(q.remesh_vertices) + " vertices; " + why
                              : why) +
               (q.crease_edges > 0
                    ? "; its " + std::to_string(q.crease_chains) +
                          " crease chains keep their corners and follow the "
                          "creases (" +
                          std::to_string(q.control_crease_edges) + " control edges on them)"
                    : std::string()) +
               (fr.control_mesh.crease_cut_vertices > 0
                    ? "; cut open along them, with " +
                          std::to_string(fr.control_mesh.crease_cut_vertices) + " vertices added"
                    : std::string());
        if (!fr.control_mesh.fallback.empty()) {
          note = "part " + std::to_string(ch.parts.size()) + " (" + stage + ") has " +
                 std::to_string(fr.control_vertices) + " control vertices for " +
                 std::to_string(dense.num_vertices()) + " vertices: the remesh failed (" +
                 fr.control_mesh.fallback + ") and the simplification's split was used";
        }
      }
      if (!kept_simplified.empty()) {
        note = "part " + std::to_string(ch.parts.size()) + " (" + stage + ") has " +
               std::to_string(fr.control_vertices) + " control vertices for " +
               std::to_string(dense.num_vertices()) + " vertices: " + kept_simplified;
      }
      rep.part_notes.push_back(note);
      ch.parts.push_back(std::move(part));
      ++rep.parts_fitted;
    }
  }
  rep.e1_mean = rep.vertices_bound > 0 ? e1_sum / static_cast<double>(rep.vertices_bound) : 0.0;
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  *out = std::move(ch);
  if (report) *report = rep;
  return Status::Ok();
}

}  // namespace dermis
