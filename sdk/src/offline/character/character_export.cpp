// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Export builders for characters: `bound` re-evaluates the original vertices at their fitted
// parameters (paper Eq. 4), `lod` tessellates each fitted part (docs/notes/manifold.md section 6)
// and transfers skin weights and UVs from the original triangles.
#include "dermis/offline/character/character_export.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/surface_evaluator.h"
#include "dermis/surface/tessellation.h"
#include "offline/character/character_eval.h"

namespace dermis {
namespace {

using character::PartEval;

/// The original triangles of one part: primitive and its three vertex indices.
struct PartTriangle {
  Index primitive;
  std::uint32_t v[3];
};

std::vector<PartTriangle> PartTriangles(const Character& ch, Index part) {
  std::vector<PartTriangle> out;
  const Index m = ch.parts[static_cast<std::size_t>(part)].mesh;
  if (m < 0) return out;
  const AssetMesh& mesh = ch.asset.meshes[static_cast<std::size_t>(m)];
  for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
    const std::vector<std::uint32_t> tris = PrimitiveTriangles(mesh.primitives[p]);
    const std::vector<VertexBinding>& b = ch.bindings[static_cast<std::size_t>(m)][p];
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
      if (b[tris[t]].part != part || b[tris[t + 1]].part != part || b[tris[t + 2]].part != part) {
        continue;
      }
      out.push_back({static_cast<Index>(p), {tris[t], tris[t + 1], tris[t + 2]}});
    }
  }
  return out;
}

glm::vec3 ToFloat(const Vec3& v) { return glm::vec3(v); }

/// A unit tangent orthogonal to n, keeping the old tangent's direction where it can.
glm::vec4 Reorthogonalise(const glm::vec4& tangent, const glm::vec3& n) {
  glm::vec3 t = glm::vec3(tangent) - n * glm::dot(n, glm::vec3(tangent));
  float len = glm::length(t);
  if (!(len > 1e-6f)) {
    t = std::abs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0))
                             : glm::cross(n, glm::vec3(0, 1, 0));
    len = glm::length(t);
  }
  return glm::vec4(t / len, tangent.w < 0.0f ? -1.0f : 1.0f);
}

}  // namespace

namespace character {

/// Area-weighted vertex normals of a primitive's triangles at `positions` (unit; (0, 0, 1)
/// where no triangle has area).
std::vector<Vec3> TriangleNormals(const AssetPrimitive& prim, const std::vector<Vec3>& positions) {
  std::vector<Vec3> acc(positions.size(), Vec3(0.0));
  const std::vector<std::uint32_t> tris = PrimitiveTriangles(prim);
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const Vec3 n = glm::cross(positions[tris[t + 1]] - positions[tris[t]],
                              positions[tris[t + 2]] - positions[tris[t]]);
    for (std::size_t k = 0; k < 3; ++k) acc[tris[t + k]] += n;
  }
  for (Vec3& n : acc) {
    const double len = glm::length(n);
    n = len > 0.0 ? n / len : Vec3(0.0, 0.0, 1.0);
  }
  return acc;
}

Status MakePartEval(const Character& ch, Index part_index, int levels, PartEval* e) {
  const CharacterPart& part = ch.parts[static_cast<std::size_t>(part_index)];
  const DisplacedSurface& s = part.surface;
  e->patches.resize(s.rest_positions.size());
  s.domain->FitPatches(s.rest_positions.data(), e->patches.data());
  if (s.displacement && levels != 0) {
    if (levels < 0 || levels >= s.displacement->max_levels()) {
      e->displacement = s.displacement.get();
    } else {
      e->truncated = std::make_unique<TruncatedDisplacement>(s.displacement.get(), levels);
      e->displacement = e->truncated.get();
    }
  }
  // Orientation: the surface normal against the area-weighted normals of the source triangles.
  double agree = 0.0;
  if (part.mesh >= 0) {
    const AssetMesh& mesh = ch.asset.meshes[static_cast<std::size_t>(part.mesh)];
    for (const PartTriangle& t : PartTriangles(ch, part_index)) {
      const AssetPrimitive& prim = mesh.primitives[static_cast<std::size_t>(t.primitive)];
      const Vec3 a(prim.positions[t.v[0]]), b(prim.positions[t.v[1]]), c(prim.positions[t.v[2]]);
      const VertexBinding& vb = ch.bindings[static_cast<std::size_t>(part.mesh)]
                                           [static_cast<std::size_t>(t.primitive)][t.v[0]];
      SurfacePoint sp;
      if (!EvaluateSurface(*s.domain, e->patches.data(), e->displacement, vb.face, Vec2(vb.u, vb.v),
                           &sp)) {
        return Status::InvalidInput(ch.asset.source + ": part " + std::to_string(part_index) +
                                    ": a vertex binding is invalid");
      }
      agree += glm::dot(glm::cross(b - a, c - a), sp.normal);
    }
  }
  e->orientation = agree < 0.0 ? -1.0 : 1.0;
  return Status::Ok();
}

}  // namespace character

