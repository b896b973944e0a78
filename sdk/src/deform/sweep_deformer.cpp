// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Sweep-based deformation of control vertices (Hyun et al. 2005, "Sweep-based human
// deformation", as reconstructed in docs/notes/sweep.md section 1 and docs/deformation.md; used on
// the control mesh as in [Y] section 5).
//
// A chain J0..Jn of the skeleton becomes a sweep S(s) = C(s) + F(s) diag(sigma, sigma, 1) E:
// - trajectory C (docs/notes/sweep.md section 1.1): the bone lines, with a circular arc tangent
//   to both bones in a blend zone of half-length h_j around each interior joint; rest arc length s
//   maps linearly to each straight piece and to the arc angle;
// - frames F (1.2): the start joint's rotation transported along C (rotation-minimising: constant
//   on straight pieces, rotated about the arc axis on arcs, exact for circles), times a twist
//   about the tangent ramped in s from joint to joint (on past a joint as far as its painted
//   weight transition reaches); each twist is the swing-twist residue of the joint's rotation
//   against the transported frame, unwrapped along the chain and against the previous pose, so
//   twists past 180 degrees do not flip;
// - scale sigma (1.5): a sin^2 bump of half-width W around each bent joint, its height solved
//   per frame so that the swept volume of the zone (Pappus, over the section profile measured
//   from the vertices bound there, with what the fold clamp removes) equals the rest one,
//   never below 0 (a joint straighter than its rest bend is not thinned);
// - folds (1.6): vertices of the two bones of a bent joint are clamped against its bisector
//   plane on the inside of the bend.
// Every joint that carries skin owns a bone (sweep_chains.cpp, docs/deformation.md "Chains"):
// a chain runs through a branch joint into the child that continues it, a chain whose last
// joint carries skin (a hand, a head, a foot) ends in a virtual bone along that joint's
// vertices, and a joint too sharp or too short for its skin is cut.
// Vertices are bound once in the bind pose (1.3): to each chain holding enough of their skin
// weight, at the closest point of that chain's rest trajectory on the bones they are weighted
// to, storing the offset in the start-transported frame. A vertex of one chain is the sweep's
// point; a vertex of several chains (shoulder, hip, neck base) blends the chains' rigid frames
// at its bound points as dual quaternions (Kavan et al. 2008) and adds the weighted sum of their
// non-rigid corrections (volume bump, fold clamp): never a linear blend of positions rotated far
// apart.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "deform/deform_math.h"
#include "dermis/deform/deformer.h"
#include "dermis/deform/sweep_chains.h"

