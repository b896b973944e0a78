// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The engine runtime (docs/engine-integration.md): a character loaded once into an
/// immutable, thread-shareable RuntimeCharacter; outputs (bound vertices or a tessellation
/// level) precomputed once into RuntimeOutput; per character instance a RuntimeInstance with
/// the deformers' state and all scratch memory; per frame two jobs in the style of
/// ozz-animation, each with Validate() and Run():
///
///   PoseJob      joint palette -> sweep / LBS / DQS deformed control vertices -> refitted
///                patches (paper section 5, Eq. 2), packed for the evaluation kernel;
///   EvaluateJob  patches -> positions and unit normals of the displaced surface (Eq. 3-4)
///                into caller-owned strided float buffers.
///
/// Run() neither allocates nor throws. Core + GLM only (no Eigen, no plugins).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/deform/deformer.h"
#include "dermis/runtime/character.h"
#include "dermis/runtime/evaluation_plan.h"

namespace dermis {

/// Which original vertex a bound output vertex is.
struct BoundVertexRef {
  Index mesh = kInvalidIndex;
  Index primitive = kInvalidIndex;
  Index vertex = kInvalidIndex;
};

/// A character (or a plain version-1 surface, as one static part) ready for the runtime.
/// Immutable after loading; share one between any number of threads and instances.
class RuntimeCharacter {
 public:
  ~RuntimeCharacter();

  /// Loads a .dsurf of either version. Errors name the file and what is wrong.
  static Status Load(const std::string& path, std::unique_ptr<RuntimeCharacter>* out);
  /// The same from bytes in memory; `name` is used in messages.
  static Status FromBytes(std::string_view bytes, const std::string& name,
                          std::unique_ptr<RuntimeCharacter>* out);
  /// Takes a character built in memory (for example by the offline fitter).
  static Status FromCharacter(Character character, std::unique_ptr<RuntimeCharacter>* out);

  const Character& character() const { return character_; }
  std::size_t num_parts() const { return character_.parts.size(); }
  /// Control vertices of part p.
  std::size_t num_control_vertices(std::size_t p) const;
  /// Joints of part p's skin (0 for a static part: its pose is the rest pose).
  std::size_t num_joints(std::size_t p) const;
  /// The rig of part p's skin, or null for a static part.
  const SkinRig* rig(std::size_t p) const;
  /// The original vertices bound to part p, in (mesh, primitive, vertex) order, and their
  /// surface locations: the output order of an OutputKind::kBound output.
  const std::vector<BoundVertexRef>& bound_vertices(std::size_t p) const;
  const std::vector<SampleLocation>& bound_locations(std::size_t p) const;
  /// Bytes the character holds (surfaces, displacements, rigs, bindings, the source asset as
  /// loaded), excluding outputs and instances.
  std::size_t memory_bytes() const;
  /// Maps an engine's joint order onto part p's skin by name: remap[j] (num_joints(p) entries,
  /// resized) = index in `engine_names` of skin joint j's name. Fails naming the first skin
  /// joint the engine lacks, or an engine name listed twice that a skin joint needs.
  Status RemapJointsByName(std::size_t p, const std::vector<std::string_view>& engine_names,
                           std::vector<std::int32_t>* remap) const;

 private:
  RuntimeCharacter() = default;
  Character character_;
  std::vector<SkinRig> rigs_;                           // per skin
  std::vector<bool> rig_ok_;                            // per skin
  std::vector<std::vector<BoundVertexRef>> bound_;      // per part
  std::vector<std::vector<SampleLocation>> locations_;  // per part
};

/// What an output evaluates.
enum class OutputKind : std::uint8_t {
  kBound = 0,  ///< The part's bound original vertices (RuntimeCharacter::bound_vertices()).
  kLevel = 1,  ///< The part's uniform tessellation at `level` (TessellationPattern order).
};

/// Settings of a RuntimeOutput.
struct OutputSpec {
  OutputKind kind = OutputKind::kLevel;
  int level = 4;                 ///< kLevel: segments per control-face edge, 1..64.
  int displacement_levels = -1;  ///< Displacement levels (-1: all, 0: the domain surface).
  int threads = 1;               ///< Threads of the precomputation (0: all cores).
  /// kBound only: precompute tangent frames so that EvaluateJob can write tangents (from the
  /// source's TANGENT, else from TEXCOORD_0; 16 bytes per vertex; docs/engine-integration.md).
  bool tangents = false;
};

/// One part's output, precomputed (EvaluationPlan): immutable, thread-shareable. Keeps a
/// pointer to its character, which must outlive it.
class RuntimeOutput {
 public:
  ~RuntimeOutput();
  /// Builds the output of part `part`. Fails on a part out of range or a bad spec.
  static Status Build(const RuntimeCharacter& character, std::size_t part, const OutputSpec& spec,
                      std::unique_ptr<RuntimeOutput>* out);

