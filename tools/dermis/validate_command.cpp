// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis validate: checks a glTF file (our importer's structural checks, then the Khronos
// glTF-Validator when it is installed) or a .dsurf (its checksum and every count and index).
// Exit 0 when valid, 1 when not (or unreadable), 2 on usage errors.
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "commands.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/core/file_io.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/plugins/gltf.h"
#include "dermis/runtime/character.h"
#include "dermis/runtime/runtime.h"
#include "importers.h"
#include "report_json.h"

namespace dermis::cli {
namespace {

constexpr const char* kValidateCommand = "validate";

struct ValidateArgs {
  std::string input;
  bool json = false;
  bool require_khronos = false;
  bool quiet = false;
};

std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

// tests/js/validate.js (the project's wrapper of the Khronos validator, installed by
// scripts/setup_js.sh): from $DERMIS_VALIDATE_JS, beside the source tree of this executable
// (build/bin/../../tests/js), in the checkout an installed dermis was built from, or below the
// working directory.
std::string FindValidatorScript() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("DERMIS_VALIDATE_JS")) {
    if (fs::exists(env)) return env;
  }
  std::error_code ec;
  std::vector<fs::path> candidates;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path() / "../../tests/js/validate.js");
  // An installed dermis: the checkout it was built from (where scripts/setup_js.sh installs).
  candidates.push_back(fs::path(DERMIS_SOURCE_DIR) / "tests/js/validate.js");
  candidates.push_back("tests/js/validate.js");
  for (const fs::path& p : candidates) {
    if (fs::exists(p, ec) && fs::exists(p.parent_path() / "node_modules/gltf-validator", ec)) {
      return fs::weakly_canonical(p, ec).string();
    }
  }
  return {};
}

struct Khronos {
  bool ran = false;
  std::string why_not;
  int errors = 0, warnings = 0, infos = 0, hints = 0;
  nlohmann::json messages = nlohmann::json::array();
};

Khronos RunKhronos(const std::string& path) {
  Khronos k;
  const std::string script = FindValidatorScript();
  if (script.empty()) {
    k.why_not =
        "the Khronos glTF-Validator is not installed (run scripts/setup_js.sh, or set "
        "DERMIS_VALIDATE_JS to tests/js/validate.js of a checkout where it is)";
    return k;
  }
  if (std::system("node --version >/dev/null 2>&1") != 0) {
    k.why_not = "node is not installed (the Khronos glTF-Validator runs in Node.js)";
    return k;
  }
  const std::string cmd = "node " + ShellQuote(script) + " " + ShellQuote(path) + " --json 2>&1";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(cmd.c_str(), "r"), pclose);
  if (!pipe) {
    k.why_not = "could not start node";
    return k;
  }
  std::string out;
  std::array<char, 4096> buf;
  std::size_t n = 0;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe.get())) > 0) out.append(buf.data(), n);
  const nlohmann::json report = nlohmann::json::parse(out, nullptr, false);
  if (report.is_discarded() || !report.contains("issues")) {
    k.why_not = "the Khronos glTF-Validator failed: " + out.substr(0, 400);
    return k;
  }
  k.ran = true;
  const nlohmann::json& issues = report["issues"];
  k.errors = issues.value("numErrors", 0);
  k.warnings = issues.value("numWarnings", 0);
  k.infos = issues.value("numInfos", 0);
  k.hints = issues.value("numHints", 0);
  if (issues.contains("messages")) k.messages = issues["messages"];
  return k;
}

