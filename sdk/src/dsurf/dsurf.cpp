// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Surface .dsurf files (docs/file-format.md): version 1 with merged dense displacement
// lattices, version 3 with sparse per-level corrections; explicit little-endian fields,
// bounds-checked parsing; the container (magic, version, checksum) is dsurf_container.cpp's.
#include "dermis/dsurf/dsurf.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/byte_stream.h"
#include "dsurf/dsurf_container.h"

namespace dermis {
namespace {

// Unsigned LEB128: 7 bits per byte, low bits first, the high bit set on every byte but the
// last.
void WriteVarint(std::uint32_t v, ByteWriter* w) {
  while (v >= 0x80) {
    w->U8(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  w->U8(static_cast<std::uint8_t>(v));
}

std::uint32_t ReadVarint(ByteReader* r, const char* what) {
  std::uint64_t v = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    const std::uint8_t b = r->U8(what);
    if (!r->ok()) return 0;
    v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) {
      if (v > 0xffffffffull) break;
      return static_cast<std::uint32_t>(v);
    }
  }
  r->Fail(std::string("malformed ") + what);
  return 0;
}

// Version 3's displacement (docs/file-format.md): half extents, level counts, each level's
// coefficient count, the node runs of the sparse levels, the coefficients.
void WriteSparseLevels(const BsplineDisplacementData& b, ByteWriter* w) {
  for (double r : b.half_extent) w->F64(r);
  for (std::uint8_t l : b.num_levels) w->U8(l);
  for (std::int32_t c : b.level_counts) w->U32(static_cast<std::uint32_t>(c));
  std::size_t g = 0, node = 0;
  for (std::uint8_t levels : b.num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      const auto count = static_cast<std::size_t>(b.level_counts[g]);
      if (static_cast<std::int64_t>(count) == BsplineLatticeSize(k)) continue;  // dense
      // Runs of consecutive node indices: (first, length).
      std::vector<std::uint32_t> runs;
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t n = b.nodes[node + i];
        if (!runs.empty() && runs[runs.size() - 2] + runs.back() == n) {
          ++runs.back();
        } else {
          runs.push_back(n);
          runs.push_back(1);
        }
      }
      node += count;
      // Each run as (gap after the previous run's end, length - 1).
      WriteVarint(static_cast<std::uint32_t>(runs.size() / 2), w);
      std::uint32_t end = 0;
      for (std::size_t i = 0; i < runs.size(); i += 2) {
        WriteVarint(runs[i] - end, w);
        WriteVarint(runs[i + 1] - 1, w);
        end = runs[i] + runs[i + 1];
      }
    }
  }
  for (float x : b.values) w->F32(x);
}

// Reads version 3's displacement for nv charts into *d; errors go to r.
void ReadSparseLevels(ByteReader* r, std::uint32_t nv, BsplineDisplacementData* d) {
  d->form = BsplineLevelForm::kAdditive;
  if (!r->Need(nv, 8 + 1, "displacement charts")) return;
  d->half_extent.resize(nv);
  for (double& x : d->half_extent) x = r->F64("half extent");
  d->num_levels.resize(nv);
  std::uint64_t total_levels = 0;
  for (std::uint8_t& l : d->num_levels) {
    l = r->U8("level count");
    if (l > kMaxBsplineLevels) {
      r->Fail("a chart has " + std::to_string(l) + " displacement levels, at most " +
              std::to_string(kMaxBsplineLevels));
      return;
    }
    total_levels += l;
  }
  if (!r->Need(total_levels, 4, "level coefficient counts")) return;
  d->level_counts.resize(static_cast<std::size_t>(total_levels));
  std::uint64_t total = 0;
  std::size_t g = 0;
  for (std::uint8_t levels : d->num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      const std::uint32_t c = r->U32("level coefficient count");
      if (c > static_cast<std::uint64_t>(BsplineLatticeSize(k))) {
        r->Fail("a level-" + std::to_string(k) + " lattice has " + std::to_string(c) +
                " coefficients, more than its " + std::to_string(BsplineLatticeSize(k)) + " nodes");
        return;
      }
      d->level_counts[g] = static_cast<std::int32_t>(c);
      total += c;
    }
  }
  // Each coefficient takes 4 bytes: refuse counts the file cannot hold before allocating.
  if (!r->Need(total, 4, "displacement coefficients")) return;
  g = 0;
  for (std::uint8_t levels : d->num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      const auto count = static_cast<std::uint64_t>(d->level_counts[g]);
      const auto size = static_cast<std::uint64_t>(BsplineLatticeSize(k));
      if (count == size) continue;
      const std::uint32_t nruns = ReadVarint(r, "node run count");
      if (!r->Need(nruns, 2, "node runs")) return;
      std::uint64_t covered = 0, next = 0;
      for (std::uint32_t i = 0; i < nruns && r->ok(); ++i) {
        const std::uint64_t first = next + ReadVarint(r, "node run gap");
        const std::uint64_t length = std::uint64_t{ReadVarint(r, "node run length")} + 1;
        if (!r->ok()) return;
        if (first + length > size || covered + length > count) {
          r->Fail("node runs of a level-" + std::to_string(k) +
                  " lattice leave the lattice or exceed its coefficient count");
          return;
        }
        for (std::uint64_t n = first; n < first + length; ++n) {
          d->nodes.push_back(static_cast<std::uint32_t>(n));
        }
        covered += length;
        next = first + length;
      }
      if (covered != count) {
        r->Fail("node runs of a level-" + std::to_string(k) + " lattice cover " +
                std::to_string(covered) + " nodes, not its " + std::to_string(count) +
                " coefficients");
        return;
      }
    }
  }
  d->offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
  g = 0;
  for (std::uint32_t c = 0; c < nv; ++c) {
    std::int64_t chart = 0;
    for (int k = 0; k < d->num_levels[c]; ++k, ++g) chart += d->level_counts[g];
    d->offsets[c + 1] = d->offsets[c] + chart;
  }
  if (!r->Need(total, 4, "displacement coefficients")) return;
  d->values.resize(static_cast<std::size_t>(total));
  for (float& x : d->values) x = r->F32("coefficient");
}

}  // namespace