Status BuildBoundAsset(const Character& ch, const CharacterExportOptions& options, Asset* out) {
  if (Status s = character::RequireSourceAsset(ch); !s.ok()) return s;
  if (ch.asset.meshes.empty()) {
    return Status::InvalidInput(
        ch.asset.source + ": has no original meshes to bind (a plain surface); use --mode lod");
  }
  std::vector<PartEval> evals(ch.parts.size());
  for (std::size_t k = 0; k < ch.parts.size(); ++k) {
    Status s =
        character::MakePartEval(ch, static_cast<Index>(k), options.displacement_levels, &evals[k]);
    if (!s.ok()) return s;
  }
  Asset a = ch.asset;
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    for (std::size_t p = 0; p < a.meshes[m].primitives.size(); ++p) {
      AssetPrimitive& prim = a.meshes[m].primitives[p];
      const std::vector<VertexBinding>& bind = ch.bindings[m][p];
      bool any = false;
      for (const VertexBinding& b : bind) any = any || b.part != kInvalidIndex;
      if (!any) continue;
      const bool had_normals = !prim.normals.empty();
      if (!had_normals) prim.normals.assign(prim.positions.size(), glm::vec3(0, 0, 1));
      for (std::size_t v = 0; v < bind.size(); ++v) {
        const VertexBinding& b = bind[v];
        if (b.part == kInvalidIndex) continue;
        const PartEval& e = evals[static_cast<std::size_t>(b.part)];
        const DisplacedSurface& s = ch.parts[static_cast<std::size_t>(b.part)].surface;
        SurfacePoint sp;
        if (!EvaluateSurface(*s.domain, e.patches.data(), e.displacement, b.face, Vec2(b.u, b.v),
                             &sp)) {
          return Status::InvalidInput(ch.asset.source + ": mesh " + std::to_string(m) +
                                      " primitive " + std::to_string(p) + " vertex " +
                                      std::to_string(v) + ": invalid binding");
        }
        prim.positions[v] = ToFloat(sp.position);
        prim.normals[v] = glm::normalize(ToFloat(sp.normal * e.orientation));
        if (!prim.tangents.empty())
          prim.tangents[v] = Reorthogonalise(prim.tangents[v], prim.normals[v]);
      }
      if (!had_normals) {
        // Vertices of unfitted parts in the same primitive: normals from their triangles.
        const std::vector<Vec3> normals = character::TriangleNormals(
            prim, std::vector<Vec3>(prim.positions.begin(), prim.positions.end()));
        for (std::size_t v = 0; v < bind.size(); ++v) {
          if (bind[v].part == kInvalidIndex) prim.normals[v] = glm::vec3(normals[v]);
        }
      }
    }
  }
  *out = std::move(a);
  return Status::Ok();
}

Status BuildLodAsset(const Character& ch, const CharacterExportOptions& options, Asset* out,
                     std::vector<std::string>* notes) {
  return character::BuildLodAssetWithSources(ch, options, out, notes, nullptr);
}

