// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The one reader of .dsurf files of every version (docs/file-format.md): the container is
// checked once, then the version picks the body. A surface (version 1 or 3) reads as a
// character of one part with no asset meshes.
#include "core/byte_stream.h"
#include "dermis/core/file_io.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"
#include "dsurf/dsurf_container.h"

namespace dermis {

Status ParseCharacter(std::string_view bytes, const std::string& name, Character* out,
                      std::uint32_t* version, DsurfFileInfo* info) {
  dsurf::Contents file;
  Status s = dsurf::Open(bytes, name, &file);
  if (!s.ok()) return s;
  ByteReader r = dsurf::BodyReader(file, name);
  Character ch;
  DsurfFileInfo layout;
  layout.version = file.version;
  DsurfFileInfo* sections = info != nullptr ? &layout : nullptr;
  if (IsSurfaceDsurfVersion(file.version)) {
    CharacterPart part;
    layout.Add("header", dsurf::kHeaderBytes + 8);  // header and checksum
    s = dsurf::ReadSurfaceBody(&r, file.version, &part.surface, sections);
    if (!s.ok()) return s;
    ch.asset.source = name;
    ch.parts.push_back(std::move(part));
  } else if (file.version == kCharacterDsurfVersion) {
    s = dsurf::ReadCharacterBody(&r, &ch, sections);
    if (!s.ok()) return s;
  } else {
    s = dsurf::ReadArchiveBody(&r, &ch, &layout);
    if (!s.ok()) return s;
  }
  *out = std::move(ch);
  if (version != nullptr) *version = file.version;
  if (info != nullptr) *info = std::move(layout);
  return Status::Ok();
}

Status ReadCharacter(const std::string& path, Character* out, std::uint32_t* version,
                     std::string* bytes) {
  std::string local;
  std::string& data = bytes != nullptr ? *bytes : local;
  const Status s = ReadFileBytes(path, "a .dsurf file", &data);
  if (!s.ok()) return s;
  return ParseCharacter(data, path, out, version);
}

Status ReadDsurf(const std::string& path, DisplacedSurface* out) {
  std::string bytes;
  const Status s = ReadFileBytes(path, "a .dsurf file", &bytes);
  if (!s.ok()) return s;
  return ParseDsurf(bytes, path, out);
}

}  // namespace dermis
