// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf module: one container (magic, version, checksum) and one reader for every version
// (docs/file-format.md).
#include "dermis/dsurf/dsurf.h"

#include <catch2/catch.hpp>
#include <cstdint>
#include <string>

#include "dermis/runtime/character.h"
#include "support/fixtures.h"
#include "support/temp_files.h"

using namespace dermis;

namespace {

// FNV-1a 64, written here again so that the test does not trust the module's own.
std::uint64_t Fnv(std::string_view bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

// `bytes` with its checksum recomputed after `edit` changed the bytes before it.
template <typename Edit>
std::string Resealed(std::string bytes, Edit edit) {
  std::string body = bytes.substr(0, bytes.size() - 8);
  edit(&body);
  const std::uint64_t h = Fnv(body);
  for (int i = 0; i < 8; ++i) body.push_back(static_cast<char>((h >> (8 * i)) & 0xff));
  return body;
}

std::string SurfaceBytes(const CharacterPart& part) {
  return SerializeDsurf(*part.surface.domain, part.surface.rest_positions.data(),
                        part.surface.displacement.get());
}

}  // namespace

TEST_CASE("dsurf: one reader for surfaces and characters") {
  const Character& fitted = test::CylindersFixture();
  REQUIRE(fitted.parts.size() == 2);
  REQUIRE(fitted.parts[0].surface.displacement != nullptr);
  const std::string surface = SurfaceBytes(fitted.parts[0]);
  const std::string character = SerializeCharacter(fitted);
  // A fitted part's displacement is sparse levels: version 3 (dsurf_versions_test.cpp reads a
  // version-1 file).
  CHECK(DsurfFileVersion(surface) == kSparseDsurfVersion);
  CHECK(DsurfFileVersion(character) == kCharacterDsurfVersion);
  CHECK(DsurfFileVersion("DSURF") == 0);
  CHECK(DsurfFileVersion(std::string("glTF\x02\0\0\0\0\0\0\0", 12)) == 0);

  // A surface file reads as a character of one part, with no asset.
  Character ch;
  std::uint32_t version = 0;
  REQUIRE(ParseCharacter(surface, "s.dsurf", &ch, &version).ok());
  CHECK(version == kSparseDsurfVersion);
  REQUIRE(ch.parts.size() == 1);
  CHECK(ch.asset.source == "s.dsurf");
  CHECK(ch.asset.meshes.empty());
  CHECK(ch.bindings.empty());
  CHECK(ch.parts[0].control_joints.empty());
  CHECK(SurfaceBytes(ch.parts[0]) == surface);

  // A version-2 file reads back to the same bytes.
  REQUIRE(ParseCharacter(character, "c.dsurf", &ch, &version).ok());
  CHECK(version == kCharacterDsurfVersion);
  CHECK(ch.parts.size() == fitted.parts.size());
  CHECK(SerializeCharacter(ch) == character);

  // The surface reader reads surfaces only.
  DisplacedSurface s;
  REQUIRE(ParseDsurf(surface, "s.dsurf", &s).ok());
  CHECK(SerializeDsurf(*s.domain, s.rest_positions.data(), s.displacement.get()) == surface);
  const Status st = ParseDsurf(character, "c.dsurf", &s);
  CHECK(st.code() == StatusCode::kInvalidInput);
  CHECK(st.message() == "c.dsurf: a version 2 .dsurf is a character, not a plain surface");
}

TEST_CASE("dsurf: the container of every version") {
  const Character& fitted = test::CylindersFixture();
  for (const std::string& bytes : {SurfaceBytes(fitted.parts[0]), SerializeCharacter(fitted)}) {
    const std::uint32_t file_version = DsurfFileVersion(bytes);
    INFO("version " << file_version);
    Character ch;
    DisplacedSurface s;
    // Versions this build does not know: refused before anything else is read.
    for (const std::uint32_t v : {0u, 5u, 0xffffffffu}) {
      std::string other = bytes;
      for (int i = 0; i < 4; ++i) other[8 + i] = static_cast<char>((v >> (8 * i)) & 0xff);
      const Status st = ParseCharacter(other, "v.dsurf", &ch);
      CHECK(st.code() == StatusCode::kUnsupported);
      CHECK(st.message() == "v.dsurf: .dsurf version " + std::to_string(v) +
                                " is not supported (this build reads 1..4)");
      CHECK(ParseDsurf(other, "v.dsurf", &s).code() == StatusCode::kUnsupported);
    }
    // Bad magic, a short header, a damaged byte.
    std::string text = bytes;
    text[0] = 'd';
    CHECK(ParseCharacter(text, "m.dsurf", &ch).message() ==
          "m.dsurf: not a .dsurf file (bad magic bytes)");
    CHECK(ParseCharacter(bytes.substr(0, 20), "h.dsurf", &ch).message() ==
          "h.dsurf: truncated .dsurf header");
    std::string flipped = bytes;
    flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 1);
    CHECK(ParseCharacter(flipped, "f.dsurf", &ch).message() ==
          "f.dsurf: checksum mismatch (the file is corrupt or truncated)");
    // Bytes after the body, under a valid checksum.
    const std::string longer = Resealed(bytes, [](std::string* b) { b->append("XYZW"); });
    CHECK(ParseCharacter(longer, "l.dsurf", &ch).message() ==
          "l.dsurf: 4 unexpected bytes before the checksum");
    // A body cut short, under a valid checksum: the reader names what is missing.
    const std::string shorter = Resealed(bytes, [](std::string* b) { b->resize(b->size() - 3); });
    const Status st = ParseCharacter(shorter, "t.dsurf", &ch);
    CHECK(st.code() == StatusCode::kInvalidInput);
    CHECK_THAT(st.message(), Catch::StartsWith("t.dsurf: truncated or corrupt file: "));
  }
}

TEST_CASE("dsurf: a file is read once, its bytes handed back") {
  const Character& fitted = test::CylindersFixture();
  test::TempDir dir("dermis_dsurf");
  const std::string surface = SurfaceBytes(fitted.parts[1]);
  test::WriteFile(dir.File("part.dsurf"), surface);
  Character ch;
  std::uint32_t version = 0;
  std::string bytes;
  REQUIRE(ReadCharacter(dir.File("part.dsurf"), &ch, &version, &bytes).ok());
  CHECK(bytes == surface);
  CHECK(version == kSparseDsurfVersion);
  CHECK(ch.asset.source == dir.File("part.dsurf"));
  DisplacedSurface s;
  REQUIRE(ReadDsurf(dir.File("part.dsurf"), &s).ok());
  CHECK(s.rest_positions == fitted.parts[1].surface.rest_positions);
  const Status missing = ReadCharacter(dir.File("none.dsurf"), &ch);
  CHECK(missing.code() == StatusCode::kIoError);
  CHECK_THAT(missing.message(), Catch::StartsWith(dir.File("none.dsurf") + ": "));
  CHECK(ReadDsurf(dir.path().string(), &s).message() ==
        dir.path().string() + ": is a directory, not a .dsurf file");
}
