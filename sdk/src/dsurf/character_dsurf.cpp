// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Character files: the body of version-2 .dsurf files (docs/file-format.md, "Character
// files"); the container is dsurf_container.cpp's. Each part's surface is a complete
// version-1 or version-3 .dsurf inside, so the surface reader is shared.
#include <cmath>
#include <limits>

#include "core/byte_stream.h"
#include "dermis/asset/asset_io.h"
#include "dermis/runtime/character.h"
#include "dsurf/dsurf_container.h"

namespace dermis {
namespace dsurf {

void WriteSummary(const PartFitSummary& f, ByteWriter* w) {
  w->I64(f.points);
  w->I64(f.triangles);
  w->I64(f.points_outside);
  w->I64(f.points_not_converged);
  w->F64(f.scale);
  w->F64(f.e1_mean);
  w->F64(f.e1_max);
  w->F64(f.hausdorff);
  w->I64(f.coefficients);
  w->I32(f.levels);
}

PartFitSummary ReadSummary(ByteReader* r) {
  PartFitSummary f;
  f.points = r->I64("fit points");
  f.triangles = r->I64("fit triangles");
  f.points_outside = r->I64("fit points outside");
  f.points_not_converged = r->I64("fit points not converged");
  f.scale = r->F64("fit scale");
  f.e1_mean = r->F64("fit e1 mean");
  f.e1_max = r->F64("fit e1 max");
  f.hausdorff = r->F64("fit hausdorff");
  f.coefficients = r->I64("fit coefficients");
  f.levels = r->I32("fit levels");
  return f;
}

void WriteUnfitted(const std::vector<UnfittedPart>& unfitted, ByteWriter* w) {
  w->U32(static_cast<std::uint32_t>(unfitted.size()));
  for (const UnfittedPart& u : unfitted) {
    w->I32(u.mesh);
    w->I32(u.component);
    w->I64(u.vertices);
    w->I64(u.triangles);
    w->Str(u.reason);
  }
}

}  // namespace dsurf

std::string SerializeCharacter(const Character& ch) {
  ByteWriter w;
  dsurf::WriteHeader(kCharacterDsurfVersion, &w);
  w.Str(SerializeAsset(ch.asset));
  w.U32(static_cast<std::uint32_t>(ch.parts.size()));
  for (const CharacterPart& p : ch.parts) {
    w.I32(p.mesh);
    w.I32(p.component);
    w.I32(p.skin);
    w.Str(SerializeDsurf(*p.surface.domain, p.surface.rest_positions.data(),
                         p.surface.displacement.get(), p.surface.data_points));
    w.U64(p.control_joints.size());
    for (std::size_t i = 0; i < p.control_joints.size(); ++i) {
      for (int k = 0; k < 4; ++k) w.U32(p.control_joints[i][k]);
      for (int k = 0; k < 4; ++k) w.F32(p.control_weights[i][k]);
    }
    dsurf::WriteSummary(p.fit, &w);
  }
  w.U32(static_cast<std::uint32_t>(ch.bindings.size()));
  for (const auto& mesh : ch.bindings) {
    w.U32(static_cast<std::uint32_t>(mesh.size()));
    for (const auto& prim : mesh) {
      w.U64(prim.size());
      for (const VertexBinding& b : prim) {
        w.I32(b.part);
        w.I32(b.face);
        w.F64(b.u);
        w.F64(b.v);
      }
    }
  }
  dsurf::WriteUnfitted(ch.unfitted, &w);
  return dsurf::Finish(&w);
}

namespace {

// Part i: its mesh, component, skin, surface (a complete version-1 .dsurf), the influences of
// its control vertices and its fit summary. Errors name the part.
Status ReadPart(ByteReader* reader, const Asset& asset, std::uint32_t i, CharacterPart* p,
                DsurfFileInfo* info) {
  ByteReader& r = *reader;
  dsurf::SectionMarks marks(reader, info);
  p->mesh = r.I32("part mesh");
  p->component = r.I32("part component");
  p->skin = r.I32("part skin");
  const std::string surface = r.Str("part surface");
  if (!r.ok()) return r.status();
  if (info != nullptr) info->Add("header", 12 + 8);  // indices, the surface's length
  marks.Close(nullptr);
  const std::string where = r.name() + ": part " + std::to_string(i);
  if (p->mesh < kInvalidIndex || p->mesh >= static_cast<Index>(asset.meshes.size()) ||
      p->skin < kInvalidIndex || p->skin >= static_cast<Index>(asset.skins.size())) {
    return Status::InvalidInput(where + ": mesh or skin index out of range");
  }
  const Status s = dsurf::ParseNestedSurface(surface, where, &p->surface, info);
  if (!s.ok()) return s;
  const std::uint64_t n = r.U64("control influence count");
  if (!r.Need(n, 32, "control influences")) return r.status();
  if (n != 0 && n != p->surface.rest_positions.size()) {
    return Status::InvalidInput(where + ": " + std::to_string(n) + " control influences for " +
                                std::to_string(p->surface.rest_positions.size()) +
                                " control vertices");
  }
  p->control_joints.resize(n);
  p->control_weights.resize(n);
  const std::size_t njoints =
      p->skin >= 0 ? asset.skins[static_cast<std::size_t>(p->skin)].joints.size() : 0;
  for (std::size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 4; ++c) {
      const std::uint32_t j = r.U32("control joint");
      if (j >= njoints && r.ok())
        r.Fail("part " + std::to_string(i) + ": control joint out of range");
      p->control_joints[k][c] = static_cast<std::uint16_t>(j);
    }
    for (int c = 0; c < 4; ++c) {
      const float x = r.F32("control weight");
      if (!(x >= 0.0f && x <= 1.0f) && r.ok())
        r.Fail("part " + std::to_string(i) + ": bad control weight");
      p->control_weights[k][c] = x;
    }
  }
  marks.Close("skin influences");
  p->fit = dsurf::ReadSummary(&r);
  marks.Close("fit summaries");
  return r.status();
}

// The binding of every vertex of every primitive of every mesh of the asset; each must name a
// part, a face of it and a parameter in the unit square, or no part.
Status ReadBindings(ByteReader* reader, const Character& ch,
                    std::vector<std::vector<std::vector<VertexBinding>>>* bindings) {
  ByteReader& r = *reader;
  const std::uint32_t nmeshes = r.U32("binding mesh count");
  if (r.ok() && nmeshes != ch.asset.meshes.size()) r.Fail("bindings do not match the meshes");
  bindings->resize(r.ok() ? nmeshes : 0);
  for (std::size_t m = 0; m < bindings->size() && r.ok(); ++m) {
    const std::uint32_t nprims = r.U32("binding primitive count");
    if (r.ok() && nprims != ch.asset.meshes[m].primitives.size()) {
      r.Fail("bindings of mesh " + std::to_string(m) + " do not match its primitives");
    }
    (*bindings)[m].resize(r.ok() ? nprims : 0);
    for (std::size_t p = 0; p < (*bindings)[m].size() && r.ok(); ++p) {
      const std::uint64_t nv = r.U64("binding vertex count");
      if (r.ok() && nv != ch.asset.meshes[m].primitives[p].positions.size()) {
        r.Fail("bindings of mesh " + std::to_string(m) + " primitive " + std::to_string(p) +
               " do not match its vertices");
      }
      if (!r.Need(nv, 24, "bindings")) break;
      (*bindings)[m][p].resize(nv);
      for (VertexBinding& b : (*bindings)[m][p]) {
        b.part = r.I32("binding part");
        b.face = r.I32("binding face");
        b.u = r.F64("binding u");
        b.v = r.F64("binding v");
        if (!r.ok()) break;
        if (b.part == kInvalidIndex) continue;
        if (b.part < 0 || b.part >= static_cast<Index>(ch.parts.size()) || b.face < 0 ||
            b.face >= ch.parts[static_cast<std::size_t>(b.part)].surface.domain->num_faces() ||
            !(b.u >= 0.0 && b.u <= 1.0 && b.v >= 0.0 && b.v <= 1.0)) {
          r.Fail("mesh " + std::to_string(m) + " primitive " + std::to_string(p) +
                 ": a vertex binding is out of range");
        }
      }
    }
  }
  return r.status();
}

}  // namespace

