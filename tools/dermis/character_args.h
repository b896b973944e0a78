// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// What `dermis export`, `animate` and `render` share: the names of deformers and pose modes on
// the command line, the evaluation options, clips by name or index.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/deform/deformer.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/runtime/character.h"

namespace dermis::cli {

/// Adds the option `flag` (e.g. "--deformer") naming a deformer of the deformer table
/// (dermis/deform/deformer.h); its help is `help` followed by every deformer and what it is.
CLI::Option* AddDeformerOption(CLI::App* cmd, const std::string& flag, const std::string& help,
                               std::string* name);

/// The poser options of `export`, `animate` and `render`: the deformer by name (an unknown
/// name is an error naming the deformers), mode "bound" or "lod", level, displacement levels,
/// threads.
Status MakePoseOptions(const std::string& deformer, const std::string& mode, int level,
                       int displacement_levels, int threads, CharacterPoseOptions* out);

/// The one set of evaluation options (docs/cli.md, "Options every command shares"): the same
/// names, ranges, meanings and defaults in `tessellate`, `export`, `animate` and `render`.
/// --mode: what a character's meshes are.
constexpr const char* kDefaultMode = "bound";
/// --level n: segments per control-face edge of the tessellation, 1..kMaxLevel.
constexpr int kDefaultLevel = 6;
constexpr int kMaxLevel = 128;
/// --displacement-levels L: -1 all the levels the file has (the default), 0 the domain surface
/// alone, L > 0 the first L levels (more than the file has: all of them); at most
/// kMaxBsplineLevels (the most a .dsurf can hold).
constexpr int kAllDisplacementLevels = -1;

/// Adds --mode bound|lod (bound described by `bound_help`) with kDefaultMode.
CLI::Option* AddModeOption(CLI::App* cmd, const std::string& bound_help, std::string* mode);
/// Adds --level (and -l when `short_name`) with kDefaultLevel and the range 1..kMaxLevel.
CLI::Option* AddLevelOption(CLI::App* cmd, int* level, bool short_name = false);
/// Adds --displacement-levels with kAllDisplacementLevels and the range -1..kMaxBsplineLevels.
CLI::Option* AddDisplacementLevelsOption(CLI::App* cmd, int* displacement_levels);

/// Registers the three options above, shared by `export`, `animate` and `render`.
void AddEvaluationOptions(CLI::App* cmd, const std::string& bound_help, std::string* mode,
                          int* level, int* displacement_levels);

/// "clips: 0 'walk', 1 'run'" (or "it has no clips"), for messages.
std::string ClipList(const Asset& asset);

/// The clip named by `arg` (a name first, then an index; "rest": the rest pose, -1; empty:
/// clip 0, or the rest pose without clips). Errors name `input` and list the clips.
Status ResolveClip(const Asset& asset, const std::string& input, const std::string& arg, int* clip);

}  // namespace dermis::cli
