// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Runtime archives: the body of version-4 .dsurf files (docs/file-format.md, "Runtime
// archives"): a character packed for the runtime, the way ozz-animation turns raw objects into
// runtime ones. The rig instead of the source asset (unless kept), control positions and
// patch-fit operators in f32, 16-bit indices where the counts allow, the displacement levels'
// sparse structure with f32 extents and varint counts, the coefficients in f32 or quantised per
// level to at most 16 bits, influences and bindings in 16-bit fields. The container (magic,
// version, checksum) is dsurf_container.cpp's; every count and index is checked before use.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/byte_stream.h"
#include "dermis/asset/asset_io.h"
#include "dermis/core/limits.h"
#include "dermis/runtime/character.h"
#include "dsurf/dsurf_container.h"

namespace dermis {
namespace {

constexpr std::uint32_t kFlagQuantized = 1;
constexpr std::uint32_t kFlagSourceKept = 2;
constexpr std::uint32_t kKnownFlags = kFlagQuantized | kFlagSourceKept;

constexpr std::uint8_t kNoDisplacement = 0;
constexpr std::uint8_t kMergedDisplacement = 1;
constexpr std::uint8_t kAdditiveDisplacement = 2;

// Indices below `count` take 2 bytes when count <= 65536, else 4.
int IndexBytes(std::uint64_t count) { return count <= 65536 ? 2 : 4; }

void WriteIndex(std::uint32_t v, int bytes, ByteWriter* w) {
  if (bytes == 2) {
    w->U16(static_cast<std::uint16_t>(v));
  } else {
    w->U32(v);
  }
}

// A face coordinate in [0, 1] as a u16 (0 and 1 exact).
std::uint16_t UnitToU16(double x) {
  return static_cast<std::uint16_t>(std::lround(std::clamp(x, 0.0, 1.0) * 65535.0));
}

// Vertex count of primitive (m, q): its bindings' count (the asset's positions may be gone).
std::uint64_t PrimitiveVertices(const Character& ch, std::size_t m, std::size_t q) {
  if (m < ch.bindings.size() && q < ch.bindings[m].size()) return ch.bindings[m][q].size();
  return ch.asset.meshes[m].primitives[q].positions.size();
}

// The rig and the primitives' vertex counts: what the runtime needs of the source asset (the
// bound output's triangles are the source primitives', which the engine has).
void WriteRig(const Character& ch, ByteWriter* w) {
  const Asset& a = ch.asset;
  std::vector<bool> joint(a.nodes.size(), false);
  for (const AssetSkin& s : a.skins) {
    for (Index j : s.joints) {
      if (j >= 0 && static_cast<std::size_t>(j) < joint.size())
        joint[static_cast<std::size_t>(j)] = true;
    }
  }
  w->U32(static_cast<std::uint32_t>(a.nodes.size()));
  for (std::size_t n = 0; n < a.nodes.size(); ++n) {
    w->I32(a.nodes[n].parent);
    w->Str(joint[n] ? a.nodes[n].name : std::string());
  }
  w->U32(static_cast<std::uint32_t>(a.skins.size()));
  for (const AssetSkin& s : a.skins) {
    w->U32(static_cast<std::uint32_t>(s.joints.size()));
    for (Index j : s.joints) w->I32(j);
    w->U8(s.has_inverse_bind_matrices ? 1 : 0);
    if (!s.has_inverse_bind_matrices) continue;
    for (const glm::mat4& m : s.inverse_bind_matrices) {
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) w->F32(m[c][r]);
      }
    }
  }
  w->U32(static_cast<std::uint32_t>(a.meshes.size()));
  for (std::size_t m = 0; m < a.meshes.size(); ++m) {
    w->U32(static_cast<std::uint32_t>(a.meshes[m].primitives.size()));
    for (std::size_t q = 0; q < a.meshes[m].primitives.size(); ++q) {
      w->U8(static_cast<std::uint8_t>(a.meshes[m].primitives[q].mode));
      w->U32(static_cast<std::uint32_t>(PrimitiveVertices(ch, m, q)));
    }
  }
}

