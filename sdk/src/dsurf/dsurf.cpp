// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf container (docs/file-format.md): explicit little-endian fields, bounds-checked
// parsing, FNV-1a 64 checksum over everything before it.
#include "dermis/dsurf/dsurf.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "core/byte_stream.h"
#include "dermis/core/file_io.h"

namespace dermis {
namespace {

constexpr char kMagic[8] = {'D', 'S', 'U', 'R', 'F', '\r', '\n', '\x1a'};

}  // namespace

std::string SerializeDsurf(const ManifoldDomain& domain, const Vec3* rest_positions,
                           const BsplineDisplacement* displacement) {
  const DomainData& d = domain.data();
  const MeshTopology& topo = domain.topology();
  ByteWriter w;
  w.str().append(kMagic, 8);
  w.U32(kDsurfVersion);
  w.U32(0);  // flags, reserved
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
  if (displacement) {
    const BsplineDisplacementData& b = displacement->data();
    for (double r : b.half_extent) w.F64(r);
    for (std::uint8_t l : b.num_levels) w.U8(l);
    for (std::int64_t o : b.offsets) w.I64(o);
    for (float x : b.values) w.F32(x);
  }
  w.U64(Fnv1a64(w.str()));
  return std::move(w.str());
}

Status ParseDsurf(std::string_view bytes, const std::string& name, DisplacedSurface* out) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0) {
    return Status::InvalidInput(name + ": not a .dsurf file (bad magic bytes)");
  }
  if (bytes.size() < 16) return Status::InvalidInput(name + ": truncated .dsurf header");
  ByteReader r(bytes.substr(0, bytes.size() - 8), name);
  {
    ByteReader tail(bytes.substr(bytes.size() - 8), name);
    const std::uint64_t stored = tail.U64("checksum");
    if (stored != Fnv1a64(bytes.substr(0, bytes.size() - 8))) {
      return Status::InvalidInput(name + ": checksum mismatch (the file is corrupt or truncated)");
    }
  }
  r.Raw(8);
  const std::uint32_t version = r.U32("version");
  if (r.ok() && (version == 0 || version > kDsurfVersion)) {
    return Status::Unsupported(name + ": .dsurf version " + std::to_string(version) +
                               " is not supported (this build reads 1.." +
                               std::to_string(kDsurfVersion) + ")");
  }
  r.U32("flags");
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
  if (r.ok() && has_displacement == 1) {
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
  if (!r.ok()) return r.status();
  if (r.pos() != bytes.size() - 8) {
    return Status::InvalidInput(name + ": " + std::to_string(bytes.size() - 8 - r.pos()) +
                                " unexpected bytes before the checksum");
  }
  Status s = MeshTopology::BuildQuads(static_cast<Index>(nv), quads, &data.topology);
  if (!s.ok()) return s.WithContext(name);
  DisplacedSurface result;
  result.domain = ManifoldDomain::Create(std::move(data), &s);
  if (!result.domain) return s.WithContext(name);
  result.rest_positions = std::move(positions);
  if (has_displacement == 1) {
    result.displacement = BsplineDisplacement::Create(std::move(disp), nv, &s);
    if (!result.displacement) return s.WithContext(name);
  }
  *out = std::move(result);
  return Status::Ok();
}

Status ReadDsurf(const std::string& path, DisplacedSurface* out) {
  std::string bytes;
  Status s = ReadFileBytes(path, "a .dsurf file", &bytes);
  if (!s.ok()) return s;
  return ParseDsurf(bytes, path, out);
}

}  // namespace dermis
