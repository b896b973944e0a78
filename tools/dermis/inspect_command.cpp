// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis inspect: what a file holds. glTF (.gltf, .glb) and every format Assimp reads: meshes,
// skins, clips, influences per vertex, materials, images, nodes. .dsurf: control mesh and
// displacement lattices. Text summary on stdout, or one deterministic JSON object (--json,
// "schema": "dermis.inspect/1").
//
// Every report is built as JSON first; the text output is printed from that JSON, so a new
// field needs one line in the Describe* function and (optionally) one in the Print* function.
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "character_json.h"
#include "commands.h"
#include "dermis/asset/asset.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/character.h"
#include "dermis/runtime/runtime.h"
#include "importers.h"
#include "report_json.h"

namespace dermis::cli {
namespace {

constexpr const char* kInspectCommand = "inspect";

constexpr const char* kInspectSchema = "dermis.inspect/1";

struct InspectArgs {
  std::string input;
  bool json = false;
  int memory_level = 4;  // the tessellation level whose output memory is reported
};

// The memory the runtime takes for a loaded character and for each part's outputs (the bound
// vertices and a tessellation level): what an engine budgets with (docs/engine-integration.md).
Status DescribeRuntimeMemory(Character ch, int level, Json* out) {
  std::unique_ptr<RuntimeCharacter> rc;
  Status s = RuntimeCharacter::FromCharacter(std::move(ch), &rc);
  if (!s.ok()) return s;
  Json j;
  j["character_bytes"] = rc->memory_bytes();
  j["level"] = level;
  Json parts = Json::array();
  std::size_t outputs = 0;
  for (std::size_t p = 0; p < rc->num_parts(); ++p) {
    Json part;
    for (const OutputKind kind : {OutputKind::kBound, OutputKind::kLevel}) {
      OutputSpec spec;
      spec.kind = kind;
      spec.level = level;
      spec.threads = 0;
      std::unique_ptr<RuntimeOutput> o;
      s = RuntimeOutput::Build(*rc, p, spec, &o);
      if (!s.ok()) return s;
      const char* name = kind == OutputKind::kBound ? "bound" : "level";
      part[name]["vertices"] = o->num_vertices();
      part[name]["bytes"] = o->memory_bytes();
      outputs += o->memory_bytes();
    }
    parts.push_back(part);
  }
  std::unique_ptr<RuntimeInstance> inst;
  s = RuntimeInstance::Create(*rc, DeformerKind::kLbs, &inst);
  if (!s.ok()) return s;
  j["instance_bytes"] = inst->memory_bytes();
  j["outputs_bytes"] = outputs;
  j["parts"] = parts;
  *out = j;
  return Status::Ok();
}

// ---------------------------------------------------------------------------------------------
// Assets (glTF and Assimp formats).

const char* ModeName(PrimitiveMode mode) {
  switch (mode) {
    case PrimitiveMode::kPoints:
      return "POINTS";
    case PrimitiveMode::kLines:
      return "LINES";
    case PrimitiveMode::kLineLoop:
      return "LINE_LOOP";
    case PrimitiveMode::kLineStrip:
      return "LINE_STRIP";
    case PrimitiveMode::kTriangles:
      return "TRIANGLES";
    case PrimitiveMode::kTriangleStrip:
      return "TRIANGLE_STRIP";
    case PrimitiveMode::kTriangleFan:
      return "TRIANGLE_FAN";
  }
  return "UNKNOWN";
}

std::int64_t TriangleCount(const AssetPrimitive& prim) {
  const auto n =
      static_cast<std::int64_t>(prim.indices.empty() ? prim.positions.size() : prim.indices.size());
  switch (prim.mode) {
    case PrimitiveMode::kTriangles:
      return n / 3;
    case PrimitiveMode::kTriangleStrip:
    case PrimitiveMode::kTriangleFan:
      return std::max<std::int64_t>(0, n - 2);
    default:
      return 0;
  }
}

Json Attributes(const AssetPrimitive& prim) {
  Json a = Json::array();
  if (!prim.positions.empty()) a.push_back("POSITION");
  if (!prim.normals.empty()) a.push_back("NORMAL");
  if (!prim.tangents.empty()) a.push_back("TANGENT");
  for (std::size_t i = 0; i < prim.texcoords.size(); ++i)
    a.push_back("TEXCOORD_" + std::to_string(i));
  for (std::size_t i = 0; i < prim.colors.size(); ++i) a.push_back("COLOR_" + std::to_string(i));
  for (std::size_t i = 0; i < prim.joints.size(); ++i) a.push_back("JOINTS_" + std::to_string(i));
  for (std::size_t i = 0; i < prim.weights.size(); ++i) a.push_back("WEIGHTS_" + std::to_string(i));
  return a;
}

// Non-zero weights of vertex v over all WEIGHTS_n sets.
int Influences(const AssetPrimitive& prim, std::size_t v) {
  int count = 0;
  for (const std::vector<glm::vec4>& set : prim.weights) {
    if (v >= set.size()) continue;
    for (int k = 0; k < 4; ++k) count += set[v][k] != 0.0f ? 1 : 0;
  }
  return count;
}

/// The meshes of an asset, their totals, and the histogram of skinned vertices by number of
/// non-zero weights.
Json DescribeMeshes(const Asset& asset, Json* totals, std::vector<std::int64_t>* histogram) {
  std::int64_t total_primitives = 0, total_vertices = 0, total_triangles = 0;
  Json meshes = Json::array();
  for (const AssetMesh& mesh : asset.meshes) {
    Json m;
    m["name"] = mesh.name;
    std::int64_t vertices = 0, triangles = 0;
    Json prims = Json::array();
    for (const AssetPrimitive& prim : mesh.primitives) {
      Json p;
      p["mode"] = ModeName(prim.mode);
      p["vertices"] = prim.positions.size();
      p["indices"] = prim.indices.size();
      p["triangles"] = TriangleCount(prim);
      p["attributes"] = Attributes(prim);
      p["morph_targets"] = prim.targets.size();
      p["material"] = prim.material;
      prims.push_back(p);
      vertices += static_cast<std::int64_t>(prim.positions.size());
      triangles += TriangleCount(prim);
      if (!prim.weights.empty()) {
        for (std::size_t v = 0; v < prim.positions.size(); ++v) {
          const auto k = static_cast<std::size_t>(Influences(prim, v));
          if (histogram->size() <= k) histogram->resize(k + 1, 0);
          ++(*histogram)[k];
        }
      }
    }
    m["vertices"] = vertices;
    m["triangles"] = triangles;
    m["primitives"] = prims;
    meshes.push_back(m);
    total_primitives += static_cast<std::int64_t>(mesh.primitives.size());
    total_vertices += vertices;
    total_triangles += triangles;
  }
  (*totals)["meshes"] = asset.meshes.size();
  (*totals)["primitives"] = total_primitives;
  (*totals)["vertices"] = total_vertices;
  (*totals)["triangles"] = total_triangles;
  return meshes;
}

/// Clips: duration, channels, samplers and keyframes of each.
Json DescribeClips(const Asset& asset) {
  Json clips = Json::array();
  for (const AssetAnimation& anim : asset.animations) {
    Json c;
    c["name"] = anim.name;
    c["duration"] = anim.Duration();
    c["channels"] = anim.channels.size();
    c["samplers"] = anim.samplers.size();
    std::int64_t keyframes = 0;
    for (const AssetAnimationSampler& s : anim.samplers)
      keyframes += static_cast<std::int64_t>(s.times.size());
    c["keyframes"] = keyframes;
    clips.push_back(c);
  }
  return clips;
}

/// The "asset" section of a report: everything an importer produced.
Json DescribeAsset(const Asset& asset) {
  Json j;
  j["generator"] = asset.generator;
  j["copyright"] = asset.copyright;
  j["scenes"] = asset.scenes.size();
  j["nodes"] = asset.nodes.size();
  Json totals;
  std::vector<std::int64_t> histogram;  // [k] = skinned vertices with k non-zero weights
  Json meshes = DescribeMeshes(asset, &totals, &histogram);
  j["totals"] = totals;
  j["meshes"] = meshes;

  Json skins = Json::array();
  for (const AssetSkin& skin : asset.skins) {
    Json s;
    s["name"] = skin.name;
    s["joints"] = skin.joints.size();
    s["inverse_bind_matrices"] = skin.has_inverse_bind_matrices;
    skins.push_back(s);
  }
  j["skins"] = skins;

  Json influences;
  std::int64_t skinned = 0;
  for (const std::int64_t count : histogram) skinned += count;
  influences["skinned_vertices"] = skinned;
  influences["max"] = histogram.empty() ? 0 : histogram.size() - 1;
  influences["histogram"] = histogram;  // index = influences, value = vertices
  j["influences"] = influences;
  j["clips"] = DescribeClips(asset);

  Json materials = Json::array();
  for (const AssetMaterial& material : asset.materials) materials.push_back(material.name);
  j["materials"] = materials;
  j["textures"] = asset.textures.size();
  Json images = Json::array();
  for (const AssetImage& image : asset.images) {
    Json i;
    i["name"] = image.name;
    i["mime_type"] = image.mime_type;
    i["bytes"] = image.bytes.size();
    images.push_back(i);
  }
  j["images"] = images;
  return j;
}

// ---------------------------------------------------------------------------------------------
// Displaced surfaces (.dsurf, also embedded in .glb as DERMIS_displaced_surface).

/// The bytes of each section of a .dsurf file as its reader found them, and what a runtime
/// archive's header records (docs/file-format.md).
Json DescribeLayout(const DsurfFileInfo& info, const Character& ch) {
  Json j;
  j["version"] = info.version;
  Json sections = Json::array();
  for (const auto& section : info.sections) {
    Json e;
    e["section"] = section.first;
    e["bytes"] = section.second;
    sections.push_back(e);
  }
  j["sections"] = sections;
  if (info.version == kRuntimeArchiveVersion) {
    Json a;
    a["quantized_displacements"] = info.archive.quantize_displacements;
    a["source_kept"] = info.archive.keep_source;
    a["skins"] = ch.asset.skins.size();
    const RuntimeArchiveError& e = info.archive_error;
    a["diagonal"] = e.diagonal;
    a["level8_max_error"] = e.level8_max;
    a["level8_mean_error"] = e.level8_mean;
    a["bound_max_error"] = e.bound_max;
    j["archive"] = a;
  }
  return j;
}

/// Parses .dsurf bytes (a file, or the extension of a .glb). A plain surface (version 1) fills
/// report["surface"]; a character (version 2) fills report["character"] and, when
/// `with_asset` (a .dsurf file rather than a .glb that already described its asset),
/// report["asset"] from the source asset it stores.
Status InspectDsurfBytes(std::string_view bytes, const std::string& name, bool with_asset,
                         int memory_level, Json* report) {
  Character ch;
  std::uint32_t version = 0;
  DsurfFileInfo info;
  const Status s = ParseCharacter(bytes, name, &ch, &version, &info);
  if (!s.ok()) return s;
  if (IsSurfaceDsurfVersion(version)) {
    (*report)["surface"] = DescribeSurface(ch.parts[0].surface);
  } else {
    if (with_asset && !ch.source_stripped) (*report)["asset"] = DescribeAsset(ch.asset);
    (*report)["character"] = DescribeCharacter(ch);
  }
  (*report)["layout"] = DescribeLayout(info, ch);
  return DescribeRuntimeMemory(std::move(ch), memory_level, &(*report)["runtime_memory"]);
}

/// A .dsurf file.
Status InspectDsurf(const std::string& path, int memory_level, Json* report) {
  std::string bytes;
  const Status s = ReadFileBytes(path, "a .dsurf file", &bytes);
  if (!s.ok()) return s;
  return InspectDsurfBytes(bytes, path, true, memory_level, report);
}

/// Any file an asset importer reads: fills report["asset"] (and report["surface"] or
/// report["character"] for a file that carries a Dermis surface, as a .glb can in its
/// DERMIS_displaced_surface extension).
Status InspectAssetFile(const std::string& path, int memory_level, Json* report) {
  ImportedAsset imported;
  Status s = Importers().ImportAsset(path, &imported);
  if (!s.ok()) return s;
  (*report)["asset"] = DescribeAsset(imported.asset);
  if (!imported.embedded_dsurf.empty()) {
    s = InspectDsurfBytes(imported.embedded_dsurf, path + " (" + kDsurfGltfExtension + ")", false,
                          memory_level, report);
    if (!s.ok()) return s;
  }
  return Status::Ok();
}

// ---------------------------------------------------------------------------------------------
// Text output.

std::string Str(const Json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_null()) return "-";
  if (v.is_number_float()) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.4g", v.get<double>());
    return buf;
  }
  return v.dump(-1, ' ', false, Json::error_handler_t::replace);
}