// Coefficient groups: per chart, per level, the coefficients stored for it.
std::vector<std::uint32_t> CoefficientGroups(const BsplineDisplacementData& d) {
  std::vector<std::uint32_t> groups;
  std::size_t g = 0;
  for (std::uint8_t levels : d.num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      groups.push_back(d.form == BsplineLevelForm::kAdditive
                           ? static_cast<std::uint32_t>(d.level_counts[g])
                           : static_cast<std::uint32_t>(BsplineLatticeSize(k)));
    }
  }
  return groups;
}

// Level of each coefficient group (CoefficientGroups() order).
std::vector<int> GroupLevels(const BsplineDisplacementData& d) {
  std::vector<int> levels;
  for (std::uint8_t n : d.num_levels) {
    for (int k = 0; k < n; ++k) levels.push_back(k);
  }
  return levels;
}

double Diagonal(const std::vector<Vec3>& points) {
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Vec3& p : points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return points.empty() ? 0.0 : glm::length(hi - lo);
}

// Bits, least significant first, into bytes.
class BitWriter {
 public:
  explicit BitWriter(ByteWriter* w) : w_(w) {}
  void Put(std::uint32_t v, int bits) {
    acc_ |= static_cast<std::uint64_t>(v) << fill_;
    fill_ += bits;
    while (fill_ >= 8) {
      w_->U8(static_cast<std::uint8_t>(acc_ & 0xff));
      acc_ >>= 8;
      fill_ -= 8;
    }
  }
  void Flush() {
    if (fill_ > 0) w_->U8(static_cast<std::uint8_t>(acc_ & 0xff));
    acc_ = 0;
    fill_ = 0;
  }

 private:
  ByteWriter* w_;
  std::uint64_t acc_ = 0;
  int fill_ = 0;
};

// The coefficients, group after group: f32 when `diagonal` is 0; else quantised per level
// (docs/file-format.md, "Runtime archives"): level k's coefficients of every chart share an
// offset, a step and a width of 1..16 bits, the fewest that keep every coefficient within
// kQuantizationTolerance * diagonal of its value (16 bits: within half a step of 1/65535 of
// the level's range), bit-packed.
void WriteCoefficients(const BsplineDisplacementData& d, double diagonal, ByteWriter* w) {
  if (diagonal <= 0.0) {
    for (float x : d.values) w->F32(x);
    return;
  }
  const std::vector<std::uint32_t> groups = CoefficientGroups(d);
  const std::vector<int> level_of = GroupLevels(d);
  int nlevels = 0;
  for (int k : level_of) nlevels = std::max(nlevels, k + 1);
  std::vector<float> lo(static_cast<std::size_t>(nlevels), std::numeric_limits<float>::max());
  std::vector<float> hi(static_cast<std::size_t>(nlevels), -std::numeric_limits<float>::max());
  std::size_t at = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto k = static_cast<std::size_t>(level_of[g]);
    for (std::uint32_t i = 0; i < groups[g]; ++i, ++at) {
      lo[k] = std::min(lo[k], d.values[at]);
      hi[k] = std::max(hi[k], d.values[at]);
    }
  }
  const double tolerance = dsurf::kQuantizationTolerance * diagonal;
  std::vector<float> step(lo.size(), 0.0f);
  std::vector<int> bits(lo.size(), 1);
  w->U8(static_cast<std::uint8_t>(nlevels));
  for (std::size_t k = 0; k < lo.size(); ++k) {
    if (lo[k] > hi[k]) lo[k] = hi[k] = 0.0f;  // no coefficient at this level
    const double range = static_cast<double>(hi[k]) - lo[k];
    while (bits[k] < 16 && range / static_cast<double>((1u << bits[k]) - 1) > 2.0 * tolerance)
      ++bits[k];
    step[k] = static_cast<float>(range / static_cast<double>((1u << bits[k]) - 1));
    w->F32(lo[k]);
    w->F32(step[k]);
    w->U8(static_cast<std::uint8_t>(bits[k]));
  }
  BitWriter bw(w);
  at = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const auto k = static_cast<std::size_t>(level_of[g]);
    const double top = static_cast<double>((1u << bits[k]) - 1);
    for (std::uint32_t i = 0; i < groups[g]; ++i, ++at) {
      const double q =
          step[k] > 0.0f ? std::round((static_cast<double>(d.values[at]) - lo[k]) / step[k]) : 0.0;
      bw.Put(static_cast<std::uint32_t>(std::clamp(q, 0.0, top)), bits[k]);
    }
  }
  bw.Flush();
}

