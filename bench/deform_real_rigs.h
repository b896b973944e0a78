// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// bench_deform, part 3: LBS, DQS and the sweep on the shared glTF rigs, fitted and posed as a
// user would (dermis fit, dermis animate --mode lod): bends and twists built on the assets' own
// skeletons, and every clip of every character on the fitted surface.
#pragma once

#include <string>

namespace dermis::bench {

/// Settings of the real-rig part of bench_deform.
struct RealRigOptions {
  std::string data;           ///< Folder of the shared glTF files.
  int level = 4;              ///< Tessellation level of the lod surface (dermis animate default).
  double twist_step = 5.0;    ///< Degrees per frame of the animated 0..360 degree twist.
  int clip_frames = 60;       ///< Evenly spaced times per clip of the fitted-clip table.
  bool clips = true;          ///< Also every clip of every character on the fitted surface.
  int threads = 2;            ///< Threads of the fits and evaluations (results do not vary).
  double input_quads = -1.0;  ///< CharacterFitOptions::input_quads; < 0: its default.
  std::string only;
  /// Non-empty: a folder for contact sheets of the limb tests (one PNG per test: a row per
  /// deformer, a column per pose).
  std::string pictures;  ///< Non-empty: only the assets whose file name contains it.
};

/// Prints the real-rig tables (see deform_real_rigs.cpp for the definitions).
void RunRealRigs(const RealRigOptions& options);

}  // namespace dermis::bench
