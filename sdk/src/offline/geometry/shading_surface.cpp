// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Phong tessellation (Boubekeur and Alexa 2008, "Phong Tessellation", ACM TOG 27(5), Eq. 2-3)
// of a character's source mesh with its own shading normals; hard and boundary edges stay
// straight, so that it has no cracks (docs/characters.md).
#include "dermis/offline/geometry/shading_surface.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace dermis {

void ShadingSurface::Build(const PolygonMesh& mesh, const std::vector<Vec3>& corner_normals,
                           double shape, double max_move) {
  mesh_ = &mesh;
  shape_ = shape;
  curved_ = false;
  capped_ = 0;
  const std::size_t nf = static_cast<std::size_t>(mesh.num_faces());
  normals_.assign(3 * nf, Vec3(0.0));
  shaded_.assign(nf, 0);
  hard_.assign(3 * nf, 1);
  scale_.assign(3 * nf, 0.0);
  smooth_edges_.clear();
  if (corner_normals.size() != 3 * nf) return;
  for (std::size_t f = 0; f < nf; ++f) {
    if (mesh.face_size(static_cast<Index>(f)) != 3) continue;
    const Index* v = &mesh.face_vertices[mesh.face_offsets[static_cast<Index>(f)]];
    const Vec3 n = glm::cross(mesh.positions[v[1]] - mesh.positions[v[0]],
                              mesh.positions[v[2]] - mesh.positions[v[0]]);
    const double ln = glm::length(n);
    if (!(ln > 0.0)) continue;
    bool all = true;
    for (std::size_t k = 0; k < 3 && all; ++k) {
      const Vec3& cn = corner_normals[3 * f + k];
      const double lc = glm::length(cn);
      all = lc > 0.0 && std::isfinite(lc);
      normals_[3 * f + k] = all ? cn / lc : Vec3(0.0);
    }
    shaded_[f] = all ? 1 : 0;
    if (!all) std::fill(normals_.begin() + 3 * f, normals_.begin() + 3 * f + 3, Vec3(0.0));
  }
  // (a, b, face, corner opposite, shaded) per face edge, a < b, over every face (a face
  // without normals, without area or of another size counts too): an edge is curved where
  // exactly two faces meet, both shaded, with the same normals at both of its ends.
  std::vector<std::array<std::uint32_t, 5>> half;
  half.reserve(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[static_cast<Index>(f)]];
    const std::uint32_t size = static_cast<std::uint32_t>(mesh.face_size(static_cast<Index>(f)));
    for (std::uint32_t k = 0; k < size; ++k) {
      const std::uint32_t a = static_cast<std::uint32_t>(v[k]);
      const std::uint32_t b = static_cast<std::uint32_t>(v[(k + 1) % size]);
      // In a triangle the edge (k, k + 1) is opposite corner k + 2.
      half.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(f), (k + 2) % 3,
                      static_cast<std::uint32_t>(shaded_[f])});
    }
  }
  std::sort(half.begin(), half.end());
  auto normal_at = [&](std::uint32_t f, std::uint32_t vertex) {
    const Index* v = &mesh.face_vertices[mesh.face_offsets[static_cast<Index>(f)]];
    std::size_t k = 0;
    while (k < 2 && static_cast<std::uint32_t>(v[k]) != vertex) ++k;
    return normals_[3 * std::size_t{f} + k];
  };
  for (std::size_t i = 0; i < half.size();) {
    std::size_t j = i + 1;
    while (j < half.size() && half[j][0] == half[i][0] && half[j][1] == half[i][1]) ++j;
    if (j == i + 2 && half[i][4] && half[i + 1][4]) {
      const std::uint32_t f0 = half[i][2], f1 = half[i + 1][2];
      // The same stored normals (a renderer interpolates them as one): compared exactly, so
      // that both faces compute the edge's term from the same numbers.
      const bool smooth = normal_at(f0, half[i][0]) == normal_at(f1, half[i][0]) &&
                          normal_at(f0, half[i][1]) == normal_at(f1, half[i][1]);
      if (smooth) smooth_edges_.push_back({half[i][0], half[i][1]});
      if (smooth && shape > 0.0) {
        // The term at the edge's midpoint (w_k = w_l = 1/2), times the shape factor.
        const Vec3 &xa = mesh.positions[half[i][0]], &xb = mesh.positions[half[i][1]];
        const Vec3 &na = normal_at(f0, half[i][0]), &nb = normal_at(f0, half[i][1]);
        const double peak =
            0.25 * shape * glm::length(glm::dot(xb - xa, na) * na + glm::dot(xa - xb, nb) * nb);
        double scale = 1.0;
        if (max_move > 0.0 && peak > max_move) {
          scale = max_move / peak;
          ++capped_;
        }
        hard_[3 * std::size_t{f0} + half[i][3]] = 0;
        hard_[3 * std::size_t{f1} + half[i + 1][3]] = 0;
        scale_[3 * std::size_t{f0} + half[i][3]] = scale;
        scale_[3 * std::size_t{f1} + half[i + 1][3]] = scale;
        if (peak > 0.0) curved_ = true;
      }
    }
    i = j;
  }
}

