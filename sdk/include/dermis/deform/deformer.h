// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Skeletal deformers of control vertices (runtime; core + GLM only): linear blend
/// skinning and dual-quaternion skinning as baselines, and the sweep-based deformer (Hyun et
/// al. 2005 as reconstructed in docs/deformation.md). One interface: the rig and the rest
/// vertices are described once (Make*Deformer), then per frame SetPose() takes the joint
/// palette and Deform() writes the deformed vertices into caller-owned buffers.
///
/// Paper context [Y section 5]: only the control vertices of a displaced surface are deformed;
/// the local patches are refitted from them and the unchanged displacements ride along.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dermis/core/status.h"
#include "dermis/core/types.h"

namespace dermis {

/// A skeleton as the deformers see it: the joints of one skin, in the skin's joint order.
struct SkinRig {
  /// Parent of each joint within the rig, or -1 (a root, or a parent that is not a joint).
  std::vector<Index> parents;
  /// Bind pose of each joint: the inverse of its inverse bind matrix, mapping the joint's local
  /// frame to mesh (bind) space. Must be invertible and finite; the translation column is the
  /// joint's position at bind time.
  std::vector<glm::dmat4> bind;
  /// Joint names, for messages only (may be empty).
  std::vector<std::string> names;
};

/// Up to four influences of one vertex; weights are non-negative and sum to 1 (unused slots
/// have weight 0).
struct VertexWeights {
  glm::u16vec4 joints{0};
  glm::vec4 weights{0.0f};
};

/// Checks a rig and its influences: joint count, parents in range and acyclic, finite
/// invertible bind matrices, joint indices in range, finite non-negative weights with a
/// positive sum. `name` prefixes messages. `influences` may be null when `count` is 0.
Status ValidateRig(const SkinRig& rig, const VertexWeights* influences, std::size_t count,
                   const std::string& name);

/// Which deformer. The values are those of the C API's dermis_deformer.
enum class DeformerKind : std::uint8_t { kLbs = 0, kDqs = 1, kSweep = 2 };

class Deformer;

/// One row of the deformer table: everything the SDK, the C API and the tools know of a
/// deformer. The table (deform/deformer_registry.cpp) is the only list of deformers: a new one
/// is a DeformerKind value, its Make function and one row (docs/overview.md).
struct DeformerInfo {
  DeformerKind kind;
  const char* name;         ///< As tools and messages name it: "lbs", "dqs", "sweep".
  const char* description;  ///< One line for help texts.
  /// Creates the deformer with its default settings (MakeDeformer()).
  Status (*make)(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                 const VertexWeights* influences, std::size_t count,
                 std::unique_ptr<Deformer>* out);
};

/// The deformer table, in DeformerKind order; `*count` receives its length.
const DeformerInfo* DeformerTable(std::size_t* count);

/// The row of `kind`, or null for a value that names no deformer.
const DeformerInfo* FindDeformer(DeformerKind kind);

/// The row named `name` (exactly, lower case), or null.
const DeformerInfo* FindDeformer(std::string_view name);

/// The kind named `name`; kInvalidInput "unknown deformer 'NAME' (deformers: lbs, dqs,
/// sweep)" if there is none.
Status DeformerFromName(std::string_view name, DeformerKind* out);

/// The names of every deformer, in table order.
std::vector<std::string> DeformerNames();

/// "lbs", "dqs", "sweep"; "unknown" for a value that names no deformer.
const char* DeformerName(DeformerKind kind);

/// A deformer of a fixed set of rest vertices by one rig.
///
/// Threading: SetPose() is called once per frame by one thread; afterwards Deform() may run
/// concurrently on disjoint ranges. Neither allocates, neither throws.
class Deformer {
 public:
  virtual ~Deformer() = default;
  virtual DeformerKind kind() const = 0;
  virtual std::size_t num_vertices() const = 0;
  virtual std::size_t num_joints() const = 0;

  /// Takes the joint palette of a frame: `skin_matrices[j]` = world(joint j) * inverseBind(j),
  /// mapping mesh (bind) space to world space (the matrices glTF skinning uses), one per joint.
  /// Fails, keeping the previous pose, if a matrix is not finite (the only case that builds an
  /// error message, so the only one that allocates). A singular matrix (a joint scaled to 0)
  /// is accepted: DQS and the sweep then take no rotation from it, only its linear part.
  virtual Status SetPose(const glm::dmat4* skin_matrices) = 0;

  /// Deformed positions of vertices [begin, end) into `positions[begin..end)`; if `normals` is
  /// non-null and rest normals were given, the deformed unit normals too.
  virtual void Deform(std::size_t begin, std::size_t end, Vec3* positions, Vec3* normals) const = 0;

  /// Forgets what earlier poses left behind (the sweep's twist unwrapping); call it before a
  /// pose unrelated to the previous one. LBS and DQS keep no history.
  virtual void ResetHistory() {}
};

/// Linear blend skinning: x' = sum_j w_j M_j x; normals by the inverse transpose of the blended
/// matrix. `rest_normals` may be null. Copies what it needs.
Status MakeLbsDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                       const VertexWeights* influences, std::size_t count,
                       std::unique_ptr<Deformer>* out);