void WriteSurface(const DisplacedSurface& s, bool quantize, bool keep_source, ByteWriter* w) {
  const DomainData& d = s.domain->data();
  const MeshTopology& topo = s.domain->topology();
  w->U8(static_cast<std::uint8_t>(d.options.chart_type));
  w->U8(static_cast<std::uint8_t>(d.options.blend_type));
  w->F64(d.options.blend_lb);
  const auto nv = static_cast<std::uint32_t>(topo.num_vertices());
  const auto nf = static_cast<std::uint32_t>(topo.num_faces());
  w->U32(nv);
  w->U32(nf);
  for (const Vec3& p : s.rest_positions) {
    for (int c = 0; c < 3; ++c) w->F32(static_cast<float>(p[c]));
  }
  const int vbytes = IndexBytes(nv);
  for (std::uint32_t f = 0; f < nf; ++f) {
    for (int k = 0; k < 4; ++k)
      WriteIndex(static_cast<std::uint32_t>(topo.face_vertex(static_cast<Index>(f), k)), vbytes, w);
  }
  for (VertexKind k : d.vertex_kind) w->U8(static_cast<std::uint8_t>(k));
  const auto nops = static_cast<std::uint32_t>(d.operator_offsets.size() - 1);
  w->U32(nops);
  for (Index o : d.operator_offsets) w->U32(static_cast<std::uint32_t>(o));
  for (double x : d.operator_values) w->F32(static_cast<float>(x));
  const int obytes = IndexBytes(nops);
  for (Index o : d.vertex_operator) WriteIndex(static_cast<std::uint32_t>(o), obytes, w);
  if (!s.displacement) {
    w->U8(kNoDisplacement);
  } else {
    const BsplineDisplacementData& b = s.displacement->data();
    if (b.form == BsplineLevelForm::kAdditive) {
      w->U8(kAdditiveDisplacement);
      dsurf::WriteSparseStructure(b, /*compact=*/true, w);
    } else {
      w->U8(kMergedDisplacement);
      for (double r : b.half_extent) w->F32(static_cast<float>(r));
      for (std::uint8_t l : b.num_levels) w->U8(l);
    }
    WriteCoefficients(b, quantize ? Diagonal(s.rest_positions) : 0.0, w);
  }
  if (keep_source) w->U64(static_cast<std::uint64_t>(std::max<std::int64_t>(s.data_points, 0)));
}

}  // namespace

std::string SerializeRuntimeArchive(const Character& ch, const RuntimeArchiveOptions& options,
                                    const RuntimeArchiveError& error) {
  ByteWriter w;
  dsurf::WriteHeader(kRuntimeArchiveVersion, &w);
  w.U32((options.quantize_displacements ? kFlagQuantized : 0u) |
        (options.keep_source ? kFlagSourceKept : 0u));
  w.F64(error.level8_max);
  w.F64(error.level8_mean);
  w.F64(error.bound_max);
  w.F64(error.diagonal);
  if (options.keep_source) {
    w.Str(SerializeAsset(ch.asset));
  } else {
    WriteRig(ch, &w);
  }
  w.U32(static_cast<std::uint32_t>(ch.parts.size()));
  for (const CharacterPart& p : ch.parts) {
    w.I32(p.mesh);
    w.I32(p.component);
    w.I32(p.skin);
    WriteSurface(p.surface, options.quantize_displacements, options.keep_source, &w);
    w.U32(static_cast<std::uint32_t>(p.control_joints.size()));
    const std::size_t njoints =
        p.skin >= 0 ? ch.asset.skins[static_cast<std::size_t>(p.skin)].joints.size() : 0;
    for (std::size_t i = 0; i < p.control_joints.size(); ++i) {
      for (int k = 0; k < 4; ++k) {
        if (njoints <= 256) {
          w.U8(static_cast<std::uint8_t>(p.control_joints[i][k]));
        } else {
          w.U16(p.control_joints[i][k]);
        }
      }
      // Weights as u16 summing to 65535: the largest takes the rounding.
      std::uint32_t q[4], sum = 0;
      int largest = 0;
      for (int k = 0; k < 4; ++k) {
        const float x = std::clamp(p.control_weights[i][k], 0.0f, 1.0f);
        q[k] = static_cast<std::uint32_t>(std::lround(static_cast<double>(x) * 65535.0));
        sum += q[k];
        if (p.control_weights[i][k] > p.control_weights[i][largest]) largest = k;
      }
      if (sum > 0) {
        const std::int64_t fixed =
            static_cast<std::int64_t>(q[largest]) + 65535 - static_cast<std::int64_t>(sum);
        q[largest] = static_cast<std::uint32_t>(std::clamp<std::int64_t>(fixed, 0, 65535));
      }
      for (int k = 0; k < 4; ++k) w.U16(static_cast<std::uint16_t>(q[k]));
    }
    if (options.keep_source) dsurf::WriteSummary(p.fit, &w);
  }
  for (std::size_t m = 0; m < ch.bindings.size(); ++m) {
    for (std::size_t q = 0; q < ch.bindings[m].size(); ++q) {
      for (const VertexBinding& b : ch.bindings[m][q]) {
        w.U16(static_cast<std::uint16_t>(b.part + 1));
        if (b.part == kInvalidIndex) continue;
        const Index faces = ch.parts[static_cast<std::size_t>(b.part)].surface.domain->num_faces();
        if (IndexBytes(static_cast<std::uint64_t>(faces)) == 2) {
          w.U16(static_cast<std::uint16_t>(b.face));
        } else {
          w.U32(static_cast<std::uint32_t>(b.face));
        }
        w.U16(UnitToU16(b.u));
        w.U16(UnitToU16(b.v));
      }
    }
  }
  if (options.keep_source) dsurf::WriteUnfitted(ch.unfitted, &w);
  return dsurf::Finish(&w);
}