int RunValidate(const ValidateArgs& a) {
  std::string bytes;
  Status s = ReadFileBytes(a.input, "the input", &bytes);
  nlohmann::json j;
  nlohmann::json options;
  options["require-khronos"] = a.require_khronos;
  StartReport(&j, "dermis.validate/1", std::move(options));
  j["input"] = a.input;
  bool valid = s.ok();
  std::string kind;
  Khronos khronos;
  if (s.ok()) {
    if (const std::uint32_t version = DsurfFileVersion(bytes); version != 0) {
      kind = IsSurfaceDsurfVersion(version)      ? "dsurf surface"
             : version == kRuntimeArchiveVersion ? "dsurf runtime archive"
                                                 : "dsurf character";
      // The same reader and checks as every consumer: the parse (which builds each domain and
      // checks every offset and index), the asset, and the runtime character the C API loads.
      Character ch;
      s = ParseCharacter(bytes, a.input, &ch);
      if (s.ok() && !IsSurfaceDsurfVersion(version) && !ch.source_stripped)
        s = ValidateAsset(ch.asset);
      if (s.ok()) {
        std::unique_ptr<RuntimeCharacter> runtime;
        s = RuntimeCharacter::FromBytes(bytes, a.input, &runtime);
      }
    } else if (Importers().Find(a.input, ImportKind::kScan) != nullptr) {
      // OBJ, PLY: our readers, as fit and tessellate use them (never Assimp's).
      kind = "mesh";
      PolygonMesh mesh;
      Index dropped = 0;
      s = ReadFitInput(a.input, &mesh, &dropped, &Importers());
    } else {
      const Importer* importer = Importers().Find(a.input, ImportKind::kAsset);
      kind = importer != nullptr && importer->name() == "gltf" ? "gltf" : "other";
      ImportedAsset imported;
      s = Importers().ImportAsset(a.input, &imported);
      if (s.ok()) s = ValidateAsset(imported.asset);
      if (kind == "gltf") {  // the Khronos validator reads glTF only
        khronos = RunKhronos(a.input);
        if (khronos.ran && khronos.errors > 0) valid = false;
      }
    }
    valid = valid && s.ok();
  }
  j["kind"] = kind;
  j["valid"] = valid;
  j["structural"] = s.ok() ? "ok" : s.message();
  if (kind == "gltf") {
    nlohmann::json k;
    k["ran"] = khronos.ran;
    if (khronos.ran) {
      k["errors"] = khronos.errors;
      k["warnings"] = khronos.warnings;
      k["infos"] = khronos.infos;
      k["hints"] = khronos.hints;
      k["messages"] = khronos.messages;
    } else {
      k["why_not"] = khronos.why_not;
    }
    j["khronos"] = k;
  }
  if (a.require_khronos && kind == "gltf" && !khronos.ran) valid = false;
  if (a.json) {
    std::printf("%s\n", j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
  } else if (!a.quiet || !valid) {
    if (!s.ok()) std::fprintf(stderr, "dermis validate: error: %s\n", s.message().c_str());
    if (kind == "gltf") {
      if (khronos.ran) {
        for (const auto& m : khronos.messages) {
          static const char* kSeverity[] = {"error", "warning", "info", "hint"};
          const int sev = m.value("severity", 0);
          std::fprintf(stderr, "  %s %s %s: %s\n", kSeverity[sev >= 0 && sev < 4 ? sev : 0],
                       m.value("code", std::string()).c_str(),
                       m.value("pointer", std::string()).c_str(),
                       m.value("message", std::string()).c_str());
        }
        std::fprintf(stderr,
                     "dermis validate: Khronos glTF-Validator: %d errors, %d warnings, %d infos, "
                     "%d hints\n",
                     khronos.errors, khronos.warnings, khronos.infos, khronos.hints);
      } else {
        std::fprintf(stderr, "dermis validate: note: %s; ran the structural checks only\n",
                     khronos.why_not.c_str());
      }
    }
    std::fprintf(stderr, "dermis validate: %s: %s\n", a.input.c_str(), valid ? "valid" : "INVALID");
  }
  return valid ? kExitOk : kExitFailure;
}

}  // namespace

void AddValidateCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<ValidateArgs>();
  CLI::App* cmd = app->add_subcommand(
      "validate",
      "Check a file: glTF (.gltf/.glb) through the importer's structural checks and the Khronos "
      "glTF-Validator when installed; .dsurf (checksum, counts, indices, the runtime load); OBJ "
      "and "
      "PLY through the readers fit and tessellate use; other formats through Assimp. Exit 0 valid, "
      "1 invalid.");
  cmd->add_option("INPUT", args->input, "File to check")->required();
  cmd->add_flag("--json", args->json,
                "Print a JSON report (schema dermis.validate/1; the Khronos messages included)");
  cmd->add_flag("--require-khronos", args->require_khronos,
                "glTF: fail when the Khronos glTF-Validator cannot run");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing for a valid file");
  cmd->callback([run, args]() { *run = [args]() { return RunValidate(*args); }; });
}

}  // namespace dermis::cli
