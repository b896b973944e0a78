// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf container shared by every version (docs/file-format.md): the magic, the version
// and flags words, the FNV-1a 64 checksum at the end. Internal to the dsurf module: the body
// of each version is written and read by its own file (dsurf.cpp: versions 1 and 3, a surface;
// character_dsurf.cpp: version 2, a character), and dsurf_read.cpp dispatches on the version.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/byte_stream.h"
#include "dermis/core/status.h"
#include "dermis/dsurf/dsurf.h"

namespace dermis::dsurf {

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

/// The body of a version-1 or version-3 file (a surface), read by `r`.
Status ReadSurfaceBody(ByteReader* r, std::uint32_t version, DisplacedSurface* out);

/// The body of a version-2 file (a character), read by `r`.
Status ReadCharacterBody(ByteReader* r, Character* out);

}  // namespace dermis::dsurf