namespace {

// The rig section into a stripped asset: nodes (name, parent), skins, each primitive's mode
// and vertex count (returned in *vertices, per mesh per primitive).
void ReadRig(ByteReader* reader, Asset* a, std::vector<std::vector<std::uint64_t>>* vertices) {
  ByteReader& r = *reader;
  const std::uint32_t nnodes = r.U32("node count");
  if (r.ok() && nnodes > limits::kMaxNodes)
    r.Fail("more than " + std::to_string(limits::kMaxNodes) + " nodes");
  if (!r.Need(nnodes, 12, "nodes")) return;
  a->nodes.resize(nnodes);
  for (std::uint32_t n = 0; n < nnodes && r.ok(); ++n) {
    AssetNode& node = a->nodes[n];
    node.parent = r.I32("node parent");
    node.name = r.Str("node name");
    if (r.ok() && (node.parent < kInvalidIndex || node.parent >= static_cast<Index>(nnodes) ||
                   node.parent == static_cast<Index>(n))) {
      r.Fail("node " + std::to_string(n) + ": parent " + std::to_string(node.parent) +
             " out of range");
    }
  }
  const std::uint32_t nskins = r.U32("skin count");
  if (!r.Need(nskins, 5, "skins")) return;
  a->skins.resize(nskins);
  for (std::uint32_t s = 0; s < nskins && r.ok(); ++s) {
    AssetSkin& skin = a->skins[s];
    const std::uint32_t nj = r.U32("joint count");
    if (!r.Need(nj, 4, "joints")) return;
    skin.joints.resize(nj);
    for (Index& j : skin.joints) {
      j = r.I32("joint");
      if (r.ok() && (j < 0 || j >= static_cast<Index>(nnodes)))
        r.Fail("skin " + std::to_string(s) + ": joint node " + std::to_string(j) + " out of range");
    }
    const std::uint8_t has = r.U8("inverse bind flag");
    if (r.ok() && has > 1) r.Fail("skin " + std::to_string(s) + ": bad inverse bind flag");
    skin.has_inverse_bind_matrices = has == 1;
    skin.inverse_bind_matrices.assign(has == 1 && r.Need(nj, 64, "inverse bind matrices") ? nj : 0,
                                      glm::mat4(1.0f));
    for (glm::mat4& m : skin.inverse_bind_matrices) {
      for (int c = 0; c < 4; ++c) {
        for (int k = 0; k < 4; ++k) {
          m[c][k] = r.F32("inverse bind matrix");
          if (r.ok() && !std::isfinite(m[c][k]))
            r.Fail("skin " + std::to_string(s) + ": an inverse bind matrix is not finite");
        }
      }
    }
    if (has == 0) skin.inverse_bind_matrices.assign(nj, glm::mat4(1.0f));
  }
  const std::uint32_t nmeshes = r.U32("mesh count");
  if (!r.Need(nmeshes, 4, "meshes")) return;
  a->meshes.resize(nmeshes);
  vertices->resize(nmeshes);
  for (std::uint32_t m = 0; m < nmeshes && r.ok(); ++m) {
    const std::uint32_t nprims = r.U32("primitive count");
    if (!r.Need(nprims, 5, "primitives")) return;
    a->meshes[m].primitives.resize(nprims);
    (*vertices)[m].resize(nprims);
    for (std::uint32_t q = 0; q < nprims && r.ok(); ++q) {
      AssetPrimitive& p = a->meshes[m].primitives[q];
      const std::uint8_t mode = r.U8("primitive mode");
      if (r.ok() && mode > 6) r.Fail("mesh " + std::to_string(m) + ": unknown primitive mode");
      p.mode = static_cast<PrimitiveMode>(mode);
      const std::uint32_t nv = r.U32("primitive vertex count");
      // Each vertex has a binding of at least 2 bytes further on.
      if (!r.Need(nv, 2, "primitive vertices")) return;
      (*vertices)[m][q] = nv;
    }
  }
}

// The coefficients of WriteCoefficients(): f32, or quantised per level and bit-packed.
void ReadCoefficients(ByteReader* reader, bool quantized, BsplineDisplacementData* d) {
  ByteReader& r = *reader;
  const std::vector<std::uint32_t> groups = CoefficientGroups(*d);
  std::uint64_t total = 0;
  for (std::uint32_t n : groups) total += n;
  if (!quantized) {
    if (!r.Need(total, 4, "displacement coefficients")) return;
    d->values.resize(static_cast<std::size_t>(total));
    for (float& x : d->values) x = r.F32("coefficient");
    return;
  }
  const std::vector<int> level_of = GroupLevels(*d);
  const int nlevels = r.U8("quantised level count");
  if (r.ok() && nlevels > kMaxBsplineLevels) r.Fail("too many quantised displacement levels");
  if (!r.Need(static_cast<std::uint64_t>(nlevels), 9, "quantised levels")) return;
  std::vector<float> lo(static_cast<std::size_t>(nlevels)), step(lo.size());
  std::vector<int> bits(lo.size());
  for (std::size_t k = 0; k < lo.size(); ++k) {
    lo[k] = r.F32("coefficient offset");
    step[k] = r.F32("coefficient step");
    bits[k] = r.U8("coefficient bits");
    if (r.ok() && (!std::isfinite(lo[k]) || !std::isfinite(step[k]) || step[k] < 0.0f ||
                   bits[k] < 1 || bits[k] > 16)) {
      r.Fail("displacement level " + std::to_string(k) +
             ": bad quantisation (offset, step or bit count)");
      return;
    }
  }
  std::uint64_t total_bits = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (level_of[g] >= nlevels) {
      if (groups[g] == 0) continue;
      r.Fail("a displacement level has coefficients but no quantisation");
      return;
    }
    total_bits += std::uint64_t{groups[g]} * static_cast<std::uint64_t>(bits[level_of[g]]);
  }
  if (!r.Need((total_bits + 7) / 8, 1, "displacement coefficients")) return;
  d->values.resize(static_cast<std::size_t>(total));
  std::uint64_t acc = 0;
  int fill = 0;
  std::size_t at = 0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (groups[g] == 0) continue;
    const auto k = static_cast<std::size_t>(level_of[g]);
    const std::uint64_t mask = (std::uint64_t{1} << bits[k]) - 1;
    for (std::uint32_t i = 0; i < groups[g]; ++i, ++at) {
      while (fill < bits[k]) {
        acc |= r.Raw(1) << fill;  // covered by the Need() above
        fill += 8;
      }
      d->values[at] = lo[k] + step[k] * static_cast<float>(acc & mask);
      acc >>= bits[k];
      fill -= bits[k];
    }
  }
}