Vec3 ShadingSurface::EdgeTerm(Index f, std::size_t c) const {
  const Index* v = &mesh_->face_vertices[mesh_->face_offsets[f]];
  const std::size_t fi = static_cast<std::size_t>(f);
  const std::size_t k = (c + 1) % 3, l = (c + 2) % 3;
  const Vec3 &xk = mesh_->positions[v[k]], &xl = mesh_->positions[v[l]];
  const Vec3 &nk = normals_[3 * fi + k], &nl = normals_[3 * fi + l];
  return glm::dot(xl - xk, nk) * nk + glm::dot(xk - xl, nl) * nl;
}

Vec3 ShadingSurface::Point(Index f, const double w[3]) const {
  const Index* v = &mesh_->face_vertices[mesh_->face_offsets[f]];
  const std::size_t fi = static_cast<std::size_t>(f);
  Vec3 p(0.0);
  const int n = std::min(3, static_cast<int>(mesh_->face_size(f)));
  for (int k = 0; k < n; ++k) p += w[k] * mesh_->positions[v[k]];
  if (!curved_ || !shaded_[fi]) return p;
  // Phong's point minus the flat one is a sum over the edges (k, l) of w_k w_l times a term of
  // that edge's ends alone: -((x_l - x_k).n_k) n_k - ((x_k - x_l).n_l) n_l. A hard edge's term
  // is left out, so that edge stays straight and the faces on either side meet.
  Vec3 move(0.0);
  for (std::size_t c = 0; c < 3; ++c) {
    if (hard_[3 * fi + c]) continue;
    const std::size_t k = (c + 1) % 3, l = (c + 2) % 3;
    move -= scale_[3 * fi + c] * w[k] * w[l] * EdgeTerm(f, c);
  }
  return p + shape_ * move;
}

Vec3 ShadingSurface::Normal(Index f, const double w[3]) const {
  const std::size_t fi = static_cast<std::size_t>(f);
  if (!shaded_[fi]) return Vec3(0.0);
  const Vec3 n =
      w[0] * normals_[3 * fi] + w[1] * normals_[3 * fi + 1] + w[2] * normals_[3 * fi + 2];
  const double ln = glm::length(n);
  return ln > 1e-12 && std::isfinite(ln) ? n / ln : Vec3(0.0);
}

double ShadingSurface::NormalDeviation() const {
  // Each face split 4 x 4 into 16 triangles of equal area, one point at each one's centroid.
  constexpr int kSplit = 4;
  double sum = 0.0, area = 0.0;
  for (Index f = 0; f < mesh_->num_faces(); ++f) {
    const std::size_t fi = static_cast<std::size_t>(f);
    if (!shaded_[fi]) continue;
    const Index* v = &mesh_->face_vertices[mesh_->face_offsets[f]];
    const Vec3 &x0 = mesh_->positions[v[0]], &x1 = mesh_->positions[v[1]],
               &x2 = mesh_->positions[v[2]];
    const double a = 0.5 * glm::length(glm::cross(x1 - x0, x2 - x0)) / (kSplit * kSplit);
    for (int i = 0; i < kSplit; ++i) {
      for (int j = 0; i + j < kSplit; ++j) {
        for (int down = 0; down < 2 && i + j + down < kSplit; ++down) {
          const double off = down ? 2.0 / 3.0 : 1.0 / 3.0;
          const double w[3] = {(i + off) / kSplit, (j + off) / kSplit,
                               1.0 - (i + off) / kSplit - (j + off) / kSplit};
          // The surface's derivatives along w0 and w1 (w2 = 1 - w0 - w1): the flat part
          // x0 - x2 and x1 - x2, and each curved edge's w_k w_l differentiated.
          const double du[3] = {1.0, 0.0, -1.0}, dv[3] = {0.0, 1.0, -1.0};
          Vec3 pu = x0 - x2, pv = x1 - x2;
          if (curved_) {
            for (std::size_t c = 0; c < 3; ++c) {
              if (hard_[3 * fi + c]) continue;
              const std::size_t k = (c + 1) % 3, l = (c + 2) % 3;
              const Vec3 term = shape_ * scale_[3 * fi + c] * EdgeTerm(f, c);
              pu -= (du[k] * w[l] + w[k] * du[l]) * term;
              pv -= (dv[k] * w[l] + w[k] * dv[l]) * term;
            }
          }
          const Vec3 shading =
              w[0] * normals_[3 * fi] + w[1] * normals_[3 * fi + 1] + w[2] * normals_[3 * fi + 2];
          const Vec3 own = glm::cross(pu, pv);
          const double lo = glm::length(own), ls = glm::length(shading);
          if (!(lo > 0.0) || !(ls > 0.0)) continue;
          // The angle between the two lines: Phong's surface is the same for a negated normal,
          // and a part whose normals point against its winding is measured as one that does not.
          const double cosine = std::abs(glm::dot(own, shading)) / (lo * ls);
          sum += a * std::acos(std::min(1.0, cosine));
          area += a;
        }
      }
    }
  }
  return area > 0.0 ? sum / area : 0.0;
}

}  // namespace dermis
