// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/offline/fit/seam_displacement.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include "dermis/offline/build/crease_chains.h"
#include "dermis/offline/build/crease_cut.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/build/reference_surface.h"
#include "dermis/offline/fit/surface_fit.h"
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

TEST_CASE("seam displacement: a fit cut open along a fold keeps its two sides together") {
  // FitSurface with FitOptions::cut_control_mesh (what FitCharacter sets on a part with hard
  // creases): a sheet folded along x = 0 (z = 0.6 |x| + a ripple the displacement has to
  // carry), 24 x 24 quads, its control mesh keeping the fold and cut open along it. The two
  // fitted sides, displacement included, meet along the whole fold; no control-vertex fit
  // runs on the cut mesh; the MBA displacement is refused with a cut.
  PolygonMesh sheet;
  sheet.source_name = "folded sheet";
  const int n = 24;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -1.0 + 2.0 * i / n, y = 2.0 * j / n;
      sheet.positions.push_back({x, y, 0.6 * std::abs(x) + 0.01 * std::sin(5.0 * y) * x * x});
    }
  }
  auto id = [&](int i, int j) { return static_cast<Index>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      sheet.AddFace({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  std::vector<std::uint32_t> triangles;
  for (Index f = 0; f < sheet.num_faces(); ++f) {
    const Index* v = &sheet.face_vertices[static_cast<std::size_t>(sheet.face_offsets[f])];
    for (int k : {0, 1, 2, 0, 2, 3}) triangles.push_back(static_cast<std::uint32_t>(v[k]));
  }
  auto ref = std::make_shared<ReferenceSurface>();
  REQUIRE(ref->Build(sheet.positions, triangles, "folded sheet").ok());
  auto chains = std::make_shared<CreaseChains>();
  chains->Build(*ref, 30.0, 80.0);
  REQUIRE(chains->num_chains() == 1);
  FitInput input;
  input.points = sheet.positions;
  input.mesh = &sheet;
  FitOptions options;
  options.threads = 2;
  options.holdout = 0.0;
  options.control_vertices = 120;
  options.remesh.crease_angle_deg = 30.0;
  options.control_fit_iterations = 2;  // asked for, and not run on the cut mesh
  auto cut = std::make_shared<CreaseCutResult>();
  options.cut_control_mesh = [ref, chains, cut](PolygonMesh* control,
                                                std::vector<std::uint8_t>* seam) {
    Status s = CutAlongCreases(*chains, 1e-9, control, cut.get());
    if (s.ok()) *seam = cut->seam;
    return s;
  };
  FittedSurface fitted;
  FitReport report;
  REQUIRE(FitSurface(input, options, &fitted, &report).ok());
  CHECK(cut->cut_edges > 0);
  CHECK(report.control_fit_rounds == 0);
  const ManifoldDomain& domain = *fitted.surface.domain;
  const MeshTopology& topo = domain.topology();
  const std::vector<Vec3>& x = fitted.surface.control.positions;
  using Key = std::array<double, 3>;
  auto key = [&](Index v) {
    const Vec3& p = x[static_cast<std::size_t>(v)];
    return Key{p.x, p.y, p.z};
  };
  std::map<std::pair<Key, Key>, std::vector<Index>> sides;
  for (Index h = 0; h < topo.num_halfedges(); ++h) {
    if (topo.twin(h) != kInvalidIndex) continue;
    Key a = key(topo.halfedge_origin(h)), b = key(topo.halfedge_dest(h));
    if (b < a) std::swap(a, b);
    sides[{a, b}].push_back(h);
  }
  double gap = 0.0, displaced = 0.0;
  int pairs = 0;
  for (const auto& [ends, hs] : sides) {
    if (hs.size() != 2) continue;
    ++pairs;
    for (int i = 1; i < 8; ++i) {
      Vec3 p[2], q[2];
      for (int s = 0; s < 2; ++s) {
        const Index h = hs[static_cast<std::size_t>(s)];
        const Index f = topo.halfedge_face(h);
        const int corner = static_cast<int>(h - topo.face_offset(f));
        const double t = key(topo.halfedge_origin(h)) == ends.first ? i / 8.0 : 1.0 - i / 8.0;
        SurfacePoint with, without;
        const Vec2 uv = CornerToFace(corner, Vec2(t, 0.0));
        REQUIRE(EvaluateSurface(domain, fitted.surface.patches.data(), fitted.displacement.get(), f,
                                uv, &with));
        REQUIRE(EvaluateSurface(domain, fitted.surface.patches.data(), nullptr, f, uv, &without));
        p[s] = with.position;
        q[s] = without.position;
      }
      gap = std::max(gap, glm::length(p[0] - p[1]));
      displaced = std::max(displaced, glm::length(p[0] - q[0]));
    }
  }
  INFO(pairs << " cut edges: the sides apart by at most " << gap << ", displaced by " << displaced);
  CHECK(pairs == cut->cut_edges);
  CHECK(gap < 1e-9);
  CHECK(displaced < 1e-9);
  // The fit still follows the ripple away from the fold.
  CHECK(report.error.max < 0.05);
  options.displacement.method = DisplacementMethod::kMba;
  CHECK(FitSurface(input, options, &fitted, &report).code() == StatusCode::kInvalidInput);
}