Status ReadSurface(ByteReader* reader, bool quantized, bool source_kept, DisplacedSurface* out,
                   dsurf::SectionMarks* marks) {
  ByteReader& r = *reader;
  DomainData data;
  std::uint32_t nv = 0, nf = 0;
  dsurf::ReadDomainHeader(&r, &data.options, &nv, &nf);
  marks->Close("header");
  std::vector<Vec3> positions;
  if (r.Need(nv, 12, "control positions")) {
    positions.resize(nv);
    for (Vec3& p : positions) {
      for (int c = 0; c < 3; ++c) p[c] = static_cast<double>(r.F32("position"));
      if (r.ok() && (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)))
        r.Fail("a control position is not finite");
    }
  }
  const int vbytes = IndexBytes(nv);
  std::vector<Index> quads;
  if (r.Need(nf, 4 * static_cast<std::uint64_t>(vbytes), "quads")) {
    quads.resize(static_cast<std::size_t>(nf) * 4);
    for (Index& q : quads) {
      q = static_cast<Index>(vbytes == 2 ? r.Raw(2) : r.U32("quad"));
      if (r.ok() && (q < 0 || static_cast<std::uint32_t>(q) >= nv))
        r.Fail("quad vertex out of range");
    }
  }
  dsurf::ReadVertexKinds(&r, nv, &data.vertex_kind);
  marks->Close("control meshes");
  const std::uint32_t nops = r.U32("operator count");
  if (r.Need(static_cast<std::uint64_t>(nops) + 1, 4, "operator offsets")) {
    data.operator_offsets.resize(static_cast<std::size_t>(nops) + 1);
    for (Index& o : data.operator_offsets) {
      const std::uint32_t x = r.U32("operator offset");
      if (r.ok() && x > static_cast<std::uint32_t>(std::numeric_limits<Index>::max()))
        r.Fail("operator offset too large");
      o = static_cast<Index>(x);
    }
  }
  const std::int64_t nvalues = r.ok() ? data.operator_offsets.back() : 0;
  if (r.Need(static_cast<std::uint64_t>(nvalues), 4, "operator values")) {
    data.operator_values.resize(static_cast<std::size_t>(nvalues));
    for (double& x : data.operator_values) x = static_cast<double>(r.F32("operator value"));
  }
  const int obytes = IndexBytes(nops);
  if (r.Need(nv, static_cast<std::uint64_t>(obytes), "vertex operators")) {
    data.vertex_operator.resize(nv);
    for (Index& o : data.vertex_operator)
      o = static_cast<Index>(obytes == 2 ? r.Raw(2) : r.U32("vertex operator"));
  }
  marks->Close("patch operators");
  const std::uint8_t kind = r.U8("displacement kind");
  if (r.ok() && kind > kAdditiveDisplacement) r.Fail("bad displacement kind");
  marks->Close("header");
  BsplineDisplacementData disp;
  if (r.ok() && kind == kAdditiveDisplacement) {
    dsurf::ReadSparseStructure(&r, nv, /*compact=*/true, quantized ? 1 : 32, &disp);
  } else if (r.ok() && kind == kMergedDisplacement) {
    if (r.Need(nv, 4 + 1, "displacement charts")) {
      disp.half_extent.resize(nv);
      for (double& x : disp.half_extent) x = static_cast<double>(r.F32("half extent"));
      disp.num_levels.resize(nv);
      for (std::uint8_t& l : disp.num_levels) {
        l = r.U8("level count");
        if (r.ok() && l > kMaxBsplineLevels) r.Fail("a chart has too many displacement levels");
      }
      disp.offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
      for (std::uint32_t c = 0; c < nv && r.ok(); ++c) {
        std::int64_t n = 0;
        for (int k = 0; k < disp.num_levels[c]; ++k) n += BsplineLatticeSize(k);
        disp.offsets[c + 1] = disp.offsets[c] + n;
      }
    }
  }
  marks->Close("displacement lattices");
  if (r.ok() && kind != kNoDisplacement) ReadCoefficients(&r, quantized, &disp);
  marks->Close("displacement coefficients");
  std::int64_t data_points = 0;
  if (source_kept) {
    data_points = r.I64("data points");
    if (r.ok() && data_points < 0) r.Fail("negative data point count");
    marks->Close("fit summaries");
  }
  if (!r.ok()) return r.status();
  Status s = MeshTopology::BuildQuads(static_cast<Index>(nv), quads, &data.topology);
  if (!s.ok()) return s.WithContext(r.name());
  DisplacedSurface result;
  result.domain = ManifoldDomain::Create(std::move(data), &s);
  if (!result.domain) return s.WithContext(r.name());
  result.rest_positions = std::move(positions);
  result.data_points = data_points;
  if (kind != kNoDisplacement) {
    result.displacement = BsplineDisplacement::Create(std::move(disp), nv, &s);
    if (!result.displacement) return s.WithContext(r.name());
  }
  *out = std::move(result);
  return Status::Ok();
}

