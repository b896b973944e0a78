// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf container shared by every version (docs/file-format.md): the magic, the version
// and flags words, the FNV-1a 64 checksum at the end. Internal to the dsurf module: the body
// of each version is written and read by its own file (dsurf.cpp: versions 1 and 3, a surface;
// character_dsurf.cpp: version 2, a character), and dsurf_read.cpp dispatches on the version.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_stream.h"
#include "dermis/core/status.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"

namespace dermis::dsurf {

/// Runtime archives with quantised displacements: each coefficient within this fraction of the
/// diagonal of its part's control mesh (or half a step of 1/65535 of its level's range, where
/// 16 bits cannot do better). With at most 13 levels whose B-spline weights sum to 1 the
/// displacement moves by at most 13 times this (2.6e-5 of the diagonal); measured errors are
/// far below (docs/file-format.md, "Runtime archives").
constexpr double kQuantizationTolerance = 2e-6;

/// Magic, version and flags: the bytes before every body.
constexpr std::size_t kHeaderBytes = 16;

/// Starts a file: magic, `version`, flags 0.
void WriteHeader(std::uint32_t version, ByteWriter* w);

/// Appends the checksum of everything written so far and returns the file's bytes.
std::string Finish(ByteWriter* w);

/// A checked file: its version and the bytes before the checksum (header included, so that
/// offsets in messages are offsets in the file).
struct Contents {
  std::uint32_t version = 0;
  std::string_view bytes;
};

/// Checks the magic, the header's size, the version (1 .. kLatestDsurfVersion) and the
/// checksum. Errors name `name`: "not a .dsurf file (bad magic bytes)", "truncated .dsurf
/// header", ".dsurf version N is not supported (this build reads 1..3)" (kUnsupported) or
/// "checksum mismatch (the file is corrupt or truncated)".
Status Open(std::string_view bytes, const std::string& name, Contents* out);

/// A reader of a body: positioned after the header of `contents`, errors naming `name`.
ByteReader BodyReader(const Contents& contents, const std::string& name);

/// Ok if `r` read its body to the end; otherwise the reader's error, or "NAME: N unexpected
/// bytes before the checksum".
Status CheckEnd(const ByteReader& r);

/// Adds the bytes a reader consumed since the last mark to a section of `info` (nothing if
/// `info` is null): the byte layout `dermis inspect` prints.
class SectionMarks {
 public:
  SectionMarks(const ByteReader* r, DsurfFileInfo* info) : r_(r), info_(info), last_(r->pos()) {}
  /// The bytes since the last mark belong to `section` (null: counted elsewhere).
  void Close(const char* section) {
    if (info_ != nullptr && section != nullptr && r_->pos() > last_)
      info_->Add(section, r_->pos() - last_);
    last_ = r_->pos();
  }
  DsurfFileInfo* info() const { return info_; }

 private:
  const ByteReader* r_;
  DsurfFileInfo* info_;
  std::size_t last_;
};

/// The body of a version-1 or version-3 file (a surface), read by `r`; `info` (may be null)
/// receives its sections.
Status ReadSurfaceBody(ByteReader* r, std::uint32_t version, DisplacedSurface* out,
                       DsurfFileInfo* info = nullptr);

/// Parses a complete surface file (versions 1, 3) nested in another file, its sections (its
/// header and checksum as "header") into `info` (may be null).
Status ParseNestedSurface(std::string_view bytes, const std::string& name, DisplacedSurface* out,
                          DsurfFileInfo* info);

/// The body of a version-2 file (a character), read by `r`.
Status ReadCharacterBody(ByteReader* r, Character* out, DsurfFileInfo* info = nullptr);

/// The body of a version-4 file (a runtime archive), read by `r`.
Status ReadArchiveBody(ByteReader* r, Character* out, DsurfFileInfo* info = nullptr);

/// A part's fit summary (versions 2 and 4): 4 x i64, 4 x f64, i64, i32.
void WriteSummary(const PartFitSummary& f, ByteWriter* w);
PartFitSummary ReadSummary(ByteReader* r);
/// The components left as ordinary meshes (versions 2 and 4): u32 count, then per part i32
/// mesh, i32 component, i64 vertices, i64 triangles, string reason.
void WriteUnfitted(const std::vector<UnfittedPart>& unfitted, ByteWriter* w);
Status ReadUnfitted(ByteReader* r, std::vector<UnfittedPart>* unfitted);

/// The domain header every surface version starts with: u8 chart type (0..2), u8 blend type
/// (0..1), f64 blend lb, u32 vertex count, u32 face count. Writes the options into *options
/// and the counts into *nv, *nf; an unknown type or a count past Index fails `r`.
void ReadDomainHeader(ByteReader* r, DomainOptions* options, std::uint32_t* nv, std::uint32_t* nf);

/// The control vertices' kinds (u8 each, 0..3), checked against the bytes left before the
/// vector is sized; an unknown kind fails `r`.
void ReadVertexKinds(ByteReader* r, std::uint32_t nv, std::vector<VertexKind>* kinds);

/// Unsigned LEB128 (7 bits per byte, low bits first, the high bit set on every byte but the
/// last; at most 5 bytes).
void WriteVarint(std::uint32_t v, ByteWriter* w);
std::uint32_t ReadVarint(ByteReader* r, const char* what);

/// The level structure of sparse (additive) displacement lattices: half extents (f64, or f32
/// if `compact`), level counts (u8), each level's coefficient count (u32, or varints if
/// `compact`), the node runs of the sparse levels (varints). Not the coefficients.
void WriteSparseStructure(const BsplineDisplacementData& b, bool compact, ByteWriter* w);
/// Reads it for `nv` charts into *d (form, half extents, level counts, nodes, offsets) and
/// returns the coefficient count, checked against the bytes left at `coefficient_bits` each
/// before any node list is allocated; 0 after an error (in r).
std::uint64_t ReadSparseStructure(ByteReader* r, std::uint32_t nv, bool compact,
                                  int coefficient_bits, BsplineDisplacementData* d);

}  // namespace dermis::dsurf
