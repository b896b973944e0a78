// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Posing a fitted character offline (paper section 5): a pose of the skeleton moves the
/// control vertices of every skinned part through a Deformer (LBS, DQS or the sweep), the local
/// patches are refitted from them and the unchanged displacements ride along; the bound original
/// vertices (`bound`) or the tessellation of every part (`lod`) are evaluated there, in world
/// space. Unfitted parts are posed as a glTF viewer poses them (PosePrimitive: linear blend
/// skinning, or the node's world matrix), static parts by their node's world matrix applied to
/// the rest surface. Also the static glTF asset of one pose and the morph-target bake of every
/// clip (docs/characters.md, "Posing and baking").
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/asset/asset_pose.h"
#include "dermis/core/progress.h"
#include "dermis/core/status.h"
#include "dermis/deform/deformer.h"
#include "dermis/runtime/character.h"

namespace dermis {

/// What is evaluated on the posed surfaces.
enum class CharacterPoseMode : std::uint8_t {
  kBound = 0,  ///< The original vertices at their fitted parameters (BuildBoundAsset()).
  kLod = 1,    ///< Each part tessellated at a level (BuildLodAsset()).
};

/// Settings of a CharacterPoser.
struct CharacterPoseOptions {
  DeformerKind deformer = DeformerKind::kSweep;  ///< Deformer of the control vertices.
  CharacterPoseMode mode = CharacterPoseMode::kBound;
  int level = 4;                 ///< `lod`: segments per control-face edge (1..64).
  int displacement_levels = -1;  ///< Displacement levels evaluated (-1: all, 0: none).
  int threads = 1;               ///< Threads of Evaluate() (0: all cores); results do not vary.
};

/// One primitive drawn by one node of CharacterPoser::asset().
struct DrawnPrimitive {
  Index node = kInvalidIndex;
  Index mesh = kInvalidIndex;
  Index primitive = kInvalidIndex;
};

/// The posed vertices of one drawn primitive, in world space.
struct PosedPrimitive {
  std::vector<Vec3> positions;
  /// Unit normals, one per position; empty for points and lines.
  std::vector<Vec3> normals;
};

/// Default rate at which a clip is stepped from its start to the posed time (steps per second).
constexpr double kDefaultPoseStepsPerSecond = 30.0;

/// The times a clip is played through to reach `time` (seconds, >= 0): 0, 1/rate, 2/rate, ...
/// while below `time` by more than a thousandth of a step (and in float32), then `time` itself. The
/// sweep deformer's twist unwrapping depends on the poses that came before, so a pose at `time` is
/// the last of these steps; the bake's frames are exactly these times for the clip's duration, so
/// posing at a frame time repeats the bake's history.
std::vector<double> ClipStepTimes(double time, double steps_per_second);

/// Poses one character: built once (deformers bound, patches' operators shared with the
/// character), then per pose SetPose() (cheap: the deformers' palettes) and Evaluate() (deform,
/// refit, evaluate). Keeps a pointer to the character, which must outlive it.
///
/// The drawn primitives are those of every node of asset() that has a mesh, in node order,
/// primitives in mesh order (what tests/js/three_pose.js lists). A node with a skin is posed
/// through that skin (its own transform ignored, glTF 2.0 section 3.7.3): one deformer per
/// (skin, part) pair of control vertices with the part's transferred weights.
class CharacterPoser {
 public:
  CharacterPoser();
  ~CharacterPoser();
  CharacterPoser(CharacterPoser&&) noexcept;
  CharacterPoser& operator=(CharacterPoser&&) noexcept;
  CharacterPoser(const CharacterPoser&) = delete;
  CharacterPoser& operator=(const CharacterPoser&) = delete;

  /// Builds the poser: the export asset of `options.mode`, the rest evaluation of every part
  /// and the deformers. Fails (naming the asset's source) on bad options or a bad rig; a
  /// deformer that is not available gives its kUnsupported status.
  static Status Build(const Character& character, const CharacterPoseOptions& options,
                      CharacterPoser* out);

  /// The asset whose primitives are posed: BuildBoundAsset() or BuildLodAsset() of the
  /// character (topology, texture coordinates, colours, materials, nodes, skins, clips; its
  /// positions are the rest ones in mesh space).
  const Asset& asset() const;
  const std::vector<DrawnPrimitive>& drawn() const;
  const CharacterPoseOptions& options() const;
  /// Where each vertex of drawn() primitive `drawn_index` lies on a fitted part's surface:
  /// `lod`, the tessellation sample (vertex i is the part pattern's sample i); `bound`, the
  /// original vertex's binding (part < 0 for a vertex of an unfitted part). Empty for a
  /// primitive that no part replaces, or an index out of range. Owned by the poser.
  const std::vector<VertexBinding>& surface_locations(std::size_t drawn_index) const;

  /// Takes a pose of asset() (one history step of the sweep): world and skin matrices, and each
  /// deformer's SetPose(). Fails, naming the skin and joint, on a matrix that is not invertible.
  Status SetPose(const AssetPose& pose);

  /// Forgets the deformers' history (call before a pose unrelated to the previous one).
  void ResetHistory();

  /// Evaluates the last pose given to SetPose(): `out` gets one entry per drawn() primitive.
  Status Evaluate(std::vector<PosedPrimitive>* out);

  /// ResetHistory(), then clip `clip` played through ClipStepTimes(min(time, duration),
  /// steps_per_second) and, past the clip's end, `time`
  /// (SetPose() at each step), then Evaluate(). `clip` < 0: the rest pose (RestPose()). Times past
  /// the clip's end hold its last keyframe. `progress`, if set, is called once per pose step
  /// and once for the evaluation ("posing steps", done, steps + 1).
  Status PoseClip(int clip, double time, double steps_per_second, std::vector<PosedPrimitive>* out,
                  const ProgressCallback& progress = {});

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// A static (unskinned, unanimated) asset of one pose: one root node with an identity transform
/// per drawing node of poser.asset() (named after it), each with a mesh of its posed primitives:
/// world-space positions and normals, the source's indices, mode, texture coordinates, colours
/// and material. Tangents, skins, morph targets and clips are not kept; materials, textures,
/// images and samplers are.
Status BuildPosedAsset(const CharacterPoser& poser, const std::vector<PosedPrimitive>& posed,
                       Asset* out);

/// What BuildBakedAsset() made.
struct CharacterBakeReport {
  std::vector<std::size_t> frames;  ///< Per clip.
  std::size_t targets = 0;          ///< Morph targets per primitive (all clips' frames).
  std::size_t vertices = 0;         ///< Vertices of all baked primitives.
  /// vertices * targets: each costs 24 bytes (a position and a normal delta) in the file.
  std::uint64_t vertex_frames = 0;
};

/// Bakes every clip of poser->asset(), sampled at ClipStepTimes(duration, fps) (each clip
/// played from its start after ResetHistory()), into the morph targets of a static asset
/// (BuildPosedAsset() of the rest pose; the base positions are the rest pose's): one target per
/// frame of every clip, holding (frame - rest) world-space position and normal deltas, and one
/// animation per clip whose weights channel on every baked node is one-hot at the clip's own
/// frames (LINEAR: exact at the frames, linear in between). Any glTF viewer thus plays exactly
/// the poser's motion, the sweep's included. Fails when the asset has no clips.
/// `progress`, if set, is called once per baked frame ("baking frames", done, total).
Status BuildBakedAsset(CharacterPoser* poser, double fps, Asset* out, CharacterBakeReport* report,
                       const ProgressCallback& progress = {});

}  // namespace dermis