  const RuntimeCharacter& character() const { return *character_; }
  std::size_t part() const { return part_; }
  const OutputSpec& spec() const { return spec_; }
  std::size_t num_vertices() const { return plan_.num_samples(); }
  /// kLevel: 3 vertex indices per counter-clockwise triangle; kBound: empty (the source
  /// primitives' indices apply).
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }
  const EvaluationPlan& plan() const { return plan_; }
  /// OutputSpec::tangents: 4 floats per vertex (PlanOutputBuffers::tangent_frames); else empty.
  const std::vector<float>& tangent_frames() const { return tangent_frames_; }
  /// Bytes the output holds (plan, triangles, tangent frames).
  std::size_t memory_bytes() const {
    return plan_.memory_bytes() + triangles_.capacity() * 4 + tangent_frames_.capacity() * 4;
  }

 private:
  RuntimeOutput() = default;
  const RuntimeCharacter* character_ = nullptr;
  std::size_t part_ = 0;
  OutputSpec spec_;
  EvaluationPlan plan_;
  std::vector<std::uint32_t> triangles_;
  std::vector<float> tangent_frames_;
};

/// One posed instance of a character: the deformers (the sweep keeps history from frame to
/// frame) and every per-frame buffer. Use one instance per character on screen; one thread at
/// a time runs its PoseJob, after which any number of EvaluateJobs may read it concurrently.
class RuntimeInstance {
 public:
  ~RuntimeInstance();
  /// Binds the deformers of every skinned part (allocates; not per frame). The instance starts
  /// in the rest pose.
  static Status Create(const RuntimeCharacter& character, DeformerKind deformer,
                       std::unique_ptr<RuntimeInstance>* out);

  const RuntimeCharacter& character() const { return *character_; }
  DeformerKind deformer() const { return kind_; }
  /// Forgets the sweep's twist history (before a pose unrelated to the last one).
  void ResetHistory();
  /// Part p's current control vertices and packed patches (kPackedPatchStride floats each).
  const Vec3* control_positions(std::size_t p) const;
  const float* packed_patches(std::size_t p) const;
  /// Bytes the instance holds (deformer state, control vertices, patches, palettes).
  std::size_t memory_bytes() const;

 private:
  friend struct PoseJob;
  struct PartState;
  RuntimeInstance() = default;
  const RuntimeCharacter* character_ = nullptr;
  DeformerKind kind_ = DeformerKind::kSweep;
  std::vector<std::unique_ptr<PartState>> parts_;
};

/// Poses one part of an instance: SetPose + Deform of its control vertices, refit of the
/// local patches (Eq. 2), packing. No allocation.
struct PoseJob {
  RuntimeInstance* instance = nullptr;
  std::size_t part = 0;
  /// num_skin_matrices column-major 4x4 float matrices world(joint) * inverseBind(joint), one
  /// per joint of the part's skin (glTF's joint matrices before the mesh node's inverse). A
  /// static part takes none and stays in its rest pose.
  const float* skin_matrices = nullptr;
  std::size_t num_skin_matrices = 0;
  /// Optional: the engine's joint order. When set, skin_matrices holds the engine's palette of
  /// num_skin_matrices matrices (any count) and skin joint j takes matrix joint_remap[j]; the
  /// array has num_joints(part) entries (RemapJointsByName()).
  const std::int32_t* joint_remap = nullptr;

  /// True if the job can run: instance set, part in range, the right matrix count (with a
  /// remap: every remapped index inside the palette).
  bool Validate() const;
  /// Validate(), then the pose. False (pose unchanged) if invalid or a matrix is not finite.
  bool Run() const;
};

/// Evaluates blocks [block_begin, block_end) of an output with an instance's current patches.
/// Split the block range over threads for parallel evaluation; results do not depend on the
/// split.
struct EvaluateJob {
  const RuntimeOutput* output = nullptr;
  const RuntimeInstance* instance = nullptr;
  std::size_t block_begin = 0;
  std::size_t block_end = SIZE_MAX;  ///< Clamped to output->plan().num_blocks().
  /// output->num_vertices() entries each. buffers.tangents needs an output built with
  /// OutputSpec::tangents (Run() fails otherwise); Run() supplies tangent_frames itself.
  PlanOutputBuffers buffers;
  SimdPath path = SimdPath::kAuto;

  bool Validate() const;
  bool Run() const;
};

}  // namespace dermis