namespace dermis {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMinBend = 1e-7;  // radians; below this a joint is straight
// The volume bump's support is measured in bins along the chain (the section profile of a
// tapered limb), and the fold clamp's effect is integrated at a few points per bin.
constexpr int kBumpBins = 32;
constexpr int kFoldSamples = 4;

// 0 for x <= 0, 1 for x >= 1, 3x^2 - 2x^3 between: the binding's ramps.
double SmoothStep(double x) {
  const double t = std::clamp(x, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

/// One evaluated pose of a chain's trajectory (rest or posed).
struct ChainGeom {
  std::vector<Vec3> p;         // joint positions, n + 1
  std::vector<Vec3> t;         // bone directions, n
  std::vector<double> theta;   // bend per joint (0 at the ends), n + 1
  std::vector<Vec3> axis;      // arc axis per joint
  std::vector<Vec3> a, b;      // arc start (on bone j-1) and end (on bone j) per joint
  std::vector<Vec3> centre;    // arc centre per joint
  std::vector<glm::dquat> u;   // transport after joint j's arc, u[0] = identity, n + 1
  std::vector<Vec3> bisector;  // unit (t[j-1] + t[j]) per joint
  std::vector<double> h;       // blend half-length per joint in rest arc length (0 at the ends)

  void Resize(std::size_t joints) {
    p.resize(joints);
    t.resize(joints - 1);
    theta.assign(joints, 0.0);
    axis.assign(joints, Vec3(0.0));
    a.resize(joints);
    b.resize(joints);
    centre.resize(joints);
    u.assign(joints, glm::dquat(1.0, 0.0, 0.0, 0.0));
    bisector.assign(joints, Vec3(0.0));
    h.assign(joints, 0.0);
  }
};

/// What a chain keeps from the bind pose.
struct Chain {
  std::vector<Index> joints;   // J0..Jn (rig indices); a virtual end repeats the last joint
  std::vector<double> s;       // rest arc length at each joint (polyline), n + 1
  std::vector<double> len;     // rest bone lengths, n
  std::vector<double> radius;  // skin radius around each interior joint
  std::vector<double> h_base;  // blend half-length of a slight bend
  std::vector<double> h_max;   // largest blend half-length (a share of the shorter bone)
  std::vector<double> w;       // volume bump half-width per joint (0: no bump)
  std::vector<double> reach;   // twist ramp of each joint: from the joint before to s + reach
  std::vector<Vec3> t0;        // rest bone directions
  ChainGeom rest;
  // Per-frame state (preallocated).
  ChainGeom pose;
  glm::dquat q0{1.0, 0.0, 0.0, 0.0};  // rotation of J0 relative to bind
  double scale = 1.0;                 // uniform scale of the whole chain in this pose
  double dqs_share = 0.0;             // 0: swept; 1: a joint stretches non-uniformly, DQS instead
  std::vector<double> tau;            // twist per joint
  std::vector<double> prev_tau;
  std::vector<double> k;  // bump height per joint
  // Per joint, kBumpBins bins over the bump's support [s_j - w_j, s_j + w_j], from the vertices
  // bound there: `section` = their mean squared radial offset (the section's area / pi),
  // `bumped` = that times their mean share of this chain (what the bump can add: a vertex
  // blended with other chains gets the bump at its share); `fold_beta` = the bump at
  // kFoldSamples points per bin.
  std::vector<double> section, bumped, fold_beta;
  // Per joint and bin, int b and int b^2 over the bin; per joint, sum_i A_i (1 - c_rest) times
  // the part of bin i on the rest arc (the rest zone's arc loss / pi).
  std::vector<double> bin_b1, bin_b2, rest_loss;
  // For the fold term, per joint and bin: sqrt(section) (the section's radius) and bumped /
  // section (the mean chain share); per joint, the largest section.
  std::vector<double> bin_radius, bin_share, widest;
  double length() const { return s.back(); }
  std::size_t bones() const { return len.size(); }
};

/// A vertex bound to one chain.
struct Binding {
  std::uint32_t chain = 0;
  std::uint32_t bone = 0;  // bone holding s (n - 1 beyond the end)
  double weight = 0.0;
  double s = 0.0;
  Vec3 axial{0.0}, radial{0.0};              // offset in the start-transported frame
  Vec3 normal{0.0};                          // rest normal in the same frame
  glm::dquat rest_back{1.0, 0.0, 0.0, 0.0};  // rest transport at s, inverted
  // Constant per binding, precomputed: the twist at s is tau[twist_full] plus the increments of
  // at most two joints still ramping there, and the bumps reaching s (first, count in
  // SweepDeformer::bumps_).
  std::uint16_t twist_full = 0;
  std::uint16_t twist_joint[2] = {0, 0};  // 0: unused
  double twist_share[2] = {0.0, 0.0};
  std::uint32_t bump_first = 0;
  std::uint16_t bump_count = 0;
};

/// One volume bump reaching a bound vertex: the joint and the bump's shape there.
struct BumpTerm {
  std::uint16_t joint = 0;
  double beta = 0.0;
};

/// The joints of a vertex that no chain binding carries (a chain share at most the blend
/// threshold), entering the blend by their own rigid transforms; weights in the bindings' scale.
struct LooseWeights {
  glm::u16vec4 joints{0};
  glm::dvec4 weights{0.0};
};

double ArcCompression(double theta) {
  if (theta < 1e-6) return 1.0;
  return 0.5 * theta / std::tan(0.5 * theta);
}

double Bump(double u, double w) {
  if (!(w > 0.0) || std::fabs(u) >= w) return 0.0;
  const double x = std::sin(kPi * (u + w) / (2.0 * w));
  return x * x;
}

/// Integrals of the bump b(u) = sin^2(pi (u + w) / (2 w)) = (1 + cos(pi u / w)) / 2 and of b^2
/// over [-a, a], a <= w (closed form).
double BumpIntegral(double a, double w) { return a + (w / kPi) * std::sin(kPi * a / w); }
double BumpSquaredIntegral(double a, double w) {
  return 0.75 * a + (w / kPi) * std::sin(kPi * a / w) +
         (w / (8.0 * kPi)) * std::sin(2.0 * kPi * a / w);
}

/// int_0^x b(u) du and int_0^x b(u)^2 du for |x| <= w (odd in x).
double BumpIntegralTo(double x, double w) { return 0.5 * BumpIntegral(x, w); }
double BumpSquaredIntegralTo(double x, double w) { return 0.5 * BumpSquaredIntegral(x, w); }

/// Area of the part of a disc of radius rho beyond a chord at distance y >= 0 from its centre.
double DiscSegment(double rho, double y) {
  if (!(rho > y)) return 0.0;
  return rho * rho * std::acos(y / rho) - y * std::sqrt(rho * rho - y * y);
}

/// Blend half-length at joint j for bend theta (docs/notes/sweep.md section 1.6): the arc radius h
/// / tan(theta/2) must stay above the skin radius r for the cross sections not to cross inside the
/// bend, so h grows as r tan(theta / 2) (with a 10 % margin) from its base value up to its cap.
double BlendHalfLength(const Chain& c, std::size_t j, double theta, bool grow) {
  double h = c.h_base[j];
  if (grow && theta > kMinBend) {
    h = theta < kPi - 1e-9 ? std::max(h, 1.1 * c.radius[j] * std::tan(0.5 * theta)) : c.h_max[j];
  }
  return std::min(h, c.h_max[j]);
}

/// Arcs, transports and bisectors of a chain from its joint positions (bone stretch scales
/// the blend zone with the bones).
void BuildGeom(const Chain& c, bool grow, ChainGeom* g) {
  const std::size_t n = c.bones();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = g->p[i + 1] - g->p[i];
    const double l = glm::length(d);
    g->t[i] = l > 0.0 ? d / l : (i > 0 ? g->t[i - 1] : c.t0[i]);
  }
  g->u[0] = glm::dquat(1.0, 0.0, 0.0, 0.0);
  for (std::size_t j = 1; j < n; ++j) {
    const Vec3 t1 = g->t[j - 1], t2 = g->t[j];
    const double len_in = glm::length(g->p[j] - g->p[j - 1]);
    const double len_out = glm::length(g->p[j + 1] - g->p[j]);
    Vec3 cr = glm::cross(t1, t2);
    double sin_t = glm::length(cr);
    const double theta = std::atan2(sin_t, glm::dot(t1, t2));
    if (sin_t <= 1e-12 && glm::dot(t1, t2) < 0.0) {
      // Folded back by (nearly) 180 degrees: the plane of the bend is undefined. Keep the
      // previous pose's axis (g holds it), else the rest one, else any normal of t1.
      Vec3 axis = g->axis[j];
      if (!(glm::dot(axis, axis) > 0.5)) axis = c.rest.axis[j];
      if (!(glm::dot(axis, axis) > 0.5)) {
        axis = glm::cross(t1, std::fabs(t1.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0));
      }
      axis -= glm::dot(axis, t1) * t1;
      cr = glm::normalize(axis) * std::sin(theta);
      sin_t = std::max(std::sin(theta), 1e-300);
    }
    g->h[j] = BlendHalfLength(c, j, theta, grow);
    // The zone scales with the bones' stretch, and never reaches past half a posed bone.
    const double hp = std::min(g->h[j] * 0.5 * (len_in / c.len[j - 1] + len_out / c.len[j]),
                               0.49 * std::min(len_in, len_out));
    g->a[j] = g->p[j] - hp * t1;
    g->b[j] = g->p[j] + hp * t2;
    if (theta > kMinBend && sin_t > 0.0 && hp > 0.0) {
      g->theta[j] = theta;
      g->axis[j] = glm::normalize(cr);
      const double radius = hp / std::tan(0.5 * theta);
      const Vec3 inward = glm::cross(g->axis[j], t1);  // the arc turns toward axis x t1
      g->centre[j] = g->a[j] + radius * inward;
      g->u[j] = glm::angleAxis(theta, g->axis[j]) * g->u[j - 1];
      // The bisector of t1 and t2; folded back completely it is the inward normal.
      const Vec3 bis = t1 + t2;
      const double bl = glm::length(bis);
      g->bisector[j] = bl > 1e-9 ? bis / bl : inward;
    } else {
      g->theta[j] = 0.0;
      g->axis[j] = Vec3(0.0);
      g->centre[j] = g->p[j];
      g->bisector[j] = t1;
      // A straight joint: transport across it by the minimal rotation (usually identity).
      g->u[j] = (sin_t > 1e-15 ? glm::angleAxis(theta, cr / sin_t) : glm::dquat(1.0, 0, 0, 0)) *
                g->u[j - 1];
    }
  }
  if (n >= 1) g->u[n] = g->u[n - 1];
}

/// The bone of a chain holding rest arc length s (the last one beyond the end).
std::size_t BoneAt(const Chain& c, double s) {
  std::size_t i = 0;
  while (i + 1 < c.bones() && s >= c.s[i + 1]) ++i;
  return i;
}

/// Position, tangent and transport rotation of a chain's trajectory at rest arc length s (in
/// [0, length]) on bone i = BoneAt(c, s) (a binding keeps it: no search per frame).
void EvalTrajectoryOnBone(const Chain& c, const ChainGeom& g, double s, std::size_t i, Vec3* pos,
                          Vec3* tangent, glm::dquat* transport) {
  const std::size_t n = c.bones();
  // In the second half of joint i's arc?
  std::size_t j = 0;
  if (i >= 1 && s < c.s[i] + g.h[i]) {
    j = i;
  } else if (i + 1 < n && s > c.s[i + 1] - g.h[i + 1]) {
    j = i + 1;
  }
  if (j != 0 && g.h[j] > 0.0) {
    const double f = (s - (c.s[j] - g.h[j])) / (2.0 * g.h[j]);
    if (g.theta[j] > 0.0) {
      const glm::dquat r = glm::angleAxis(f * g.theta[j], g.axis[j]);
      *pos = g.centre[j] + r * (g.a[j] - g.centre[j]);
      *tangent = r * g.t[j - 1];
      *transport = r * g.u[j - 1];
    } else {
      *pos = g.a[j] + f * (g.b[j] - g.a[j]);
      *tangent = g.t[j - 1];
      *transport = f < 0.5 ? g.u[j - 1] : g.u[j];
    }
    return;
  }
  // Straight piece of bone i, from the end of joint i's arc to the start of joint i+1's.
  const double s_from = c.s[i] + (i >= 1 ? g.h[i] : 0.0);
  const double s_to = c.s[i + 1] - (i + 1 < n ? g.h[i + 1] : 0.0);
  const Vec3 from = i >= 1 ? g.b[i] : g.p[0];
  const Vec3 to = i + 1 < n ? g.a[i + 1] : g.p[n];
  const double f = s_to > s_from ? (s - s_from) / (s_to - s_from) : 0.0;
  *pos = from + f * (to - from);
  *tangent = g.t[i];
  *transport = g.u[i];
}

/// The same at any s, clamped to the chain.
void EvalTrajectory(const Chain& c, const ChainGeom& g, double s, Vec3* pos, Vec3* tangent,
                    glm::dquat* transport) {
  s = std::clamp(s, 0.0, c.length());
  EvalTrajectoryOnBone(c, g, s, BoneAt(c, s), pos, tangent, transport);
}

/// Height k of joint j's volume bump in the chain's pose (docs/notes/sweep.md 1.5,
/// docs/deformation.md "Volume"), before clamping to [0, 1]. Pappus over the bump's support,
/// bin by bin: the zone's volume / pi is sum_i A_i int_i c + G_i int_i (2 k b + k^2 b^2) c, where
/// c(u) = c(theta) on the arc [-h, h] and 1 elsewhere, A_i the bin's section and G_i its
/// bumped section; k solves it equal to the rest zone's sum_i A_i int_i c_rest (quadratic,
/// closed form; a uniform tube gives the closed form of a centred tube). Past the rest bend the
/// fold clamp then moves the skin of each side that crossed the bisector plane onto it: on the
/// straight parts it removes a disc segment beyond y = a cot(theta / 2) toward the inside of
/// the bend (a the distance from the joint), on the arc it removes the sections' part beyond
/// the arc's centre (y > R = h cot(theta / 2)), which Pappus counted negatively. Both depend on
/// k: a few fixed-point steps solve with them.
double BumpHeight(const Chain& c, std::size_t j, bool clamp_folds) {
  const double w = c.w[j];
  const double hp = std::min(c.pose.h[j], w);
  const double cp = ArcCompression(c.pose.theta[j]);
  const double du = 2.0 * w / kBumpBins;
  const double* area = &c.section[j * kBumpBins];
  const double* gain = &c.bumped[j * kBumpBins];
  const double* bin_b1 = &c.bin_b1[j * kBumpBins];
  const double* bin_b2 = &c.bin_b2[j * kBumpBins];
  double qa = 0.0, qb = 0.0, loss = 0.0;
  for (int i = 0; i < kBumpBins; ++i) {
    const double u0 = -w + i * du, u1 = u0 + du;
    // The part of the bin on the posed arc: whole, none, or (at most two bins) a part.
    const double p0 = std::clamp(u0, -hp, hp), p1 = std::clamp(u1, -hp, hp);
    double in1 = 0.0, in2 = 0.0;
    if (p0 == u0 && p1 == u1) {
      in1 = bin_b1[i], in2 = bin_b2[i];
    } else if (p1 > p0) {
      in1 = BumpIntegralTo(p1, w) - BumpIntegralTo(p0, w);
      in2 = BumpSquaredIntegralTo(p1, w) - BumpSquaredIntegralTo(p0, w);
    }
    qa += gain[i] * (bin_b2[i] - (1.0 - cp) * in2);
    qb += gain[i] * (bin_b1[i] - (1.0 - cp) * in1);
    loss += area[i] * (1.0 - cp) * (p1 - p0);
  }
  const double qc = c.rest_loss[j] - loss;
  auto root = [&](double extra) {
    const double disc = qb * qb - qa * (qc + extra);
    return qa > 0.0 && disc >= 0.0 ? (-qb + std::sqrt(disc)) / qa : 0.0;
  };
  double k = root(0.0);
  const double theta = c.pose.theta[j];
  if (!clamp_folds || !(theta > c.rest.theta[j] + 1e-9) || !(hp > 0.0)) return k;
  const double cot = 1.0 / std::tan(0.5 * theta), arc_radius = hp * cot;
  // No section reaches the arc's centre line, even with the largest bump: nothing is clamped.
  if (4.0 * c.widest[j] <= arc_radius * arc_radius) return k;
  const double* beta = &c.fold_beta[j * kBumpBins * kFoldSamples];
  const double* radius = &c.bin_radius[j * kBumpBins];
  const double* bin_share = &c.bin_share[j * kBumpBins];
  auto fold = [&](double kk) {  // volume / pi the clamp adds (negative: removes)
    double sum = 0.0;
    for (int i = 0; i < kBumpBins; ++i) {
      if (!(area[i] > 0.0)) continue;
      for (int q = 0; q < kFoldSamples; ++q) {
        const double u = -w + (i + (q + 0.5) / kFoldSamples) * du, au = std::fabs(u);
        const double rho = (1.0 + kk * beta[i * kFoldSamples + q]) * radius[i];
        double t = 0.0;
        if (au < hp) {
          if (rho > arc_radius) {
            const double e = rho * rho - arc_radius * arc_radius;
            t = (theta / (2.0 * hp)) *
                ((2.0 / 3.0) * e * std::sqrt(e) - arc_radius * DiscSegment(rho, arc_radius));
          }
        } else {
          t = -DiscSegment(rho, au * cot);
        }
        sum += bin_share[i] * t;
      }
    }
    return sum * du / (kFoldSamples * kPi);
  };
  for (int it = 0; it < 4; ++it) k = root(fold(std::clamp(k, 0.0, 1.0)));
  return k;
}

class SweepDeformer final : public Deformer {
 public:
  Status Build(const SkinRig& rig, const Vec3* rest, const Vec3* normals,
               const VertexWeights* influences, std::size_t count, const SweepOptions& o);

  DeformerKind kind() const override { return DeformerKind::kSweep; }
  std::size_t num_vertices() const override { return count_; }
  std::size_t num_joints() const override { return joints_; }

  Status SetPose(const glm::dmat4* m) override;
  void Deform(std::size_t begin, std::size_t end, Vec3* positions, Vec3* normals) const override;
  void ResetHistory() override {
    for (Chain& c : chains_) c.prev_tau.clear();
    history_ = false;
  }

 private:
  void MakeChains(const std::vector<SweepChain>& chains);
  /// Chain::section, bumped and fold_beta from the bindings.
  void MeasureBumpSections();
  /// The sweep's image of a bound vertex (`x`, with the volume bump and the fold clamp), the
  /// rotation of its frame relative to the rest frame at its point (`rotation`) and its image
  /// without the bump and the clamp (`rigid`: the rest offset carried rigidly by that frame).
  void EvalBinding(const Binding& b, Vec3* x, glm::dquat* rotation, Vec3* rigid,
                   Vec3* normal) const;
  /// A vertex bound to several chains, or with loose joints: the chains' rigid frames at its
  /// points and the loose joints' rigid parts blended as dual quaternions (two-phase: scales
  /// and stretches blended linearly first), plus the weighted corrections of the chains.
  void Blend(std::size_t v, Vec3* position, Vec3* normal) const;

  SweepOptions options_;
  std::size_t joints_ = 0, count_ = 0;
  bool has_normals_ = false;
  bool history_ = false;
  std::vector<Chain> chains_;
  std::vector<int> chain_of_;              // per joint: chain, or -1 (no skin, no bone)
  std::vector<int> bone_of_;               // per joint: bone index within its chain
  std::vector<glm::dquat> pose_rotation_;  // per joint, relative to bind (per frame)
  std::vector<double> joint_scale_;        // per joint: mean scale (per frame)
  std::vector<double> joint_skew_;         // per joint: relative non-uniformity (per frame)
  std::vector<std::uint32_t> first_;       // per vertex: first binding, count_ + 1 entries
  std::vector<Binding> bindings_;
  std::vector<BumpTerm> bumps_;
  std::vector<LooseWeights> loose_;   // per vertex
  std::vector<std::uint8_t> direct_;  // per vertex: 1 = one chain, whole weight (no blend)
  // Rest data and the per-frame joint palette (DQS of stretched chains, loose joints).
  std::vector<Vec3> rest_, normals_;
  std::vector<VertexWeights> weights_;
  std::vector<deform::DualQuat> dq_;
  std::vector<glm::dmat3> stretch_;
  bool has_stretch_ = false;
};

void SweepDeformer::MakeChains(const std::vector<SweepChain>& chains) {
  chain_of_.assign(joints_, -1);
  bone_of_.assign(joints_, -1);
  for (const SweepChain& sc : chains) {
    Chain c;
    c.joints = sc.joints;
    // A virtual end moves with the last joint: it repeats that joint.
    if (sc.virtual_end) c.joints.push_back(sc.joints.back());
    const int id = static_cast<int>(chains_.size());
    const std::size_t nj = c.joints.size(), bones = nj - 1;
    for (std::size_t i = 0; i < bones; ++i) {
      chain_of_[static_cast<std::size_t>(c.joints[i])] = id;
      bone_of_[static_cast<std::size_t>(c.joints[i])] = static_cast<int>(i);
    }
    c.s.assign(nj, 0.0);
    c.len.assign(bones, 0.0);
    c.t0.assign(bones, Vec3(0.0));
    for (std::size_t i = 0; i < bones; ++i) {
      const Vec3 d = sc.points[i + 1] - sc.points[i];
      c.len[i] = glm::length(d);
      c.t0[i] = d / c.len[i];
      c.s[i + 1] = c.s[i] + c.len[i];
    }
    c.radius.assign(nj, 0.0);
    c.h_base.assign(nj, 0.0);
    c.h_max.assign(nj, 0.0);
    c.w.assign(nj, 0.0);
    c.reach.assign(nj, 0.0);
    c.tau.assign(nj, 0.0);
    c.k.assign(nj, 0.0);
    c.rest.Resize(nj);
    c.pose.Resize(nj);
    for (std::size_t i = 0; i < nj; ++i) c.rest.p[i] = sc.points[i];
    chains_.push_back(std::move(c));
  }
}

void SweepDeformer::MeasureBumpSections() {
  // Per chain and bin: bound vertices, sum of squared radial offsets, sum of chain shares.
  std::vector<std::vector<double>> count(chains_.size()), r2(chains_.size()), share(chains_.size());
  for (std::size_t ci = 0; ci < chains_.size(); ++ci) {
    const std::size_t bins = chains_[ci].joints.size() * kBumpBins;
    count[ci].assign(bins, 0.0);
    r2[ci].assign(bins, 0.0);
    share[ci].assign(bins, 0.0);
  }
  for (const Binding& b : bindings_) {
    const Chain& c = chains_[b.chain];
    for (std::size_t j = 1; j + 1 < c.joints.size(); ++j) {
      const double w = c.w[j], u = b.s - c.s[j];
      if (!(w > 0.0) || std::fabs(u) >= w) continue;
      const int bin = std::min(kBumpBins - 1, static_cast<int>((u + w) / (2.0 * w) * kBumpBins));
      const std::size_t at = j * kBumpBins + static_cast<std::size_t>(bin);
      count[b.chain][at] += 1.0;
      r2[b.chain][at] += glm::dot(b.radial, b.radial);
      share[b.chain][at] += b.weight;
    }
  }
  for (std::size_t ci = 0; ci < chains_.size(); ++ci) {
    Chain& c = chains_[ci];
    const std::size_t nj = c.joints.size();
    c.section.assign(nj * kBumpBins, 1.0);
    c.bumped.assign(nj * kBumpBins, 1.0);
    c.fold_beta.assign(nj * kBumpBins * kFoldSamples, 0.0);
    c.bin_b1.assign(nj * kBumpBins, 0.0);
    c.bin_b2.assign(nj * kBumpBins, 0.0);
    c.rest_loss.assign(nj, 0.0);
    c.bin_radius.assign(nj * kBumpBins, 1.0);
    c.bin_share.assign(nj * kBumpBins, 1.0);
    c.widest.assign(nj, 1.0);
    for (std::size_t j = 1; j + 1 < nj; ++j) {
      const double w = c.w[j];
      if (!(w > 0.0)) continue;
      const double* n = &count[ci][j * kBumpBins];
      // An empty bin takes its nearest bound neighbour's values (the lower one on a tie); a
      // support with no bound vertex keeps a uniform tube (nothing there moves anyway).
      for (int i = 0; i < kBumpBins; ++i) {
        int from = -1;
        for (int d = 0; d < kBumpBins && from < 0; ++d) {
          if (i - d >= 0 && n[i - d] > 0.0) {
            from = i - d;
          } else if (i + d < kBumpBins && n[i + d] > 0.0) {
            from = i + d;
          }
        }
        if (from < 0) break;
        const std::size_t src = j * kBumpBins + static_cast<std::size_t>(from);
        const double area = r2[ci][src] / n[from];
        c.section[j * kBumpBins + static_cast<std::size_t>(i)] = area;
        c.bumped[j * kBumpBins + static_cast<std::size_t>(i)] = area * share[ci][src] / n[from];
      }
      const double du = 2.0 * w / kBumpBins;
      const double hr = std::min(c.rest.h[j], w), cr = ArcCompression(c.rest.theta[j]);
      c.widest[j] = 0.0;
      for (int i = 0; i < kBumpBins; ++i) {
        const double u0 = -w + i * du, u1 = u0 + du;
        const std::size_t at = j * kBumpBins + static_cast<std::size_t>(i);
        c.widest[j] = std::max(c.widest[j], c.section[at]);
        c.bin_radius[at] = std::sqrt(c.section[at]);
        c.bin_share[at] = c.section[at] > 0.0 ? c.bumped[at] / c.section[at] : 0.0;
        c.bin_b1[at] = BumpIntegralTo(u1, w) - BumpIntegralTo(u0, w);
        c.bin_b2[at] = BumpSquaredIntegralTo(u1, w) - BumpSquaredIntegralTo(u0, w);
        c.rest_loss[j] +=
            c.section[at] * (1.0 - cr) * (std::clamp(u1, -hr, hr) - std::clamp(u0, -hr, hr));
        for (int q = 0; q < kFoldSamples; ++q) {
          const double u = -w + (i + (q + 0.5) / kFoldSamples) * du;
          c.fold_beta[(j * kBumpBins + static_cast<std::size_t>(i)) * kFoldSamples +
                      static_cast<std::size_t>(q)] = Bump(u, w);
        }
      }
    }
  }
}

Status SweepDeformer::Build(const SkinRig& rig, const Vec3* rest, const Vec3* normals,
                            const VertexWeights* influences, std::size_t count,
                            const SweepOptions& o) {
  options_ = o;
  joints_ = rig.parents.size();
  count_ = count;
  has_normals_ = normals != nullptr;
  if (o.stations_per_bone < 1 || !(o.blend_radius_factor >= 0.0) ||
      !(o.max_blend_fraction >= 0.0 && o.max_blend_fraction < 0.5) ||
      !(o.volume_width_factor >= 1.0)) {
    return Status::InvalidInput("sweep: options out of range");
  }
  // The binding's ramps are continuous only in these ranges (deformer.h).
  if (!(o.single_chain_threshold > 0.5 && o.single_chain_threshold <= 1.0) ||
      !(o.single_chain_ramp >= 0.0 && o.single_chain_ramp <= o.single_chain_threshold - 0.5) ||
      !(o.blend_threshold >= 0.0 &&
        2.0 * o.blend_threshold <= o.single_chain_threshold - o.single_chain_ramp)) {
    return Status::InvalidInput(
        "sweep: binding options out of range: single_chain_threshold must be in (0.5, 1], "
        "single_chain_ramp in [0, single_chain_threshold - 0.5] and blend_threshold in [0, "
        "(single_chain_threshold - single_chain_ramp) / 2]");
  }
  std::vector<SweepChain> chains;
  const Status s = BuildSweepChains(rig, rest, influences, count, o, &chains);
  if (!s.ok()) return s;
  rest_.assign(rest, rest + count);
  if (normals != nullptr) normals_.assign(normals, normals + count);
  weights_.assign(influences, influences + count);
  dq_.resize(joints_);
  stretch_.assign(joints_, glm::dmat3(1.0));
  pose_rotation_.assign(joints_, glm::dquat(1.0, 0.0, 0.0, 0.0));
  joint_scale_.assign(joints_, 1.0);
  joint_skew_.assign(joints_, 0.0);
  MakeChains(chains);

  // Blend half-lengths from the vertices around each joint: the 90th percentile of their
  // distance to the bone polyline (the skin, not the inside), and, with follow_weights, at
  // least the 90th percentile of the distance along the chain of the vertices the joint shares
  // with the joint before it (each holding at least a tenth of their two weights: the painted
  // transition), capped per bone length.
  std::vector<std::vector<std::vector<double>>> near(chains_.size()), mixed(chains_.size()),
      past(chains_.size());
  for (std::size_t ci = 0; ci < chains_.size(); ++ci) {
    near[ci].resize(chains_[ci].joints.size());
    mixed[ci].resize(chains_[ci].joints.size());
    past[ci].resize(chains_[ci].joints.size());
  }
  auto closest = [&](const Chain& c, const Vec3& x, double* dist, double* arc) {
    *dist = std::numeric_limits<double>::max();
    *arc = 0.0;
    for (std::size_t i = 0; i < c.bones(); ++i) {
      const Vec3 p0 = c.rest.p[i];
      const double f = std::clamp(glm::dot(x - p0, c.t0[i]) / c.len[i], 0.0, 1.0);
      const double d = glm::length(x - (p0 + f * c.len[i] * c.t0[i]));
      if (d < *dist) *dist = d, *arc = c.s[i] + f * c.len[i];
    }
  };
  for (std::size_t v = 0; v < count; ++v) {
    const glm::dvec4 w = deform::NormalizedWeights(influences[v]);
    int seen[4] = {-1, -1, -1, -1};
    for (int k = 0; k < 4; ++k) {
      if (!(w[k] > 0.0)) continue;
      const std::size_t j = influences[v].joints[k];
      const int ci = chain_of_[j];
      if (ci < 0) continue;
      const Chain& c = chains_[static_cast<std::size_t>(ci)];
      double best = 0.0, best_s = 0.0;
      closest(c, rest[v], &best, &best_s);
      for (std::size_t jj = 1; jj + 1 < c.joints.size(); ++jj) {
        const double reach = 0.5 * std::min(c.len[jj - 1], c.len[jj]);
        if (std::fabs(best_s - c.s[jj]) <= reach) near[ci][jj].push_back(best);
      }
      // The painted transitions, once per chain.
      if (std::find(seen, seen + 4, ci) != seen + 4) continue;
      seen[k] = ci;
      for (std::size_t jj = 1; jj < c.joints.size(); ++jj) {
        if (c.joints[jj] == c.joints[jj - 1]) continue;  // a virtual end
        double a = 0.0, b = 0.0;
        for (int q = 0; q < 4; ++q) {
          if (influences[v].joints[q] == static_cast<std::size_t>(c.joints[jj - 1])) a += w[q];
          if (influences[v].joints[q] == static_cast<std::size_t>(c.joints[jj])) b += w[q];
        }
        if (a > 0.0 && b > 0.0 && std::min(a, b) >= 0.1 * (a + b)) {
          mixed[ci][jj].push_back(std::fabs(best_s - c.s[jj]));
          if (best_s > c.s[jj]) past[ci][jj].push_back(best_s - c.s[jj]);
        }
      }
    }
  }
  auto percentile90 = [](std::vector<double>* r) {
    std::sort(r->begin(), r->end());
    return (*r)[std::min(r->size() - 1,
                         static_cast<std::size_t>(0.9 * static_cast<double>(r->size())))];
  };
  for (std::size_t ci = 0; ci < chains_.size(); ++ci) {
    Chain& c = chains_[ci];
    for (std::size_t j = 1; j + 1 < c.joints.size(); ++j) {
      const double shorter = std::min(c.len[j - 1], c.len[j]);
      const double radius = near[ci][j].empty() ? 0.1 * shorter : percentile90(&near[ci][j]);
      c.radius[j] = radius;
      c.h_max[j] = o.max_blend_fraction * shorter;
      double h = o.blend_radius_factor * radius;
      if (o.follow_weights && !mixed[ci][j].empty()) h = std::max(h, percentile90(&mixed[ci][j]));
      // The joint's twist ramps in from the joint before; with follow_weights it finishes past
      // the joint where the painted transition reaches (within the bone after it).
      if (o.follow_weights && !past[ci][j].empty()) {
        c.reach[j] = std::min(percentile90(&past[ci][j]), c.len[j]);
      }
      c.h_base[j] = std::min(h, c.h_max[j]);
      if (o.preserve_volume && c.h_base[j] > 0.0) {
        // Wide enough for the largest blend zone, not past the chain's ends.
        c.w[j] = std::max(o.volume_width_factor * c.h_base[j], c.h_max[j]);
        c.w[j] = std::min(c.w[j], std::min(c.s[j], c.length() - c.s[j]));
        c.w[j] = std::max(c.w[j], c.h_max[j]);
      }
    }
    BuildGeom(c, o.grow_blend_with_bend, &c.rest);
  }

  // Bind every vertex.
  first_.assign(count + 1, 0);
  loose_.assign(count, LooseWeights{});
  direct_.assign(count, 0);
  for (std::size_t v = 0; v < count; ++v) {
    first_[v] = static_cast<std::uint32_t>(bindings_.size());
    const VertexWeights& iw = influences[v];
    const glm::dvec4 w = deform::NormalizedWeights(iw);
    // Share of each chain, and the weight of joints on no chain.
    int ids[4] = {-1, -1, -1, -1};
    double share[4] = {0, 0, 0, 0};
    int used = 0;
    bool outside = false;
    for (int k = 0; k < 4; ++k) {
      if (!(w[k] > 0.0)) continue;
      const int ci = chain_of_[iw.joints[k]];
      if (ci < 0) {
        outside = true;
        continue;
      }
      int slot = 0;
      while (slot < used && ids[slot] != ci) ++slot;
      if (slot == used) ids[used++] = ci;
      share[slot] += w[k];
    }
    int best = -1;
    for (int q = 0; q < used; ++q)
      if (best < 0 || share[q] > share[best]) best = q;
    // The binding is continuous in the weights (docs/deformation.md, "Binding"): painted
    // weights vary from vertex to vertex, and a snap between two treatments at a threshold
    // turns that noise into steps of the posed surface (CesiumMan's head on its neck chain).
    // - Everything but the strongest chain is scaled by `others`: 1 up to a best share of
    //   single_chain_threshold - single_chain_ramp, fading to 0 at single_chain_threshold,
    //   from where the vertex is the sweep's point alone, as before the ramp.
    // - A chain's share s is bound to the chain by rho(s): 0 up to blend_threshold, 1 from
    //   twice it on; the rest of its weight follows its joints' own rigid transforms (loose).
    double others = 1.0;
    if (best >= 0 && !(used == 1 && !outside)) {
      const double st = o.single_chain_threshold, ramp = o.single_chain_ramp;
      others = ramp > 0.0 ? 1.0 - SmoothStep((share[best] - (st - ramp)) / ramp)
                          : (share[best] >= st ? 0.0 : 1.0);
    }
    const bool single = best >= 0 && ((used == 1 && !outside) || !(others > 0.0));
    double rho[4] = {0, 0, 0, 0};
    for (int q = 0; q < used; ++q) {
      const double bt = o.blend_threshold;
      if (single) {
        rho[q] = q == best ? 1.0 : 0.0;
      } else {
        rho[q] = bt > 0.0 ? SmoothStep((share[q] - bt) / bt) : (share[q] > 0.0 ? 1.0 : 0.0);
      }
    }
    LooseWeights& loose = loose_[v];
    int loose_used = 0;
    for (int k = 0; k < 4 && !single; ++k) {
      if (!(w[k] > 0.0)) continue;
      const int ci = chain_of_[iw.joints[k]];
      int slot = 0;
      while (slot < used && ids[slot] != ci) ++slot;
      const double scaled = (ci >= 0 && slot == best) ? w[k] : others * w[k];
      const double part = ci >= 0 ? (1.0 - rho[slot]) * scaled : scaled;
      if (!(part > 0.0)) continue;
      loose.joints[loose_used] = iw.joints[k];
      loose.weights[loose_used] = part;
      ++loose_used;
    }
    double total = 0.0;
    for (int k = 0; k < loose_used; ++k) total += loose.weights[k];
    for (int q = 0; q < used; ++q) {
      if (!(rho[q] > 0.0)) continue;
      const double weight = single ? 1.0 : rho[q] * share[q] * (q == best ? 1.0 : others);
      if (!(weight > 0.0)) continue;
      total += weight;
      const Chain& c = chains_[static_cast<std::size_t>(ids[q])];
      // Allowed arc-length ranges: the bones this chain's joints weight the vertex to.
      double best_d = std::numeric_limits<double>::max(), best_s = 0.0;
      for (int k = 0; k < 4; ++k) {
        if (!(w[k] > 0.0) || chain_of_[iw.joints[k]] != ids[q]) continue;
        const int bone = bone_of_[iw.joints[k]];
        const double lo = c.s[static_cast<std::size_t>(bone)];
        const double hi = c.s[static_cast<std::size_t>(bone) + 1];
        const int samples = 4 * o.stations_per_bone;
        auto dist = [&](double sv) {
          Vec3 p, t;
          glm::dquat u;
          EvalTrajectory(c, c.rest, sv, &p, &t, &u);
          return glm::length(rest[v] - p);
        };
        // Coarse scan, then golden-section refinement around the best sample.
        double bs = lo, bd = dist(lo);
        for (int q2 = 1; q2 <= samples; ++q2) {
          const double sv = lo + (hi - lo) * q2 / samples;
          const double d = dist(sv);
          if (d < bd) bd = d, bs = sv;
        }
        double a = std::max(lo, bs - (hi - lo) / samples),
               b = std::min(hi, bs + (hi - lo) / samples);
        for (int it = 0; it < 60 && b - a > 1e-12 * (1.0 + c.length()); ++it) {
          const double m1 = a + 0.381966011250105 * (b - a), m2 = b - 0.381966011250105 * (b - a);
          if (dist(m1) < dist(m2)) {
            b = m2;
          } else {
            a = m1;
          }
        }
        const double sv = 0.5 * (a + b);
        const double d = dist(sv);
        if (d < bd) bd = d, bs = sv;
        if (bd < best_d) best_d = bd, best_s = bs;
      }
      Binding bind;
      bind.chain = static_cast<std::uint32_t>(ids[q]);
      bind.weight = weight;
      bind.s = best_s;
      // best_s lies in [0, length] (a bone's range): EvalTrajectoryOnBone takes it as is.
      const std::size_t bone = BoneAt(c, best_s);
      bind.bone = static_cast<std::uint32_t>(bone);
      Vec3 p, t;
      glm::dquat u;
      EvalTrajectory(c, c.rest, best_s, &p, &t, &u);
      const glm::dquat back = glm::conjugate(u);
      const Vec3 off = back * (rest[v] - p);
      const Vec3 t_start = c.t0[0];
      bind.axial = glm::dot(off, t_start) * t_start;
      bind.radial = off - bind.axial;
      bind.rest_back = back;
      if (normals != nullptr) bind.normal = back * normals[v];
      // Twist at s (docs/notes/sweep.md 1.2): each joint's increment over the joint before ramps in
      // linearly from that joint to the joint itself, or on to its painted transition's reach
      // past it; the fully ramped joints are a prefix, at most two are partly ramped at s.
      // And the volume bumps reaching s. Both are constant per binding.
      int partial = 0;
      for (std::size_t j = 1; j < c.joints.size(); ++j) {
        const double f = std::clamp((best_s - c.s[j - 1]) / (c.len[j - 1] + c.reach[j]), 0.0, 1.0);
        if (f >= 1.0) {
          bind.twist_full = static_cast<std::uint16_t>(j);
        } else if (f > 0.0 && partial < 2) {
          bind.twist_joint[partial] = static_cast<std::uint16_t>(j);
          bind.twist_share[partial++] = f;
        }
      }
      bind.bump_first = static_cast<std::uint32_t>(bumps_.size());
      for (std::size_t j = 1; j + 1 < c.joints.size(); ++j) {
        const double beta = Bump(best_s - c.s[j], c.w[j]);
        if (beta > 0.0) bumps_.push_back(BumpTerm{static_cast<std::uint16_t>(j), beta});
      }
      bind.bump_count = static_cast<std::uint16_t>(bumps_.size() - bind.bump_first);
      bindings_.push_back(bind);
    }
    // Weights scaled to sum 1 (a single chain drops the other chains' small shares).
    for (int k = 0; k < loose_used; ++k) loose.weights[k] /= total;
    for (std::uint32_t q = first_[v]; q < bindings_.size(); ++q) bindings_[q].weight /= total;
    direct_[v] = bindings_.size() - first_[v] == 1 && loose_used == 0 ? 1 : 0;
  }
  first_[count] = static_cast<std::uint32_t>(bindings_.size());
  MeasureBumpSections();
  for (Chain& c : chains_) {
    c.pose = c.rest;
    c.prev_tau.reserve(c.joints.size());
  }
  return Status::Ok();
}

Status SweepDeformer::SetPose(const glm::dmat4* m) {
  for (std::size_t j = 0; j < joints_; ++j) {
    if (!deform::IsFinite(m[j])) {
      return Status::InvalidInput("sweep: skin matrix of joint " + std::to_string(j) +
                                  " is not finite");
    }
  }
  bool stretch = false;
  for (std::size_t j = 0; j < joints_; ++j) {
    stretch = deform::SplitSkinMatrix(m[j], &dq_[j], &stretch_[j]) || stretch;
  }
  has_stretch_ = stretch;
  for (std::size_t j = 0; j < joints_; ++j) {
    pose_rotation_[j] = dq_[j].real;
    // The sweep moves rigid frames, scaled uniformly at most (an armature's unit scale): the
    // joint's mean scale and how far its stretch is from uniform (relative).
    const glm::dmat3& st = stretch_[j];
    const double lambda = (st[0][0] + st[1][1] + st[2][2]) / 3.0;
    double off = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        off = std::max(off, std::fabs(st[a][b] - (a == b ? lambda : 0.0)));
    joint_scale_[j] = lambda;
    joint_skew_[j] = lambda > 0.0 ? off / lambda : std::numeric_limits<double>::infinity();
  }
  for (Chain& c : chains_) {
    const std::size_t nj = c.joints.size(), n = c.bones();
    for (std::size_t i = 0; i < nj; ++i) {
      const std::size_t j = static_cast<std::size_t>(c.joints[i]);
      c.pose.p[i] = Vec3(m[j] * glm::dvec4(c.rest.p[i], 1.0));
    }
    // A chain whose joints stretch non-uniformly, or unevenly, has no sweep: its vertices go to
    // DQS, blended in smoothly from a relative unevenness of 1e-4 (float noise in a clip's
    // matrices stays swept) to 1e-2 (a squash and stretch is DQS), so no frame jumps.
    const double l0 = joint_scale_[static_cast<std::size_t>(c.joints[0])];
    double uneven = l0 > 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    for (const Index j : c.joints) {
      const std::size_t ju = static_cast<std::size_t>(j);
      uneven = std::max({uneven, joint_skew_[ju], std::fabs(joint_scale_[ju] / l0 - 1.0)});
    }
    const double ramp = std::clamp((uneven - 1e-4) / (1e-2 - 1e-4), 0.0, 1.0);
    c.dqs_share = std::isfinite(uneven) ? ramp * ramp * (3.0 - 2.0 * ramp) : 1.0;
    c.scale = l0 > 0.0 ? l0 : 1.0;
    BuildGeom(c, options_.grow_blend_with_bend, &c.pose);
    c.q0 = pose_rotation_[static_cast<std::size_t>(c.joints[0])];
    // Twists: the residue of each joint's rotation against the transported frame.
    for (std::size_t i = 0; i < nj; ++i) {
      const std::size_t bone = std::min(i, n - 1);
      const glm::dquat transported = c.pose.u[bone] * c.q0 * glm::conjugate(c.rest.u[bone]);
      const glm::dquat d =
          glm::conjugate(transported) * pose_rotation_[static_cast<std::size_t>(c.joints[i])];
      double tau = i == 0 ? 0.0 : deform::TwistAngle(d, c.t0[bone]);
      const double ref =
          history_ && c.prev_tau.size() == nj ? c.prev_tau[i] : (i == 0 ? 0.0 : c.tau[i - 1]);
      tau += 2.0 * kPi * std::round((ref - tau) / (2.0 * kPi));
      c.tau[i] = tau;
    }
    c.prev_tau.assign(c.tau.begin(), c.tau.end());
    // Volume: bump heights keeping the zone's rest volume, where the arc compresses
    // [s_j - h, s_j + h] by c(theta) (Pappus), over the measured sections and with what the
    // fold clamp removes (BumpHeight).
    for (std::size_t j = 1; j + 1 < nj; ++j) {
      c.k[j] = c.w[j] > 0.0 ? BumpHeight(c, j, options_.clamp_folds) : 0.0;
      // Bounded: near a full fold the arc compresses the zone to nothing and k would balloon a
      // slender limb. Never below 0: a joint straighter than its rest bend (an A-pose elbow
      // straightened, a paw bent at rest) lengthens a centred tube's zone, but the real skin
      // around a rest-bent joint does not gain that volume (its bones run off the sections'
      // centroids; docs/deformation.md "Volume"), so shrinking its sections only loses volume.
      c.k[j] = std::clamp(c.k[j], 0.0, 1.0);
    }
  }
  history_ = true;
  return Status::Ok();
}

void SweepDeformer::EvalBinding(const Binding& b, Vec3* x_out, glm::dquat* rotation, Vec3* rigid,
                                Vec3* normal) const {
  const Chain& c = chains_[b.chain];
  const std::size_t n = c.bones();
  Vec3 pos, tangent;
  glm::dquat transport;
  EvalTrajectoryOnBone(c, c.pose, b.s, b.bone, &pos, &tangent, &transport);
  // Twist: the ramps precomputed at binding (with no reach past the joints, linear in s
  // between them as in docs/notes/sweep.md 1.2).
  double twist = c.tau[b.twist_full];
  for (int q = 0; q < 2; ++q) {
    const std::size_t j = b.twist_joint[q];
    if (j != 0) twist += b.twist_share[q] * (c.tau[j] - c.tau[j - 1]);
  }
  double sigma = 1.0;
  for (std::uint32_t q = b.bump_first; q < b.bump_first + b.bump_count; ++q) {
    sigma += c.k[bumps_[q].joint] * bumps_[q].beta;
  }
  const glm::dquat g = glm::angleAxis(twist, tangent) * transport * c.q0;
  Vec3 x = pos + c.scale * (g * (b.axial + sigma * b.radial));
  // Without a bump the offset is carried rigidly: the same bytes as the rigid image below.
  const bool unbumped = sigma == 1.0;
  if (rotation != nullptr && unbumped) *rigid = x;
  if (options_.clamp_folds) {
    // The bisector planes of the joints at both ends of the vertex's bone.
    for (std::size_t j : {static_cast<std::size_t>(b.bone), static_cast<std::size_t>(b.bone) + 1}) {
      if (j == 0 || j >= n || !(c.pose.theta[j] > c.rest.theta[j] + 1e-9)) continue;
      const double d = glm::dot(x - c.pose.p[j], c.pose.bisector[j]);
      const bool before = b.s < c.s[j];
      if ((before && d > 0.0) || (!before && d < 0.0)) x -= d * c.pose.bisector[j];
    }
  }
  *x_out = x;
  if (rotation != nullptr) {
    *rotation = g * b.rest_back;
    if (!unbumped) *rigid = pos + c.scale * (g * (b.axial + b.radial));
  }
  if (normal != nullptr) *normal = g * b.normal;
}

void SweepDeformer::Blend(std::size_t v, Vec3* position, Vec3* normal) const {
  // Up to 4 chains and 4 loose joints.
  glm::dquat real[8], dual[8];
  double weight[8];
  int terms = 0;
  // Two-phase: the chains' uniform scales and the loose joints' stretches, blended linearly.
  double scale = 0.0;
  glm::dmat3 stretch(0.0);
  bool stretched = false;
  Vec3 correction(0.0);
  const Vec3& x0 = rest_[v];
  for (std::uint32_t q = first_[v]; q < first_[v + 1]; ++q) {
    const Binding& b = bindings_[q];
    const double lambda = chains_[b.chain].scale;
    Vec3 x, rigid;
    glm::dquat r;
    EvalBinding(b, &x, &r, &rigid, nullptr);
    // The frame carries the rest offset rigidly: rigid = r (lambda x0) + t.
    const Vec3 t = rigid - lambda * (r * x0);
    real[terms] = r;
    dual[terms] = 0.5 * (glm::dquat(0.0, t.x, t.y, t.z) * r);
    weight[terms++] = b.weight;
    scale += b.weight * lambda;
    stretched = stretched || lambda != 1.0;
    correction += b.weight * (x - rigid);
  }
  const LooseWeights& lw = loose_[v];
  for (int k = 0; k < 4; ++k) {
    if (!(lw.weights[k] > 0.0)) continue;
    const std::size_t j = lw.joints[k];
    real[terms] = dq_[j].real;
    dual[terms] = dq_[j].dual;
    weight[terms++] = lw.weights[k];
    if (has_stretch_) {
      stretch += lw.weights[k] * stretch_[j];
      stretched = true;
    } else {
      scale += lw.weights[k];
    }
  }
  int pivot = 0;
  for (int k = 1; k < terms; ++k)
    if (weight[k] > weight[pivot]) pivot = k;
  glm::dquat br(0.0, 0.0, 0.0, 0.0), bd(0.0, 0.0, 0.0, 0.0);
  double total = 0.0;
  for (int k = 0; k < terms; ++k) {
    const double sign = glm::dot(real[k], real[pivot]) < 0.0 ? -1.0 : 1.0;
    br = br + (sign * weight[k]) * real[k];
    bd = bd + (sign * weight[k]) * dual[k];
    total += weight[k];
  }
  const double len = glm::length(br);
  deform::DualQuat blended;
  blended.real = br / len;
  blended.dual = bd / len;
  Vec3 x = x0;
  if (stretched) {
    for (int c = 0; c < 3; ++c) stretch[c][c] += scale;
    stretch /= total;
    x = stretch * x;
  }
  *position = blended.real * x + deform::Translation(blended) + correction;
  if (normal != nullptr) {
    Vec3 nn = normals_[v];
    if (stretched)
      nn = deform::Cofactor(stretch) * nn * (glm::determinant(stretch) < 0.0 ? -1.0 : 1.0);
    nn = blended.real * nn;
    const double l = glm::length(nn);
    *normal = l > 0.0 ? nn / l : normals_[v];
  }
}

void SweepDeformer::Deform(std::size_t begin, std::size_t end, Vec3* positions,
                           Vec3* normals) const {
  end = std::min(end, count_);
  const bool want_normals = normals != nullptr && has_normals_;
  for (std::size_t v = begin; v < end; ++v) {
    // A chain stretched non-uniformly (a joint scaled to hide a part, say) has no sweep: the
    // vertex is deformed by DQS, whose two-phase blend follows any scale (blended in smoothly).
    double dqs = 0.0;
    for (std::uint32_t q = first_[v]; q < first_[v + 1]; ++q) {
      dqs = std::max(dqs, chains_[bindings_[q].chain].dqs_share);
    }
    Vec3 xd(0.0), nd(0.0);
    if (dqs > 0.0) {
      deform::DqsPoint(dq_.data(), stretch_.data(), has_stretch_, weights_[v], rest_[v],
                       want_normals ? normals_[v] : Vec3(0.0), &xd, want_normals ? &nd : nullptr);
      if (dqs >= 1.0) {
        positions[v] = xd;
        if (want_normals) normals[v] = nd;
        continue;
      }
    }
    if (direct_[v]) {
      EvalBinding(bindings_[first_[v]], &positions[v], nullptr, nullptr,
                  want_normals ? &normals[v] : nullptr);
    } else {
      Blend(v, &positions[v], want_normals ? &normals[v] : nullptr);
    }
    if (dqs > 0.0) {
      positions[v] += dqs * (xd - positions[v]);
      if (want_normals) {
        const Vec3 nn = normals[v] + dqs * (nd - normals[v]);
        const double l = glm::length(nn);
        normals[v] = l > 0.0 ? nn / l : nd;
      }
    }
  }
}

}  // namespace

Status MakeSweepDeformer(const SkinRig& rig, const Vec3* rest_positions, const Vec3* rest_normals,
                         const VertexWeights* influences, std::size_t count,
                         const SweepOptions& options, std::unique_ptr<Deformer>* out) {
  auto d = std::make_unique<SweepDeformer>();
  const Status s = d->Build(rig, rest_positions, rest_normals, influences, count, options);
  if (!s.ok()) return s;
  *out = std::move(d);
  return Status::Ok();
}

}  // namespace dermis