void Row(const std::string& key, const std::string& value) {
  std::printf("%-16s %s\n", key.c_str(), value.c_str());
}

// Prints rows of cells with every column padded to its widest cell, indented by 2.
void Table(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    if (width.size() < row.size()) width.resize(row.size(), 0);
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  for (const auto& row : rows) {
    std::string line = " ";
    for (std::size_t c = 0; c < row.size(); ++c) {
      line += " ";
      line += row[c];
      if (c + 1 < row.size()) line.append(width[c] - row[c].size(), ' ');
    }
    std::printf("%s\n", line.c_str());
  }
}

std::string Quoted(const Json& name) {
  const std::string s = Str(name);
  return s.empty() ? "(unnamed)" : s;
}

void PrintAsset(const Json& a) {
  if (!a["generator"].get<std::string>().empty()) Row("generator", Str(a["generator"]));
  Row("nodes", Str(a["nodes"]));
  const Json& t = a["totals"];
  Row("meshes", Str(t["meshes"]) + " (" + Str(t["primitives"]) + " primitives, " +
                    Str(t["vertices"]) + " vertices, " + Str(t["triangles"]) + " triangles)");
  std::vector<std::vector<std::string>> rows;
  for (const Json& m : a["meshes"]) {
    for (const Json& p : m["primitives"]) {
      std::string attributes;
      for (const Json& name : p["attributes"])
        attributes += (attributes.empty() ? "" : " ") + Str(name);
      rows.push_back({Quoted(m["name"]), Str(p["mode"]), Str(p["vertices"]) + " vertices",
                      Str(p["triangles"]) + " triangles", attributes});
    }
  }
  Table(rows);
  Row("skins", Str(Json(a["skins"].size())));
  rows.clear();
  for (const Json& s : a["skins"])
    rows.push_back({Quoted(s["name"]), Str(s["joints"]) + " joints"});
  Table(rows);
  const Json& inf = a["influences"];
  if (inf["skinned_vertices"].get<std::int64_t>() > 0) {
    std::string histogram;
    const Json& h = inf["histogram"];
    for (std::size_t k = 0; k < h.size(); ++k)
      histogram += (k == 0 ? "" : ", ") + std::to_string(k) + ": " + Str(h[k]);
    Row("influences",
        "max " + Str(inf["max"]) + " per vertex (vertices by count: " + histogram + ")");
  }
  Row("clips", Str(Json(a["clips"].size())));
  rows.clear();
  for (const Json& c : a["clips"]) {
    rows.push_back({Quoted(c["name"]), Str(c["duration"]) + " s", Str(c["channels"]) + " channels",
                    Str(c["keyframes"]) + " keyframes"});
  }
  Table(rows);
  std::string materials;
  for (const Json& m : a["materials"]) materials += (materials.empty() ? "" : ", ") + Quoted(m);
  Row("materials", Str(Json(a["materials"].size())) + (materials.empty() ? "" : ": " + materials));
  Row("textures", Str(a["textures"]));
  Row("images", Str(Json(a["images"].size())));
  rows.clear();
  for (const Json& i : a["images"])
    rows.push_back({Quoted(i["name"]),
                    Str(i["mime_type"]).empty() ? "(unknown type)" : Str(i["mime_type"]),
                    Str(i["bytes"]) + " bytes"});
  Table(rows);
}

