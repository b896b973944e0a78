// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// DERMIS_displaced_surface against its JSON schema and README
// (docs/extensions/DERMIS_displaced_surface/): real --embed exports, plain and quantised +
// compressed, and the README's example. The schema check is a small draft-2020-12 subset
// (type, properties, required, additionalProperties, minimum), the keywords the schema uses;
// a keyword it does not know fails the test, so the schema cannot outgrow the check silently.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/character/character_export.h"
#include "dermis/plugins/gltf.h"
#include "support/characters.h"

namespace dermis {
namespace {

using nlohmann::json;

const char* const kExtensionDir = "docs/extensions/DERMIS_displaced_surface/";

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool HasType(const json& value, const std::string& type) {
  if (type == "object") return value.is_object();
  if (type == "integer") return value.is_number_integer();
  if (type == "number") return value.is_number();
  if (type == "string") return value.is_string();
  if (type == "array") return value.is_array();
  if (type == "boolean") return value.is_boolean();
  return false;
}

/// The schema errors of `value` ("" if none), each "pointer: what".
std::string SchemaErrors(const json& schema, const json& value, const std::string& at) {
  std::string errors;
  for (auto it = schema.begin(); it != schema.end(); ++it) {
    const std::string& key = it.key();
    if (key == "$schema" || key == "$id" || key == "title" || key == "description") continue;
    if (key == "type") {
      if (!HasType(value, it.value().get<std::string>())) {
        errors += at + ": not of type " + it.value().get<std::string>() + "\n";
      }
    } else if (key == "minimum") {
      if (value.is_number() && value.get<double>() < it.value().get<double>()) {
        errors += at + ": below the minimum\n";
      }
    } else if (key == "required") {
      for (const json& name : it.value()) {
        if (!value.is_object() || !value.contains(name.get<std::string>())) {
          errors += at + ": missing " + name.get<std::string>() + "\n";
        }
      }
    } else if (key == "properties") {
      if (!value.is_object()) continue;
      for (auto p = it.value().begin(); p != it.value().end(); ++p) {
        if (value.contains(p.key())) {
          errors += SchemaErrors(p.value(), value[p.key()], at + "/" + p.key());
        }
      }
    } else if (key == "additionalProperties") {
      if (!value.is_object() || it.value().get<bool>()) continue;
      for (auto v = value.begin(); v != value.end(); ++v) {
        if (!schema["properties"].contains(v.key())) {
          errors += at + ": property " + v.key() + " is not allowed\n";
        }
      }
    } else {
      errors += at + ": the check does not know the schema keyword " + key + "\n";
    }
  }
  return errors;
}

json Schema() {
  const std::string text =
      ReadText(std::string(kExtensionDir) + "schema/glTF.DERMIS_displaced_surface.schema.json");
  REQUIRE_FALSE(text.empty());
  return json::parse(text);
}

/// The JSON chunk of a GLB.
json GlbJson(const std::string& glb, std::string* bin) {
  REQUIRE(glb.size() >= 20);
  auto u32 = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i)
      v = (v << 8) | static_cast<unsigned char>(glb[at + std::size_t(i)]);
    return v;
  };
  const std::size_t length = u32(12);
  *bin = glb.substr(20 + length + 8);
  return json::parse(glb.substr(20, length));
}

TEST_CASE("DERMIS_displaced_surface: --embed exports match the schema and the README's layout",
          "[gltf][extension]") {
  const json schema = Schema();
  const Character& ch = test::FittedCylinders();
  const std::string dsurf = SerializeCharacter(ch);
  Asset bound;
  REQUIRE(BuildBoundAsset(ch, CharacterExportOptions{}, &bound).ok());
  for (const bool pack : {false, true}) {
    INFO("quantize and compress: " << pack);
    GltfExportOptions options;
    options.dsurf_bytes = dsurf;
    options.quantize = options.compress = pack;
    std::string glb, bin;
    REQUIRE(SerializeGltf(bound, options, true, &glb).ok());
    const json doc = GlbJson(glb, &bin);
    REQUIRE(doc["extensions"].contains(kDsurfGltfExtension));
    const json& ext = doc["extensions"][kDsurfGltfExtension];
    const std::string errors = SchemaErrors(schema, ext, "/extensions/DERMIS_displaced_surface");
    INFO(errors);
    CHECK(errors.empty());
    // Used, never required.
    const json used = doc.value("extensionsUsed", json::array());
    const json required = doc.value("extensionsRequired", json::array());
    CHECK(std::find(used.begin(), used.end(), kDsurfGltfExtension) != used.end());
    CHECK(std::find(required.begin(), required.end(), kDsurfGltfExtension) == required.end());
    // The view: in buffer 0 (the GLB's BIN), no stride, no target, no compression, no accessor.
    const std::size_t v = ext["bufferView"].get<std::size_t>();
    REQUIRE(v < doc["bufferViews"].size());
    const json& view = doc["bufferViews"][v];
    CHECK(view["buffer"] == 0);
    CHECK_FALSE(view.contains("byteStride"));
    CHECK_FALSE(view.contains("target"));
    CHECK_FALSE(view.contains("extensions"));
    CHECK(view.value("byteOffset", 0) % 4 == 0);
    for (const json& a : doc["accessors"]) CHECK(a.value("bufferView", -1) != int(v));
    const std::size_t offset = view.value("byteOffset", std::size_t{0});
    REQUIRE(view["byteLength"].get<std::size_t>() == dsurf.size());
    REQUIRE(offset + dsurf.size() <= bin.size());
    const std::string bytes = bin.substr(offset, dsurf.size());
    CHECK(bytes == dsurf);
    CHECK(bytes.compare(0, 8, std::string("DSURF\r\n\x1a", 8)) == 0);
    Character back;
    const Status s = ParseCharacter(bytes, "extension", &back);
    INFO(s.message());
    CHECK(s.ok());
  }
}

TEST_CASE("DERMIS_displaced_surface: the README's example and bad objects against the schema",
          "[gltf][extension]") {
  const json schema = Schema();
  const std::string readme = ReadText(std::string(kExtensionDir) + "README.md");
  const std::size_t start = readme.find("```json\n");
  REQUIRE(start != std::string::npos);
  const std::size_t end = readme.find("```", start + 8);
  const json example = json::parse(readme.substr(start + 8, end - start - 8));
  CHECK(SchemaErrors(schema, example["extensions"]["DERMIS_displaced_surface"], "").empty());
  CHECK(example["bufferViews"].size() > 1);
  // The check can fail.
  CHECK_FALSE(SchemaErrors(schema, json::object(), "").empty());
  CHECK_FALSE(SchemaErrors(schema, json{{"bufferView", -1}}, "").empty());
  CHECK_FALSE(SchemaErrors(schema, json{{"bufferView", 1.5}}, "").empty());
  CHECK_FALSE(SchemaErrors(schema, json{{"bufferView", 1}, {"uri", "x.dsurf"}}, "").empty());
  CHECK(SchemaErrors(schema, json{{"bufferView", 0}, {"extras", {{"a", 1}}}}, "").empty());
}

}  // namespace
}  // namespace dermis