namespace character {

namespace {

// Residual primitives: what was not fitted stays as it was.
Status KeepUnfittedTriangles(const Character& ch, Asset* a) {
  for (std::size_t m = 0; m < a->meshes.size(); ++m) {
    std::vector<AssetPrimitive> kept;
    for (std::size_t p = 0; p < a->meshes[m].primitives.size(); ++p) {
      AssetPrimitive prim = a->meshes[m].primitives[p];
      const std::vector<VertexBinding>& bind = ch.bindings[m][p];
      bool any = false;
      for (const VertexBinding& b : bind) any = any || b.part != kInvalidIndex;
      if (!any) {
        kept.push_back(std::move(prim));
        continue;
      }
      std::vector<std::uint32_t> rest;
      const std::vector<std::uint32_t> tris = PrimitiveTriangles(prim);
      for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
        if (bind[tris[t]].part == kInvalidIndex)
          rest.insert(rest.end(), {tris[t], tris[t + 1], tris[t + 2]});
      }
      if (!prim.targets.empty()) {
        return Status::Unsupported(ch.asset.source + ": /meshes/" + std::to_string(m) +
                                   ": lod export of a fitted mesh with morph targets is not "
                                   "supported yet; use --mode bound");
      }
      if (rest.empty()) continue;
      prim.mode = PrimitiveMode::kTriangles;
      prim.indices = std::move(rest);
      kept.push_back(std::move(prim));
    }
    a->meshes[m].primitives = std::move(kept);
  }
  return Status::Ok();
}

// A plain surface (no source mesh) gets a mesh, a node and a scene of its own.
void AddPlainSurfaceMeshes(const Character& ch, Asset* a) {
  for (std::size_t k = 0; k < ch.parts.size(); ++k) {
    if (ch.parts[k].mesh >= 0) continue;
    AssetMesh mesh;
    mesh.name = "dermis_surface_" + std::to_string(k);
    a->meshes.push_back(mesh);
    AssetNode node;
    node.name = mesh.name;
    node.mesh = static_cast<Index>(a->meshes.size() - 1);
    a->nodes.push_back(node);
    if (a->scenes.empty()) a->scenes.emplace_back(), a->default_scene = 0;
    a->scenes[0].nodes.push_back(static_cast<Index>(a->nodes.size() - 1));
  }
}

// Part k tessellated at the export level: positions, normals and triangles of *prim (facing
// outwards), the surface points in *x and the samples in *pattern.
Status TessellatePart(const Character& ch, std::size_t k, const CharacterExportOptions& options,
                      TessellationPattern* pattern, std::vector<Vec3>* x, AssetPrimitive* prim) {
  const CharacterPart& part = ch.parts[k];
  PartEval e;
  Status s = MakePartEval(ch, static_cast<Index>(k), options.displacement_levels, &e);
  if (!s.ok()) return s;
  const DisplacedSurface& surf = part.surface;
  s = TessellationPattern::Build(surf.domain->topology(), options.level, pattern);
  if (!s.ok()) return s.WithContext(ch.asset.source);
  const std::size_t n = pattern->samples.size();
  x->assign(n, Vec3(0.0));
  std::vector<Vec3> nrm(n);
  if (!EvaluateSamples(*surf.domain, e.patches.data(), e.displacement, pattern->samples.data(), n,
                       x->data(), nrm.data())) {
    return Status::Internal(ch.asset.source + ": part " + std::to_string(k) +
                            ": tessellation sample outside the domain");
  }
  prim->positions.resize(n);
  prim->normals.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    prim->positions[i] = ToFloat((*x)[i]);
    prim->normals[i] = glm::normalize(ToFloat(nrm[i] * e.orientation));
  }
  prim->indices = pattern->triangles;
  if (e.orientation < 0.0) {
    for (std::size_t t = 0; t + 2 < prim->indices.size(); t += 3) {
      std::swap(prim->indices[t + 1], prim->indices[t + 2]);
    }
  }
  return Status::Ok();
}