Status ReadArchivePart(ByteReader* reader, const Asset& asset, bool quantized, bool source_kept,
                       std::uint32_t i, CharacterPart* p, dsurf::SectionMarks* marks) {
  ByteReader& r = *reader;
  p->mesh = r.I32("part mesh");
  p->component = r.I32("part component");
  p->skin = r.I32("part skin");
  if (!r.ok()) return r.status();
  marks->Close("header");
  const std::string where = r.name() + ": part " + std::to_string(i);
  if (p->mesh < kInvalidIndex || p->mesh >= static_cast<Index>(asset.meshes.size()) ||
      p->skin < kInvalidIndex || p->skin >= static_cast<Index>(asset.skins.size())) {
    return Status::InvalidInput(where + ": mesh or skin index out of range");
  }
  Status s = ReadSurface(&r, quantized, source_kept, &p->surface, marks);
  if (!s.ok()) {
    // "NAME: what" -> "NAME: part i: what".
    std::string m = s.message();
    const std::string prefix = r.name() + ": ";
    if (m.rfind(prefix, 0) == 0) m.insert(prefix.size(), "part " + std::to_string(i) + ": ");
    return Status(s.code(), m);
  }
  const std::uint32_t n = r.U32("control influence count");
  marks->Close("header");
  const std::size_t njoints =
      p->skin >= 0 ? asset.skins[static_cast<std::size_t>(p->skin)].joints.size() : 0;
  const int jbytes = njoints <= 256 ? 1 : 2;
  if (!r.Need(n, 4 * static_cast<std::uint64_t>(jbytes) + 8, "control influences"))
    return r.status();
  if (n != 0 && n != p->surface.rest_positions.size()) {
    return Status::InvalidInput(where + ": " + std::to_string(n) + " control influences for " +
                                std::to_string(p->surface.rest_positions.size()) +
                                " control vertices");
  }
  p->control_joints.resize(n);
  p->control_weights.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 4; ++c) {
      const auto j = static_cast<std::uint32_t>(r.Raw(jbytes));
      if (j >= njoints && r.ok())
        r.Fail("part " + std::to_string(i) + ": control joint out of range");
      p->control_joints[k][c] = static_cast<std::uint16_t>(j);
    }
    std::uint32_t sum = 0;
    for (int c = 0; c < 4; ++c) {
      const auto q = static_cast<std::uint32_t>(r.Raw(2));
      sum += q;
      p->control_weights[k][c] = static_cast<float>(q) / 65535.0f;
    }
    if (sum != 65535 && r.ok())
      r.Fail("part " + std::to_string(i) + ": control weights do not sum to 1");
  }
  marks->Close("skin influences");
  if (source_kept) {
    p->fit = dsurf::ReadSummary(&r);
    marks->Close("fit summaries");
  }
  return r.status();
}