/// Dual-quaternion skinning (Kavan et al. 2008): each joint's rigid part as a unit dual
/// quaternion, blended in the hemisphere of the vertex's strongest joint and normalised by the
/// real part; a joint's non-rigid part (scale, shear) is applied first, blended linearly (the
/// two-phase variant). Normals rotate with the blended rotation (inverse transpose of the
/// linear part).
Status MakeDqsDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                       const VertexWeights* influences, std::size_t count,
                       std::unique_ptr<Deformer>* out);

/// Settings of the sweep deformer (docs/deformation.md).
struct SweepOptions {
  /// Samples per bone of the coarse scan that binds each vertex to its closest trajectory
  /// point (refined by golden-section search afterwards).
  int stations_per_bone = 16;
  /// Blend half-length at a joint: blend_radius_factor * r, with r the skin radius there (the
  /// 90th percentile of the distance from the bone polyline of the vertices weighted to the
  /// chain within half the shorter bone of the joint), at most max_blend_fraction of the
  /// shorter adjacent bone.
  double blend_radius_factor = 1.0;
  double max_blend_fraction = 0.49;
  /// The blend half-length is also at least the reach of the joint's painted transition: the
  /// 90th percentile of the distance along the chain from the joint of the vertices it shares
  /// with the joint before it (each of the two holding at least a tenth of their weight).
  bool follow_weights = true;
  /// A joint whose largest blend zone would fold the skin (arc radius below the skin radius)
  /// at a bend below this angle (radians) or below its rest bend is not swept through: its
  /// chain is cut there and the skin around it blends the two chains' frames (a torso or neck
  /// on short spine bones, a thick tail). Default 70 degrees: bones shorter than about 1.43
  /// times the skin radius (max_blend_fraction 0.49); on the shared characters this cuts every
  /// spine and neck joint and keeps every elbow, knee and wrist swept (docs/deformation.md,
  /// "Chains": 60 degrees left CesiumMan's mid-spine, folding at 63 degrees, swept between two
  /// cut joints, and the clip lost more volume than under DQS).
  double min_fold_angle = 1.2217304763960306;
  /// Let the blend half-length grow with the bend as 1.1 r tan(theta / 2), so the arc radius
  /// stays above the skin radius and cross sections do not cross inside the bend (up to the
  /// cap above).
  bool grow_blend_with_bend = true;
  /// Volume correction: a sin^2 bump of half-width volume_width_factor * h scales the cross
  /// sections so that the swept volume of the zone is kept (Pappus); false: no correction. The
  /// bump only widens (height in [0, 1]): a joint posed straighter than its rest bend is left
  /// as the arc puts it (docs/deformation.md "Volume").
  bool preserve_volume = true;
  double volume_width_factor = 4.0;
  /// Clamp vertices on the inside of a bend against the joint's bisector plane.
  bool clamp_folds = true;
  /// A vertex is bound to a single chain when that chain holds at least this share of its
  /// weight; otherwise to each chain holding more than blend_threshold, their frames blended as
  /// dual quaternions with the joints of the smaller shares (by their own rigid transforms).
  /// The binding is continuous in the weights, so that noise in painted weights does not step
  /// the posed surface (docs/deformation.md, "Binding"; the ramps below). In (0.5, 1].
  double single_chain_threshold = 0.95;
  /// Below single_chain_threshold the other chains and joints fade in (smoothstep) over this
  /// much of the strongest chain's share: their weights are scaled by 1 at a share of
  /// single_chain_threshold - single_chain_ramp or less, by 0 from single_chain_threshold on.
  /// 0: a snap at the threshold. In [0, single_chain_threshold - 0.5], so that the strongest
  /// chain, which the fade spares, cannot change while it is under way.
  double single_chain_ramp = 0.1;
  /// A chain's share is bound to its sweep by smoothstep((share - blend_threshold) /
  /// blend_threshold): not below blend_threshold, fully from twice it; the rest of the share
  /// follows its joints' own rigid transforms. In [0, (single_chain_threshold -
  /// single_chain_ramp) / 2], so that a vertex reaching the single-chain share is fully bound
  /// to that chain already. (Before 2026-12-08 both rules were snaps at their thresholds.)
  double blend_threshold = 0.05;
};

/// The sweep deformer: chains of the skeleton become sweeps (a trajectory through the joints,
/// circular-arc blended at interior joints; rotation-minimising frames with the joints' twists
/// spread along each bone and unwrapped against the previous frame). Every joint that carries
/// skin owns a bone (BuildSweepChains(): branch joints continue straight ahead, a skinned last
/// joint gets a virtual end bone along its vertices). Each vertex is bound once, in the bind
/// pose, to the sweeps of the chains its weights name (parameter and cross-section
/// coordinates); a vertex of several chains blends their rigid frames at its points as dual
/// quaternions (plus their volume and fold corrections by weight), never their positions.
/// Twist unwrapping makes SetPose() stateful: call ResetHistory() before jumping to a pose
/// unrelated to the previous one (twists are then taken the short way, within +-180 degrees).
Status MakeSweepDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                         const VertexWeights* influences, std::size_t count,
                         const SweepOptions& options, std::unique_ptr<Deformer>* out);

/// Creates the deformer of `kind` with its default settings (the table's make function);
/// kInvalidInput for a value that names no deformer.
Status MakeDeformer(DeformerKind kind, const SkinRig& rig, const Vec3* rest_positions,
                    const Vec3* rest_normals, const VertexWeights* influences, std::size_t count,
                    std::unique_ptr<Deformer>* out);

}  // namespace dermis