std::string SerializeDsurf(const ManifoldDomain& domain, const Vec3* rest_positions,
                           const BsplineDisplacement* displacement, std::int64_t data_points) {
  const DomainData& d = domain.data();
  const MeshTopology& topo = domain.topology();
  const bool sparse = displacement && displacement->data().form == BsplineLevelForm::kAdditive;
  ByteWriter w;
  dsurf::WriteHeader(sparse ? kSparseDsurfVersion : kDsurfVersion, &w);
  w.U8(static_cast<std::uint8_t>(d.options.chart_type));
  w.U8(static_cast<std::uint8_t>(d.options.blend_type));
  w.F64(d.options.blend_lb);
  const auto nv = static_cast<std::uint32_t>(topo.num_vertices());
  const auto nf = static_cast<std::uint32_t>(topo.num_faces());
  w.U32(nv);
  w.U32(nf);
  for (std::uint32_t v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) w.F64(rest_positions[v][c]);
  }
  for (std::uint32_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 4; ++k) w.I32(topo.face_vertex(static_cast<Index>(f), k));
  }
  for (VertexKind k : d.vertex_kind) w.U8(static_cast<std::uint8_t>(k));
  w.U32(static_cast<std::uint32_t>(d.operator_offsets.size() - 1));
  for (Index o : d.operator_offsets) w.I32(o);
  for (double x : d.operator_values) w.F64(x);
  for (Index o : d.vertex_operator) w.I32(o);
  w.U8(displacement ? 1 : 0);
  if (displacement && !sparse) {
    const BsplineDisplacementData& b = displacement->data();
    for (double r : b.half_extent) w.F64(r);
    for (std::uint8_t l : b.num_levels) w.U8(l);
    for (std::int64_t o : b.offsets) w.I64(o);
    for (float x : b.values) w.F32(x);
  }
  if (sparse) {
    WriteSparseLevels(displacement->data(), &w);
    w.U64(static_cast<std::uint64_t>(std::max<std::int64_t>(data_points, 0)));
  }
  return dsurf::Finish(&w);
}

Status ParseDsurf(std::string_view bytes, const std::string& name, DisplacedSurface* out) {
  dsurf::Contents file;
  Status s = dsurf::Open(bytes, name, &file);
  if (!s.ok()) return s;
  if (!IsSurfaceDsurfVersion(file.version)) {
    return Status::InvalidInput(name + ": a version " + std::to_string(file.version) +
                                " .dsurf is a character, not a plain surface");
  }
  ByteReader r = dsurf::BodyReader(file, name);
  return dsurf::ReadSurfaceBody(&r, file.version, out);
}

