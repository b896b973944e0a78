// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: two .dsurf files of the same character (for example a fitted character and
// its runtime archive) run through the engine runtime with the same poses, output against
// output. Links dermis::runtime only.
#pragma once

#include <string>

#include "dermis/deform/deformer.h"

namespace dermis::test {

/// How far the runtime's frames of `b` are from those of `a`.
struct FrameDeviation {
  double max = 0.0;       ///< Largest |b - a| over every vertex, part and frame.
  double mean = 0.0;      ///< Mean |b - a|.
  double diagonal = 0.0;  ///< Of a's rest output (all parts), model units.
  std::size_t vertices = 0;
};

/// Loads both (RuntimeCharacter::FromBytes, REQUIREd to succeed), builds the level-`level`
/// outputs (0: the bound outputs) of every part, and evaluates `frames` frames with
/// `deformer`: frame 0 is the rest pose, frame f > 0 turns every joint of every skin by
/// 25 f degrees about its own axis through its bind position (a pose far from the rest one,
/// composed the same way for both files). REQUIREs equal part, joint and vertex counts.
FrameDeviation CompareRuntimeFrames(const std::string& a, const std::string& b, int level,
                                    DeformerKind deformer, int frames);

}  // namespace dermis::test
