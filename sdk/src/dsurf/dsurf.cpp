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

// Version 3's displacement (docs/file-format.md): the level structure, then the
// coefficients as f32.
void WriteSparseLevels(const BsplineDisplacementData& b, ByteWriter* w) {
  dsurf::WriteSparseStructure(b, /*compact=*/false, w);
  for (float x : b.values) w->F32(x);
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
  return dsurf::ParseNestedSurface(bytes, name, out, nullptr);
}

void DsurfFileInfo::Add(const std::string& name, std::uint64_t bytes) {
  for (auto& section : sections) {
    if (section.first == name) {
      section.second += bytes;
      return;
    }
  }
  sections.emplace_back(name, bytes);
}

namespace dsurf {

Status ParseNestedSurface(std::string_view bytes, const std::string& name, DisplacedSurface* out,
                          DsurfFileInfo* info) {
  Contents file;
  Status s = Open(bytes, name, &file);
  if (!s.ok()) return s;
  if (!IsSurfaceDsurfVersion(file.version)) {
    return Status::InvalidInput(name + ": a version " + std::to_string(file.version) +
                                " .dsurf is a character, not a plain surface");
  }
  ByteReader r = BodyReader(file, name);
  if (info != nullptr) info->Add("header", kHeaderBytes + 8);  // header and checksum
  return ReadSurfaceBody(&r, file.version, out, info);
}

void ReadDomainHeader(ByteReader* reader, DomainOptions* options, std::uint32_t* nv,
                      std::uint32_t* nf) {
  ByteReader& r = *reader;
  const std::uint8_t chart = r.U8("chart type"), blend = r.U8("blend type");
  if (chart > 2) r.Fail("unknown chart type " + std::to_string(chart));
  if (blend > 1) r.Fail("unknown blend type " + std::to_string(blend));
  options->chart_type = static_cast<ChartType>(chart);
  options->blend_type = static_cast<BlendType>(blend);
  options->blend_lb = r.F64("blend lb");
  *nv = r.U32("vertex count");
  *nf = r.U32("face count");
  if (r.ok() && (*nv > static_cast<std::uint32_t>(std::numeric_limits<Index>::max()) ||
                 *nf > static_cast<std::uint32_t>(std::numeric_limits<Index>::max() / 4))) {
    r.Fail("vertex or face count too large");
  }
}

void ReadVertexKinds(ByteReader* reader, std::uint32_t nv, std::vector<VertexKind>* kinds) {
  ByteReader& r = *reader;
  if (!r.Need(nv, 1, "vertex kinds")) return;
  kinds->resize(nv);
  for (VertexKind& k : *kinds) {
    const std::uint8_t v = r.U8("vertex kind");
    if (v > 3) r.Fail("unknown vertex kind " + std::to_string(v));
    k = static_cast<VertexKind>(v);
  }
}

Status ReadSurfaceBody(ByteReader* reader, std::uint32_t version, DisplacedSurface* out,
                       DsurfFileInfo* info) {
  ByteReader& r = *reader;
  SectionMarks marks(reader, info);
  const std::string& name = r.name();
  DomainData data;
  std::uint32_t nv = 0, nf = 0;
  ReadDomainHeader(&r, &data.options, &nv, &nf);
  marks.Close("header");
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
  ReadVertexKinds(&r, nv, &data.vertex_kind);
  marks.Close("control meshes");
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
  marks.Close("patch operators");
  const std::uint8_t has_displacement = r.U8("displacement flag");
  marks.Close("header");
  BsplineDisplacementData disp;
  if (r.ok() && has_displacement > 1) r.Fail("bad displacement flag");
  if (r.ok() && has_displacement == 1 && version == kSparseDsurfVersion) {
    const std::uint64_t total = dsurf::ReadSparseStructure(&r, nv, /*compact=*/false, 32, &disp);
    marks.Close("displacement lattices");
    if (r.Need(total, 4, "displacement coefficients")) {
      disp.values.resize(static_cast<std::size_t>(total));
      for (float& x : disp.values) x = r.F32("coefficient");
    }
  } else if (r.ok() && has_displacement == 1) {
    if (r.Need(nv, 8 + 1 + 8, "displacement charts")) {
      disp.half_extent.resize(nv);
      for (double& x : disp.half_extent) x = r.F64("half extent");
      disp.num_levels.resize(nv);
      for (std::uint8_t& l : disp.num_levels) l = r.U8("level count");
      disp.offsets.resize(static_cast<std::size_t>(nv) + 1);
      for (std::int64_t& o : disp.offsets) o = r.I64("lattice offset");
    }
    marks.Close("displacement lattices");
    const std::int64_t ncoeff = r.ok() ? disp.offsets.back() : 0;
    if (r.ok() && ncoeff < 0) r.Fail("negative coefficient count");
    if (r.Need(static_cast<std::uint64_t>(ncoeff), 4, "displacement coefficients")) {
      disp.values.resize(static_cast<std::size_t>(ncoeff));
      for (float& x : disp.values) x = r.F32("coefficient");
    }
  }
  marks.Close("displacement coefficients");
  std::int64_t data_points = 0;
  if (version == kSparseDsurfVersion) {
    data_points = static_cast<std::int64_t>(r.U64("data points"));
    if (r.ok() && data_points < 0) r.Fail("negative data point count");
  }
  marks.Close("fit summaries");
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
