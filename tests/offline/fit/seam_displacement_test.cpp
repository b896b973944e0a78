// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/fit/seam_displacement.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <vector>

#include "dermis/offline/build/domain_builder.h"
#include "dermis/surface/surface_evaluator.h"

using namespace dermis;

namespace {

// Two 3 x 3 grids of unit quads side by side in z = 0 (x in [0, 3] and [3, 6], y in [0, 3]),
// with their own vertices along x = 3: a sheet cut open there (docs/characters.md, "Hard edges
// cut open"). seam: the cut's vertices, 1 inside the cut, 2 at its ends on the outer boundary.
PolygonMesh CutSheet(std::vector<std::uint8_t>* seam) {
  PolygonMesh m;
  m.source_name = "cut sheet";
  seam->clear();
  for (int side = 0; side < 2; ++side) {
    const Index base = static_cast<Index>(m.positions.size());
    for (int j = 0; j <= 3; ++j) {
      for (int i = 0; i <= 3; ++i) {
        m.positions.push_back({3.0 * side + i, static_cast<double>(j), 0.0});
        const bool on_cut = side == 0 ? i == 3 : i == 0;
        seam->push_back(on_cut ? (j == 0 || j == 3 ? 2 : 1) : 0);
      }
    }
    auto id = [&](int i, int j) { return base + static_cast<Index>(j * 4 + i); };
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        m.AddFace({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  return m;
}

// Additive data: every chart 5 levels, 0..3 dense with values from a fixed recurrence, level 4
// sparse (every seventh node).
BsplineDisplacementData Levels(Index charts) {
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>(static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5) * 0.01f;
  };
  for (Index c = 0; c < charts; ++c) {
    d.half_extent.push_back(1.2);
    d.num_levels.push_back(5);
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
    for (int k = 0; k < 5; ++k) {
      const std::int64_t size = BsplineLatticeSize(k);
      if (k < 4) {
        d.level_counts.push_back(static_cast<std::int32_t>(size));
        for (std::int64_t n = 0; n < size; ++n) d.values.push_back(next());
      } else {
        std::int32_t count = 0;
        for (std::int64_t n = 0; n < size; n += 7, ++count) {
          d.nodes.push_back(static_cast<std::uint32_t>(n));
          d.values.push_back(next());
        }
        d.level_counts.push_back(count);
      }
    }
  }
  d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  return d;
}

}  // namespace

TEST_CASE("seam displacement: the displaced sides of a cut meet, the rest is untouched") {
  std::vector<std::uint8_t> seam;
  const PolygonMesh sheet = CutSheet(&seam);
  ControlSurface cs;
  REQUIRE(BuildControlSurface(sheet, DomainOptions{}, &cs, &seam).ok());
  const ManifoldDomain& domain = *cs.domain;
  const BsplineDisplacementData before = Levels(domain.num_vertices());
  BsplineDisplacementData data = before;
  std::int64_t added = 0;
  REQUIRE(ZeroDisplacementOnSeams(domain, seam, &data, &added).ok());
  CHECK(added > 0);  // the sparse level gains the nodes its change needs
  Status s;
  auto zeroed = BsplineDisplacement::Create(data, domain.num_vertices(), &s);
  auto original = BsplineDisplacement::Create(before, domain.num_vertices(), &s);
  REQUIRE(zeroed);
  REQUIRE(original);
  // Along the cut (x = 3) both sides' displaced surfaces are the domain surface, to float
  // rounding of coefficients of about 5e-3; before, they were apart.
  const MeshTopology& topo = domain.topology();
  double gap = 0.0, gap_before = 0.0;
  for (Index f = 0; f < topo.num_faces(); ++f) {
    for (int k = 0; k < 4; ++k) {
      const Index h = topo.face_offset(f) + k;
      if (topo.twin(h) != kInvalidIndex) continue;
      const Vec3 a = cs.control.positions[static_cast<std::size_t>(topo.halfedge_origin(h))];
      const Vec3 b = cs.control.positions[static_cast<std::size_t>(topo.halfedge_dest(h))];
      if (a.x != 3.0 || b.x != 3.0) continue;
      for (int i = 0; i <= 8; ++i) {
        const Vec2 uv = CornerToFace(k, Vec2(i / 8.0, 0.0));
        SurfacePoint plain, with, was;
        REQUIRE(EvaluateSurface(domain, cs.patches.data(), nullptr, f, uv, &plain));
        REQUIRE(EvaluateSurface(domain, cs.patches.data(), zeroed.get(), f, uv, &with));
        REQUIRE(EvaluateSurface(domain, cs.patches.data(), original.get(), f, uv, &was));
        gap = std::max(gap, glm::length(with.position - plain.position));
        gap_before = std::max(gap_before, glm::length(was.position - plain.position));
      }
    }
  }
  INFO("displacement on the cut: " << gap << " (before: " << gap_before << ")");
  CHECK(gap < 1e-8);
  CHECK(gap_before > 1e-3);
  // Charts off the cut keep every coefficient; so does every node of a cut chart that no
  // boundary ray's basis reaches (rows far from the x-axis of its half-disk chart).
  const BsplineDisplacementData& after = zeroed->data();
  std::size_t lc = 0;
  for (Index c = 0; c < domain.num_vertices(); ++c) {
    const bool on = seam[static_cast<std::size_t>(c)] != 0;
    for (int k = 0; k < 4; ++k, ++lc) {
      const int m = 1 << k, stride = m + 3;
      const std::int64_t base = before.offsets[static_cast<std::size_t>(c)];
      std::int64_t offset = 0;
      for (int l = 0; l < k; ++l) offset += BsplineLatticeSize(l);
      for (int j = 0; j < stride; ++j) {
        for (int i = 0; i < stride; ++i) {
          const std::int64_t n = base + offset + j * stride + i;
          const std::int64_t n2 =
              after.offsets[static_cast<std::size_t>(c)] + offset + j * stride + i;
          // The x-axis (y = 0) lies at lattice row m / 2; its basis reaches 4 rows from there.
          const bool near_axis = j >= m / 2 - 1 && j <= m / 2 + 3;
          const bool corner = domain.chart(c).kind != VertexKind::kCrease;
          if (!on || (!near_axis && !corner)) {
            CHECK(after.values[static_cast<std::size_t>(n2)] ==
                  before.values[static_cast<std::size_t>(n)]);
          }
        }
      }
    }
    ++lc;  // the sparse level
  }
  // Merged data, or a chart count that is not the domain's, is refused.
  BsplineDisplacementData merged = before;
  merged.form = BsplineLevelForm::kMerged;
  CHECK(ZeroDisplacementOnSeams(domain, seam, &merged).code() == StatusCode::kInvalidInput);
  BsplineDisplacementData fewer = before;
  fewer.num_levels.pop_back();
  CHECK(ZeroDisplacementOnSeams(domain, seam, &fewer).code() == StatusCode::kInvalidInput);
}
