// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "character_args.h"

#include "dermis/core/file_bytes.h"

namespace dermis::cli {

Status ReadCharacterFile(const std::string& path, std::string* bytes, Character* out) {
  Status s = ReadFileBytes(path, "a .dsurf file", bytes);
  if (!s.ok()) return s;
  if (DsurfFileVersion(*bytes) == 1) return ReadCharacter(path, out);
  return ParseCharacter(*bytes, path, out);
}

DeformerKind DeformerFromName(const std::string& name) {
  if (name == "lbs") return DeformerKind::kLbs;
  if (name == "dqs") return DeformerKind::kDqs;
  return DeformerKind::kSweep;
}

CharacterPoseMode PoseModeFromName(const std::string& name) {
  return name == "lod" ? CharacterPoseMode::kLod : CharacterPoseMode::kBound;
}

void AddEvaluationOptions(CLI::App* cmd, const std::string& bound_help, std::string* mode,
                          int* level, int* displacement_levels) {
  cmd->add_option("--mode", *mode,
                  "bound: " + bound_help + "; lod: the surface tessellated at --level")
      ->check(CLI::IsMember({"bound", "lod"}))
      ->capture_default_str();
  cmd->add_option("--level", *level, "lod: segments per control-face edge")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--displacement-levels", *displacement_levels,
                  "Displacement levels to evaluate (-1: all, 0: the domain surface)")
      ->check(CLI::Range(-1, 13))
      ->capture_default_str();
}

}  // namespace dermis::cli