namespace dsurf {

Status ReadSurfaceBody(ByteReader* reader, std::uint32_t version, DisplacedSurface* out) {
  ByteReader& r = *reader;
  const std::string& name = r.name();
  DomainData data;
  const std::uint8_t chart = r.U8("chart type"), blend = r.U8("blend type");
  if (chart > 2) r.Fail("unknown chart type " + std::to_string(chart));
  if (blend > 1) r.Fail("unknown blend type " + std::to_string(blend));
  data.options.chart_type = static_cast<ChartType>(chart);
  data.options.blend_type = static_cast<BlendType>(blend);
  data.options.blend_lb = r.F64("blend lb");
  const std::uint32_t nv = r.U32("vertex count"), nf = r.U32("face count");
  if (r.ok() && (nv > static_cast<std::uint32_t>(std::numeric_limits<Index>::max()) ||
                 nf > static_cast<std::uint32_t>(std::numeric_limits<Index>::max() / 4))) {
    r.Fail("vertex or face count too large");
  }
  std::vector<Vec3> positions;
  if (r.Need(nv, 24, "control positions")) {
    positions.resize(nv);
    for (Vec3& p : positions) {
      for (int c = 0; c < 3; ++c) p[c] = r.F64("position");
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        r.Fail("a control position is not finite");
      }
    }
  }
  std::vector<Index> quads;
  if (r.Need(nf, 16, "quads")) {
    quads.resize(static_cast<std::size_t>(nf) * 4);
    for (Index& q : quads) q = r.I32("quad");
  }
  if (r.Need(nv, 1, "vertex kinds")) {
    data.vertex_kind.resize(nv);
    for (VertexKind& k : data.vertex_kind) {
      const std::uint8_t v = r.U8("vertex kind");
      if (v > 3) r.Fail("unknown vertex kind " + std::to_string(v));
      k = static_cast<VertexKind>(v);
    }
  }
  const std::uint32_t nops = r.U32("operator count");
  if (r.Need(static_cast<std::uint64_t>(nops) + 1, 4, "operator offsets")) {
    data.operator_offsets.resize(static_cast<std::size_t>(nops) + 1);
    for (Index& o : data.operator_offsets) o = r.I32("operator offset");
  }
  const std::int64_t nvalues = r.ok() ? data.operator_offsets.back() : 0;
  if (r.ok() && nvalues < 0) r.Fail("negative operator size");
  if (r.Need(static_cast<std::uint64_t>(nvalues), 8, "operator values")) {
    data.operator_values.resize(static_cast<std::size_t>(nvalues));
    for (double& x : data.operator_values) x = r.F64("operator value");
  }
  if (r.Need(nv, 4, "vertex operators")) {
    data.vertex_operator.resize(nv);
    for (Index& o : data.vertex_operator) o = r.I32("vertex operator");
  }
  const std::uint8_t has_displacement = r.U8("displacement flag");
  BsplineDisplacementData disp;
  if (r.ok() && has_displacement > 1) r.Fail("bad displacement flag");
  if (r.ok() && has_displacement == 1 && version == kSparseDsurfVersion) {
    ReadSparseLevels(&r, nv, &disp);
  } else if (r.ok() && has_displacement == 1) {
    if (r.Need(nv, 8 + 1 + 8, "displacement charts")) {
      disp.half_extent.resize(nv);
      for (double& x : disp.half_extent) x = r.F64("half extent");
      disp.num_levels.resize(nv);
      for (std::uint8_t& l : disp.num_levels) l = r.U8("level count");
      disp.offsets.resize(static_cast<std::size_t>(nv) + 1);
      for (std::int64_t& o : disp.offsets) o = r.I64("lattice offset");
    }
    const std::int64_t ncoeff = r.ok() ? disp.offsets.back() : 0;
    if (r.ok() && ncoeff < 0) r.Fail("negative coefficient count");
    if (r.Need(static_cast<std::uint64_t>(ncoeff), 4, "displacement coefficients")) {
      disp.values.resize(static_cast<std::size_t>(ncoeff));
      for (float& x : disp.values) x = r.F32("coefficient");
    }
  }
  std::int64_t data_points = 0;
  if (version == kSparseDsurfVersion) {
    data_points = static_cast<std::int64_t>(r.U64("data points"));
    if (r.ok() && data_points < 0) r.Fail("negative data point count");
  }
  Status s = CheckEnd(r);
  if (!s.ok()) return s;
  s = MeshTopology::BuildQuads(static_cast<Index>(nv), quads, &data.topology);
  if (!s.ok()) return s.WithContext(name);
  DisplacedSurface result;
  result.domain = ManifoldDomain::Create(std::move(data), &s);
  if (!result.domain) return s.WithContext(name);
  result.rest_positions = std::move(positions);
  result.data_points = data_points;
  if (has_displacement == 1) {
    result.displacement = BsplineDisplacement::Create(std::move(disp), nv, &s);
    if (!result.displacement) return s.WithContext(name);
  }
  *out = std::move(result);
  return Status::Ok();
}

}  // namespace dsurf
}  // namespace dermis