void PrintSurface(const Json& s) {
  Row("control vertices", Str(s["control_vertices"]));
  Row("charts", Str(s["charts"]));
  Row("faces", Str(s["faces"]));
  const Json& d = s["displacement"];
  if (d.is_null()) {
    Row("displacement", "none");
    return;
  }
  std::string by_levels;
  const Json& h = d["charts_by_levels"];
  for (std::size_t k = 0; k < h.size(); ++k)
    by_levels += (k == 0 ? "" : ", ") + std::to_string(k) + ": " + Str(h[k]);
  std::string per_level;
  const Json& lc = d["level_coefficients"];
  for (std::size_t k = 0; k < lc.size(); ++k)
    per_level += (k == 0 ? "" : ", ") + std::to_string(k) + ": " + Str(lc[k]);
  Row("displacement", Str(d["max_levels"]) + " levels, " + Str(d["storage"]) +
                          " (charts by levels: " + by_levels + ")");
  Row("coefficients", Str(d["coefficients"]) +
                          (d["data_points"].is_null()
                               ? std::string()
                               : ", " + Str(d["coefficients_per_point"]) + " per data point (" +
                                     Str(d["data_points"]) + " points)") +
                          "; per level: " + per_level);
}

void PrintCharacter(const Json& c) {
  Row("parts", Str(Json(c["parts"].size())) + " fitted, " + Str(Json(c["unfitted"].size())) +
                   " unfitted; " + Str(c["vertices_bound"]) + " of " + Str(c["vertices"]) +
                   " vertices bound to a surface");
  std::vector<std::vector<std::string>> rows;
  for (const Json& p : c["parts"]) {
    const Json& s = p["surface"];
    const Json& f = p["fit"];
    const Json& d = s["displacement"];
    rows.push_back(
        {"mesh " + Str(p["mesh"]) + " component " + Str(p["component"]),
         Str(s["control_vertices"]) + " control vertices", Str(s["faces"]) + " faces",
         d.is_null() ? std::string("no displacement")
                     : Str(d["max_levels"]) + " levels, " + Str(d["coefficients"]) +
                           " coefficients (" + Str(f["coefficients_per_point"]) + " per point)",
         f["points"].get<std::int64_t>() == 0
             ? std::string("fit summary not in this file")
             : "E1 mean " + Str(f["e1_mean"]) + " (" + Str(f["e1_mean_percent"]) + " %), max " +
                   Str(f["e1_max"]) + " (" + Str(f["e1_max_percent"]) + " %)",
         f["points"].get<std::int64_t>() == 0
             ? std::string()
             : "Hausdorff " + Str(f["hausdorff"]) + " (" + Str(f["hausdorff_percent"]) + " %)"});
  }
  Table(rows);
  rows.clear();
  for (const Json& u : c["unfitted"]) {
    rows.push_back({"mesh " + Str(u["mesh"]) + " component " + Str(u["component"]),
                    Str(u["vertices"]) + " vertices", "unfitted: " + Str(u["reason"])});
  }
  Table(rows);
}

