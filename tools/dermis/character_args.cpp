// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "character_args.h"

#include <charconv>

#include "dermis/core/file_io.h"
#include "dermis/surface/bspline_displacement.h"

namespace dermis::cli {

CLI::Option* AddDeformerOption(CLI::App* cmd, const std::string& flag, const std::string& help,
                               std::string* name) {
  std::size_t count = 0;
  const DeformerInfo* table = DeformerTable(&count);
  std::string list;
  for (std::size_t i = 0; i < count; ++i) {
    list += std::string(i ? ", " : "") + table[i].name + " (" + table[i].description + ")";
  }
  return cmd->add_option(flag, *name, help + ": " + list)->check(CLI::IsMember(DeformerNames()));
}

Status MakePoseOptions(const std::string& deformer, const std::string& mode, int level,
                       int displacement_levels, int threads, CharacterPoseOptions* out) {
  CharacterPoseOptions options;
  const Status s = DeformerFromName(deformer, &options.deformer);
  if (!s.ok()) return s;
  options.mode = mode == "lod" ? CharacterPoseMode::kLod : CharacterPoseMode::kBound;
  options.level = level;
  options.displacement_levels = displacement_levels;
  options.threads = threads;
  *out = options;
  return Status::Ok();
}

CLI::Option* AddModeOption(CLI::App* cmd, const std::string& bound_help, std::string* mode) {
  *mode = kDefaultMode;
  return cmd
      ->add_option(
          "--mode", *mode,
          "Characters: bound (" + bound_help + ") or lod (the surface tessellated at --level)")
      ->check(CLI::IsMember({"bound", "lod"}))
      ->capture_default_str();
}

CLI::Option* AddLevelOption(CLI::App* cmd, int* level, bool short_name) {
  *level = kDefaultLevel;
  return cmd
      ->add_option(short_name ? "-l,--level" : "--level", *level,
                   "Segments per control-face edge of the tessellation (lod mode, surfaces)")
      ->check(CLI::Range(1, kMaxLevel))
      ->capture_default_str();
}

CLI::Option* AddDisplacementLevelsOption(CLI::App* cmd, int* displacement_levels) {
  *displacement_levels = kAllDisplacementLevels;
  return cmd
      ->add_option("--displacement-levels", *displacement_levels,
                   "Displacement levels evaluated: -1 all (default), 0 the domain surface alone, "
                   "L the first L")
      ->check(CLI::Range(-1, kMaxBsplineLevels))
      ->capture_default_str();
}

void AddEvaluationOptions(CLI::App* cmd, const std::string& bound_help, std::string* mode,
                          int* level, int* displacement_levels) {
  AddModeOption(cmd, bound_help, mode);
  AddLevelOption(cmd, level);
  AddDisplacementLevelsOption(cmd, displacement_levels);
}

std::string ClipList(const Asset& asset) {
  if (asset.animations.empty()) return "it has no clips";
  std::string list = "clips:";
  for (std::size_t c = 0; c < asset.animations.size(); ++c) {
    list += (c ? ", " : " ") + std::to_string(c) + " '" + asset.animations[c].name + "'";
  }
  return list;
}

// The clip named by `arg` (a name first, then an index; "rest": the rest pose, -1).
Status ResolveClip(const Asset& asset, const std::string& input, const std::string& arg,
                   int* clip) {
  if (arg.empty()) {
    *clip = asset.animations.empty() ? -1 : 0;
    return Status::Ok();
  }
  for (std::size_t c = 0; c < asset.animations.size(); ++c) {
    if (asset.animations[c].name == arg) {
      *clip = static_cast<int>(c);
      return Status::Ok();
    }
  }
  if (arg == "rest") {
    *clip = -1;
    return Status::Ok();
  }
  int index = -1;
  const auto r = std::from_chars(arg.data(), arg.data() + arg.size(), index);
  if (r.ec == std::errc() && r.ptr == arg.data() + arg.size() && index >= 0 &&
      static_cast<std::size_t>(index) < asset.animations.size()) {
    *clip = index;
    return Status::Ok();
  }
  return Status::InvalidInput(input + ": no clip '" + arg + "' (" + ClipList(asset) + ")");
}

}  // namespace dermis::cli