// Bindings: per vertex of every primitive u16 part + 1 (0: not bound), then, if bound, u32
// face, f32 u, f32 v.
Status ReadArchiveBindings(ByteReader* reader, const Character& ch,
                           const std::vector<std::vector<std::uint64_t>>& vertices,
                           std::vector<std::vector<std::vector<VertexBinding>>>* bindings) {
  ByteReader& r = *reader;
  bindings->resize(vertices.size());
  for (std::size_t m = 0; m < vertices.size() && r.ok(); ++m) {
    (*bindings)[m].resize(vertices[m].size());
    for (std::size_t q = 0; q < vertices[m].size() && r.ok(); ++q) {
      if (!r.Need(vertices[m][q], 2, "bindings")) break;
      (*bindings)[m][q].resize(static_cast<std::size_t>(vertices[m][q]));
      for (VertexBinding& b : (*bindings)[m][q]) {
        b.part = static_cast<Index>(r.U16("binding part")) - 1;
        if (!r.ok()) break;
        if (b.part == kInvalidIndex) continue;
        if (b.part >= static_cast<Index>(ch.parts.size())) {
          r.Fail("mesh " + std::to_string(m) + " primitive " + std::to_string(q) +
                 ": a vertex binding names part " + std::to_string(b.part) +
                 ", which does not exist");
          break;
        }
        const Index faces = ch.parts[static_cast<std::size_t>(b.part)].surface.domain->num_faces();
        b.face = static_cast<Index>(IndexBytes(static_cast<std::uint64_t>(faces)) == 2
                                        ? r.U16("binding face")
                                        : r.U32("binding face"));
        b.u = static_cast<double>(r.U16("binding u")) / 65535.0;
        b.v = static_cast<double>(r.U16("binding v")) / 65535.0;
        if (!r.ok()) break;
        if (b.face < 0 || b.face >= faces) {
          r.Fail("mesh " + std::to_string(m) + " primitive " + std::to_string(q) +
                 ": a vertex binding is out of range");
          break;
        }
      }
    }
  }
  return r.status();
}

}  // namespace