void PrintLayout(const Json& l) {
  std::uint64_t total = 0;
  for (const Json& e : l["sections"]) total += e["bytes"].get<std::uint64_t>();
  Row("layout", "version " + Str(l["version"]) + ", " + std::to_string(total) + " bytes");
  std::vector<std::vector<std::string>> rows;
  for (const Json& e : l["sections"]) {
    char percent[32];
    std::snprintf(percent, sizeof(percent), "%.1f %%",
                  total > 0 ? 100.0 * e["bytes"].get<double>() / static_cast<double>(total) : 0.0);
    rows.push_back({Str(e["section"]), Str(e["bytes"]) + " bytes", percent});
  }
  Table(rows);
  if (!l.contains("archive")) return;
  const Json& a = l["archive"];
  Row("runtime archive",
      std::string(a["quantized_displacements"].get<bool>() ? "16-bit" : "f32") +
          " displacements, source " + (a["source_kept"].get<bool>() ? "kept" : "not kept") +
          "; error at the rest pose over the diagonal " + Str(a["diagonal"]) + ": level 8 max " +
          Str(a["level8_max_error"]) + ", mean " + Str(a["level8_mean_error"]) +
          ", bound vertices max " + Str(a["bound_max_error"]));
}

void PrintRuntimeMemory(const Json& m) {
  const auto mb = [](const Json& bytes) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%.3f MB", 1e-6 * bytes.get<double>());
    return std::string(buf);
  };
  Row("runtime memory", "character " + mb(m["character_bytes"]) + ", instance " +
                            mb(m["instance_bytes"]) + ", outputs (bound + level " +
                            Str(m["level"]) + ") " + mb(m["outputs_bytes"]));
  std::vector<std::vector<std::string>> rows;
  std::size_t p = 0;
  for (const Json& part : m["parts"]) {
    rows.push_back(
        {"part " + std::to_string(p++),
         "bound: " + Str(part["bound"]["vertices"]) + " vertices, " + mb(part["bound"]["bytes"]),
         "level " + Str(m["level"]) + ": " + Str(part["level"]["vertices"]) + " vertices, " +
             mb(part["level"]["bytes"])});
  }
  Table(rows);
}

