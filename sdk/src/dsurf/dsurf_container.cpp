// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf container (dsurf_container.h; docs/file-format.md): one magic, one header, one
// checksum for every version.
#include "dsurf/dsurf_container.h"

#include <cstring>

namespace dermis {
namespace dsurf {
namespace {

constexpr char kMagic[8] = {'D', 'S', 'U', 'R', 'F', '\r', '\n', '\x1a'};

}  // namespace

void WriteHeader(std::uint32_t version, ByteWriter* w) {
  w->str().append(kMagic, 8);
  w->U32(version);
  w->U32(0);  // flags, reserved
}

std::string Finish(ByteWriter* w) {
  w->U64(Fnv1a64(w->str()));
  return std::move(w->str());
}

Status Open(std::string_view bytes, const std::string& name, Contents* out) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0) {
    return Status::InvalidInput(name + ": not a .dsurf file (bad magic bytes)");
  }
  if (bytes.size() < kHeaderBytes + 8) {
    return Status::InvalidInput(name + ": truncated .dsurf header");
  }
  const std::uint32_t version = DsurfFileVersion(bytes);
  if (version == 0 || version > kLatestDsurfVersion) {
    return Status::Unsupported(name + ": .dsurf version " + std::to_string(version) +
                               " is not supported (this build reads 1.." +
                               std::to_string(kLatestDsurfVersion) + ")");
  }
  const std::string_view body = bytes.substr(0, bytes.size() - 8);
  ByteReader tail(bytes.substr(bytes.size() - 8), name);
  if (tail.U64("checksum") != Fnv1a64(body)) {
    return Status::InvalidInput(name + ": checksum mismatch (the file is corrupt or truncated)");
  }
  out->version = version;
  out->bytes = body;
  return Status::Ok();
}

ByteReader BodyReader(const Contents& contents, const std::string& name) {
  ByteReader r(contents.bytes, name);
  r.Raw(8);  // magic
  r.Raw(4);  // version
  r.Raw(4);  // flags
  return r;
}

Status CheckEnd(const ByteReader& r) {
  if (!r.ok()) return r.status();
  if (r.left() != 0) {
    return Status::InvalidInput(r.name() + ": " + std::to_string(r.left()) +
                                " unexpected bytes before the checksum");
  }
  return Status::Ok();
}

}  // namespace dsurf

std::uint32_t DsurfFileVersion(std::string_view bytes) {
  if (bytes.size() < 12 || std::memcmp(bytes.data(), dsurf::kMagic, 8) != 0) return 0;
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) {
    v |= static_cast<std::uint32_t>(
             static_cast<unsigned char>(bytes[8 + static_cast<std::size_t>(i)]))
         << (8 * i);
  }
  return v;
}

}  // namespace dermis
