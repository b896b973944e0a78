// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Tangent frames of a bound output (docs/engine-integration.md, "Tangents").
//
// A normal map needs, per vertex, the tangent of the texture's u direction (and the
// handedness of the bitangent). The bound output reproduces the source's vertices on the
// displaced surface, so the bind tangent T of each vertex (the source's TANGENT, else one made
// from TEXCOORD_0 below) is expressed once, at the rest pose, in the surface's own frame:
// T projected onto the tangent plane equals a dS/du + b dS/dv, with dS/du and dS/dv the
// derivatives of the displaced surface (Eq. 3-4) in the face coordinates the sample lies in.
// Each frame the kernel re-expresses it with the posed derivatives (a dS/du + b dS/dv, one
// Gram-Schmidt step against the posed normal, normalised), so the tangent follows the surface's
// stretch and twist exactly as the texture does, and at the rest pose it is T made orthogonal
// to the surface normal: the source's tangent itself wherever the source's normal agrees with
// the surface (MikkTSpace tangents from an exporter are kept).
//
// Without TANGENT the tangent comes from the texture coordinates, per triangle the direction
// of increasing u (the classic per-triangle solve, summed over the vertex's triangles; not a
// byte-exact MikkTSpace, which no Debian package provides), and w is the sign that makes
// cross(n, t) * w point towards decreasing glTF v (up in the image), the convention of glTF
// normal textures (three.js negates MikkTSpace's sign for glTF for the same reason).
#include "runtime/tangent_frames.h"

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "dermis/runtime/runtime.h"