void PrintText(const Json& report) {
  Row("file",
      Str(report["file"]) + " (" + Str(report["format"]) + ", " + Str(report["bytes"]) + " bytes)");
  if (report.contains("asset")) PrintAsset(report["asset"]);
  const bool embedded = report.contains("asset") && report["format"] != "dsurf";
  if (report.contains("surface")) {
    if (embedded) std::printf("%s\n", kDsurfGltfExtension);
    PrintSurface(report["surface"]);
  }
  if (report.contains("character")) {
    if (embedded) std::printf("%s\n", kDsurfGltfExtension);
    PrintCharacter(report["character"]);
  }
  if (report.contains("layout")) PrintLayout(report["layout"]);
  if (report.contains("runtime_memory")) PrintRuntimeMemory(report["runtime_memory"]);
}

// ---------------------------------------------------------------------------------------------

int RunInspect(const InspectArgs& a) {
  std::error_code ec;
  if (std::filesystem::is_directory(a.input, ec)) {
    return Fail(kInspectCommand,
                Status::IoError(a.input + ": is a directory, not a file to inspect"));
  }
  const std::uintmax_t size = std::filesystem::file_size(a.input, ec);
  if (ec || !std::filesystem::is_regular_file(a.input, ec)) {
    return Fail(kInspectCommand, Status::IoError(a.input + ": cannot open"));
  }
  const std::string ext = LowerExtension(a.input);
  Json report;
  Json options;
  options["memory-level"] = a.memory_level;
  StartReport(&report, kInspectSchema, std::move(options));
  report["file"] = a.input;
  report["format"] = ext.empty() ? std::string("unknown") : ext.substr(1);
  report["bytes"] = size;
  const Status s = ext == ".dsurf" ? InspectDsurf(a.input, a.memory_level, &report)
                                   : InspectAssetFile(a.input, a.memory_level, &report);
  if (!s.ok()) return Fail(kInspectCommand, s);
  if (a.json) {
    std::printf("%s\n", report.dump(2, ' ', false, Json::error_handler_t::replace).c_str());
  } else {
    PrintText(report);
  }
  return kExitOk;
}

}  // namespace

void AddInspectCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<InspectArgs>();
  CLI::App* cmd = app->add_subcommand(
      "inspect",
      "Print what a file holds: meshes, skins, clips, influences, materials and images of a "
      "glTF or any Assimp format; control mesh and displacement levels of a .dsurf.");
  cmd->add_option("FILE", args->input, ".gltf, .glb, .dsurf, or any format Assimp reads")
      ->required();
  cmd->add_flag("--json", args->json,
                "Print one JSON object (\"schema\": \"dermis.inspect/1\") instead of text");
  cmd->add_option("--memory-level", args->memory_level,
                  "Tessellation level whose runtime output memory is reported (a surface's, or a "
                  "character's lod output beside its bound one)")
      ->check(CLI::Range(1, 64))
      ->default_val(4);
  cmd->callback([run, args]() { *run = [args]() { return RunInspect(*args); }; });
}

}  // namespace dermis::cli