// Texture coordinates, material and skin weights of part k's tessellation, from the closest
// point of the part's original triangles; the material and the texture coordinate sets are
// those of the primitive with most triangles (sets not shared by all are dropped, with a note).
void TransferFromOriginal(const Character& ch, std::size_t k, const std::vector<Vec3>& x,
                          AssetPrimitive* prim, std::vector<std::string>* notes) {
  const CharacterPart& part = ch.parts[k];
  const std::size_t n = x.size();
  const AssetMesh& src = ch.asset.meshes[static_cast<std::size_t>(part.mesh)];
  const std::vector<PartTriangle> tris = PartTriangles(ch, static_cast<Index>(k));
  std::vector<Vec3> corners;
  std::vector<std::uint32_t> ids;
  for (const PartTriangle& t : tris) {
    const AssetPrimitive& sp = src.primitives[static_cast<std::size_t>(t.primitive)];
    for (int c = 0; c < 3; ++c) {
      ids.push_back(static_cast<std::uint32_t>(corners.size()));
      corners.push_back(Vec3(sp.positions[t.v[c]]));
    }
  }
  TriangleDistanceTree tree;
  tree.Build(corners, ids);
  std::vector<std::size_t> count(src.primitives.size(), 0);
  for (const PartTriangle& t : tris) ++count[static_cast<std::size_t>(t.primitive)];
  const std::size_t major =
      static_cast<std::size_t>(std::max_element(count.begin(), count.end()) - count.begin());
  const AssetPrimitive& mp = src.primitives[major];
  prim->material = mp.material;
  std::size_t uv_sets = mp.texcoords.size();
  for (const PartTriangle& t : tris) {
    uv_sets =
        std::min(uv_sets, src.primitives[static_cast<std::size_t>(t.primitive)].texcoords.size());
  }
  if (uv_sets < mp.texcoords.size() && notes != nullptr) {
    notes->push_back("mesh " + std::to_string(part.mesh) +
                     ": texture coordinate sets not shared by all its primitives were dropped");
  }
  prim->texcoords.assign(uv_sets, std::vector<glm::vec2>(n));
  const bool skinned = part.skin >= 0;
  if (skinned) {
    prim->joints.assign(1, std::vector<glm::u16vec4>(n));
    prim->weights.assign(1, std::vector<glm::vec4>(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    const ClosestPoint cp = tree.Query(x[i]);
    const PartTriangle& t = tris[static_cast<std::size_t>(cp.triangle)];
    const AssetPrimitive& sp = src.primitives[static_cast<std::size_t>(t.primitive)];
    for (std::size_t u = 0; u < uv_sets; ++u) {
      glm::dvec2 uv(0.0);
      for (int c = 0; c < 3; ++c) uv += cp.barycentric[c] * glm::dvec2(sp.texcoords[u][t.v[c]]);
      prim->texcoords[u][i] = glm::vec2(uv);
    }
    if (skinned) {
      BlendInfluences(VertexInfluences(sp, t.v[0]), VertexInfluences(sp, t.v[1]),
                      VertexInfluences(sp, t.v[2]), cp.barycentric, &prim->joints[0][i],
                      &prim->weights[0][i]);
    }
  }
}

}  // namespace

Status BuildLodAssetWithSources(const Character& ch, const CharacterExportOptions& options,
                                Asset* out, std::vector<std::string>* notes,
                                SurfaceSources* sources) {
  if (Status s = RequireSourceAsset(ch); !s.ok()) return s;
  if (options.level < 1 || options.level > 64) {
    return Status::InvalidInput("tessellation level must be in 1..64");
  }
  Asset a = ch.asset;
  Status s = KeepUnfittedTriangles(ch, &a);
  if (!s.ok()) return s;
  AddPlainSurfaceMeshes(ch, &a);
  if (sources != nullptr) {
    sources->assign(a.meshes.size(), {});
    for (std::size_t m = 0; m < a.meshes.size(); ++m) {
      (*sources)[m].resize(a.meshes[m].primitives.size());
    }
  }
  Index plain_mesh = static_cast<Index>(ch.asset.meshes.size());
  for (std::size_t k = 0; k < ch.parts.size(); ++k) {
    const CharacterPart& part = ch.parts[k];
    TessellationPattern pattern;
    std::vector<Vec3> x;
    AssetPrimitive prim;
    s = TessellatePart(ch, k, options, &pattern, &x, &prim);
    if (!s.ok()) return s;
    const Index mesh_index = part.mesh >= 0 ? part.mesh : plain_mesh++;
    if (part.mesh >= 0) TransferFromOriginal(ch, k, x, &prim, notes);
    a.meshes[static_cast<std::size_t>(mesh_index)].primitives.push_back(std::move(prim));
    if (sources != nullptr) {
      const std::size_t n = x.size();
      std::vector<VertexBinding> located(n);
      for (std::size_t i = 0; i < n; ++i) {
        located[i] = {static_cast<Index>(k), pattern.samples[i].face, pattern.samples[i].u,
                      pattern.samples[i].v};
      }
      (*sources)[static_cast<std::size_t>(mesh_index)].push_back(std::move(located));
    }
  }
  // Meshes left with no primitive at all are not valid glTF; none can occur unless a mesh had
  // only fitted triangles and no part, which fitting never produces.
  *out = std::move(a);
  return Status::Ok();
}

}  // namespace character

}  // namespace dermis