namespace dermis {
namespace {

// Per-vertex (sum of u directions, sum of v directions) of a triangle-list primitive from
// texture coordinate set 0. Empty if the primitive is not a triangle list.
bool UvDirections(const AssetPrimitive& prim, std::vector<glm::dvec3>* du,
                  std::vector<glm::dvec3>* dv) {
  if (prim.mode != PrimitiveMode::kTriangles || prim.texcoords.empty()) return false;
  const std::size_t n = prim.positions.size();
  const std::vector<glm::vec2>& uv = prim.texcoords[0];
  du->assign(n, glm::dvec3(0.0));
  dv->assign(n, glm::dvec3(0.0));
  const std::size_t corners = prim.indices.empty() ? n : prim.indices.size();
  for (std::size_t t = 0; t + 2 < corners; t += 3) {
    std::size_t i[3];
    for (int k = 0; k < 3; ++k) {
      i[k] = prim.indices.empty()
                 ? t + static_cast<std::size_t>(k)
                 : static_cast<std::size_t>(prim.indices[t + static_cast<std::size_t>(k)]);
      if (i[k] >= n) return false;
    }
    const glm::dvec3 e1 = glm::dvec3(prim.positions[i[1]]) - glm::dvec3(prim.positions[i[0]]);
    const glm::dvec3 e2 = glm::dvec3(prim.positions[i[2]]) - glm::dvec3(prim.positions[i[0]]);
    const glm::dvec2 w1 = glm::dvec2(uv[i[1]]) - glm::dvec2(uv[i[0]]);
    const glm::dvec2 w2 = glm::dvec2(uv[i[2]]) - glm::dvec2(uv[i[0]]);
    const double det = w1.x * w2.y - w2.x * w1.y;
    if (!(std::fabs(det) > 1e-20) || !std::isfinite(det)) continue;  // no uv area
    // e1 = w1.x Pu + w1.y Pv, e2 = w2.x Pu + w2.y Pv solved for Pu, Pv.
    const glm::dvec3 pu = (e1 * w2.y - e2 * w1.y) / det;
    const glm::dvec3 pv = (e2 * w1.x - e1 * w2.x) / det;
    // Weighted by the triangle's area (|e1 x e2|) over its uv area, i.e. a unit-free sum.
    const double weight = glm::length(glm::cross(e1, e2));
    const double pl = glm::length(pu), vl = glm::length(pv);
    for (int k = 0; k < 3; ++k) {
      if (pl > 0.0) (*du)[i[k]] += pu * (weight / pl);
      if (vl > 0.0) (*dv)[i[k]] += pv * (weight / vl);
    }
  }
  return true;
}

}  // namespace

Status BuildTangentFrames(const RuntimeCharacter& character, std::size_t part,
                          const EvaluationPlan& plan, std::vector<float>* frames) {
  const Character& ch = character.character();
  const std::string name = ch.asset.source + ", part " + std::to_string(part);
  const std::vector<BoundVertexRef>& refs = character.bound_vertices(part);
  const std::size_t count = plan.num_samples();
  if (refs.size() != count) {
    return Status::InvalidInput(name + ": tangents need the part's bound output");
  }
  // The rest surface's normals and face derivatives at every vertex, by the kernel itself.
  const DisplacedSurface& surface = ch.parts[part].surface;
  const std::size_t nc = surface.rest_positions.size();
  std::vector<LocalPatch> patches(nc);
  surface.domain->FitPatches(surface.rest_positions.data(), patches.data());
  std::vector<float> packed(nc * kPackedPatchStride);
  PackPatches(patches.data(), nc, packed.data());
  std::vector<float> pos(3 * count), nrm(3 * count), der(6 * count);
  PlanOutputBuffers ob;
  ob.positions = pos.data();
  ob.normals = nrm.data();
  ob.derivatives = der.data();
  if (count > 0 && !EvaluatePlan(plan, packed.data(), 0, plan.num_blocks(), ob)) {
    return Status::Internal(name + ": evaluating the rest pose failed");
  }
  std::map<std::pair<Index, Index>, std::pair<std::vector<glm::dvec3>, std::vector<glm::dvec3>>>
      uv_dirs;
  frames->assign(4 * count, 0.0f);
  for (std::size_t i = 0; i < count; ++i) {
    const BoundVertexRef& r = refs[i];
    const std::string where =
        name + ": mesh " + std::to_string(r.mesh) + " primitive " + std::to_string(r.primitive);
    if (r.mesh < 0 || static_cast<std::size_t>(r.mesh) >= ch.asset.meshes.size() ||
        r.primitive < 0 ||
        static_cast<std::size_t>(r.primitive) >=
            ch.asset.meshes[static_cast<std::size_t>(r.mesh)].primitives.size()) {
      return Status::InvalidInput(where + ": the character carries no such source primitive");
    }
    const AssetPrimitive& prim = ch.asset.meshes[static_cast<std::size_t>(r.mesh)]
                                     .primitives[static_cast<std::size_t>(r.primitive)];
    const std::size_t v = static_cast<std::size_t>(r.vertex);
    if (r.vertex < 0 || v >= prim.positions.size()) {
      return Status::InvalidInput(where + ": vertex " + std::to_string(r.vertex) + " out of range");
    }
    const glm::dvec3 n(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
    const glm::dvec3 su(der[6 * i], der[6 * i + 1], der[6 * i + 2]);
    const glm::dvec3 sv(der[6 * i + 3], der[6 * i + 4], der[6 * i + 5]);
    glm::dvec3 t(0.0);
    double w = 1.0;
    if (!prim.tangents.empty()) {
      t = glm::dvec3(prim.tangents[v]);
      w = prim.tangents[v].w < 0.0f ? -1.0 : 1.0;
    } else {
      auto key = std::make_pair(r.mesh, r.primitive);
      auto it = uv_dirs.find(key);
      if (it == uv_dirs.end()) {
        std::vector<glm::dvec3> du, dv;
        if (!UvDirections(prim, &du, &dv)) {
          return Status::InvalidInput(
              where +
              ": no tangents and no texture coordinates of a triangle list to make them "
              "from");
        }
        it = uv_dirs.emplace(key, std::make_pair(std::move(du), std::move(dv))).first;
      }
      t = it->second.first[v];
      // cross(n, t) * w towards decreasing v (the image's up): glTF's normal-texture convention.
      w = glm::dot(glm::cross(n, t), it->second.second[v]) > 0.0 ? -1.0 : 1.0;
    }
    // t on the tangent plane as a su + b sv (least squares through the 2 x 2 Gram system).
    glm::dvec3 tp = t - n * glm::dot(n, t);
    const double tl = glm::length(tp);
    tp = tl > 0.0 ? tp / tl : glm::dvec3(0.0);
    const double uu = glm::dot(su, su), uvd = glm::dot(su, sv), vv = glm::dot(sv, sv);
    const double tu = glm::dot(tp, su), tv = glm::dot(tp, sv);
    const double det = uu * vv - uvd * uvd;
    double a = 0.0, b = 0.0;  // (0, 0): the kernel's fallback (any unit vector orthogonal to n)
    if (det > 1e-12 * uu * vv && det > 0.0) {
      a = (tu * vv - tv * uvd) / det;
      b = (tv * uu - tu * uvd) / det;
    } else if (uu > 0.0) {
      a = tu / uu;
    }
    if (!std::isfinite(a) || !std::isfinite(b)) a = b = 0.0;
    (*frames)[4 * i] = static_cast<float>(a);
    (*frames)[4 * i + 1] = static_cast<float>(b);
    (*frames)[4 * i + 2] = static_cast<float>(w);
  }
  return Status::Ok();
}

}  // namespace dermis