namespace dsurf {

// The components left as ordinary meshes, and why.
Status ReadUnfitted(ByteReader* reader, std::vector<UnfittedPart>* unfitted) {
  ByteReader& r = *reader;
  const std::uint32_t nun = r.U32("unfitted count");
  if (r.Need(nun, 28, "unfitted parts")) {
    for (std::uint32_t i = 0; i < nun && r.ok(); ++i) {
      UnfittedPart u;
      u.mesh = r.I32("unfitted mesh");
      u.component = r.I32("unfitted component");
      u.vertices = r.I64("unfitted vertices");
      u.triangles = r.I64("unfitted triangles");
      u.reason = r.Str("unfitted reason");
      unfitted->push_back(std::move(u));
    }
  }
  return r.status();
}

Status ReadCharacterBody(ByteReader* reader, Character* out, DsurfFileInfo* info) {
  ByteReader& r = *reader;
  SectionMarks marks(reader, info);
  if (info != nullptr) info->Add("header", kHeaderBytes + 8);  // header and checksum
  Character ch;
  const std::string asset_bytes = r.Str("asset");
  if (!r.ok()) return r.status();
  marks.Close("source asset");
  Status s = ParseAsset(asset_bytes, r.name(), &ch.asset);
  if (!s.ok()) return s;
  const std::uint32_t nparts = r.U32("part count");
  marks.Close("header");
  // A part takes at least 12 + 8 + 8 + 84 bytes.
  if (!r.Need(nparts, 112, "parts")) return r.status();
  for (std::uint32_t i = 0; i < nparts; ++i) {
    CharacterPart p;
    s = ReadPart(&r, ch.asset, i, &p, info);
    if (!s.ok()) return s;
    ch.parts.push_back(std::move(p));
  }
  marks.Close(nullptr);  // counted by ReadPart
  s = ReadBindings(&r, ch, &ch.bindings);
  marks.Close("vertex bindings");
  if (s.ok()) s = ReadUnfitted(&r, &ch.unfitted);
  marks.Close("unfitted parts");
  if (s.ok()) s = CheckEnd(r);
  if (!s.ok()) return s;
  *out = std::move(ch);
  return Status::Ok();
}

}  // namespace dsurf
}  // namespace dermis