namespace dsurf {

Status ReadArchiveBody(ByteReader* reader, Character* out, DsurfFileInfo* info) {
  ByteReader& r = *reader;
  SectionMarks marks(reader, info);
  if (info != nullptr) info->Add("header", kHeaderBytes + 8);  // header and checksum
  const std::uint32_t flags = r.U32("archive flags");
  if (r.ok() && (flags & ~kKnownFlags) != 0)
    r.Fail("unknown archive flags " + std::to_string(flags));
  RuntimeArchiveError error;
  error.level8_max = r.F64("error");
  error.level8_mean = r.F64("error");
  error.bound_max = r.F64("error");
  error.diagonal = r.F64("diagonal");
  if (!r.ok()) return r.status();
  marks.Close("header");
  const bool quantized = (flags & kFlagQuantized) != 0;
  const bool source_kept = (flags & kFlagSourceKept) != 0;
  Character ch;
  std::vector<std::vector<std::uint64_t>> vertices;
  if (source_kept) {
    const std::string asset_bytes = r.Str("asset");
    if (!r.ok()) return r.status();
    const Status s = ParseAsset(asset_bytes, r.name(), &ch.asset);
    if (!s.ok()) return s;
    marks.Close("source asset");
    vertices.resize(ch.asset.meshes.size());
    for (std::size_t m = 0; m < vertices.size(); ++m) {
      for (const AssetPrimitive& p : ch.asset.meshes[m].primitives)
        vertices[m].push_back(p.positions.size());
    }
  } else {
    ReadRig(&r, &ch.asset, &vertices);
    if (!r.ok()) return r.status();
    ch.asset.source = r.name();
    ch.source_stripped = true;
    marks.Close("rig");
  }
  const std::uint32_t nparts = r.U32("part count");
  // A part takes at least 12 (indices) + 18 (chart, blend, lb, V, F) + 8 (operators) + 1
  // (displacement kind) + 4 (influence count) bytes.
  if (!r.Need(nparts, 43, "parts")) return r.status();
  if (r.ok() && nparts > 0xfffe) r.Fail("too many parts");
  marks.Close("header");
  for (std::uint32_t i = 0; i < nparts && r.ok(); ++i) {
    CharacterPart p;
    const Status s = ReadArchivePart(&r, ch.asset, quantized, source_kept, i, &p, &marks);
    if (!s.ok()) return s;
    ch.parts.push_back(std::move(p));
  }
  Status s = ReadArchiveBindings(&r, ch, vertices, &ch.bindings);
  marks.Close("vertex bindings");
  if (s.ok() && source_kept) {
    s = dsurf::ReadUnfitted(&r, &ch.unfitted);
    marks.Close("unfitted parts");
  }
  if (s.ok()) s = CheckEnd(r);
  if (!s.ok()) return s;
  if (info != nullptr) {
    info->archive.quantize_displacements = quantized;
    info->archive.keep_source = source_kept;
    info->archive_error = error;
  }
  *out = std::move(ch);
  return Status::Ok();
}

}  // namespace dsurf
}  // namespace dermis
