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

}  // namespace dermis::cli
