// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// bench_deform, part 3: the deformers on the shared glTF rigs as a user meets them. Each asset
// is fitted with `dermis fit`'s defaults (FitCharacter) and posed like `dermis animate --mode
// lod` (CharacterPoser: the control vertices deformed, the patches refitted, the displaced
// surface tessellated at a level), once per deformer.
//
// Limb tests (docs/deformation.md, "Real rigs"): a joint J of the asset's own skeleton, with
// the bone P -> J before it (P its parent joint), is
// - bent by 90, 120 and 150 degrees about an axis perpendicular to that bone (the rest bend's
//   plane when J's next bone is already bent, else a fixed world axis): `vol` = enclosed
//   (signed) volume of the whole posed lod surface / that of the rest pose, `occ` = the same for
//   the occupied volume (winding number >= 1: skin pushed into skin counts once, where the
//   signed volume counts it twice; OccupiedVolume());
// - twisted by 180 degrees about the bone axis P -> J, the surface points near it cut into
//   twenty slices across the axis (0.05 to 1.95 bone lengths from P: the bone and as far again
//   past J, where the twist's transition straddles J; within 0.6 bone lengths of the axis):
//   `radius` = smallest ratio, posed / rest, of a slice's radius (the mean distance of its
//   points from their centroid: the candy wrapper collapses it; so does the surface cutting
//   inside where a coarse control mesh turns by a large angle between neighbouring rings);
// - twisted from 0 to 360 degrees in steps (history kept, as a clip plays): `r` = the smallest
//   `radius` over every frame, and `jump` = the largest frame-to-frame displacement of a surface
//   point near the bone / (2 r sin(step / 2)), r the largest rest radius of a slice: a point
//   turning rigidly with the step moves at most 1; a flip shows as a large value.
// Clip table: every clip of every fitted character at evenly spaced times (played from its
// start, history kept): `dvol` = largest |V / V_rest - 1| of the posed lod surface's enclosed
// volume, V_rest that of the rest pose; `docc` the same for the occupied volume.
#include "deform_real_rigs.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/asset/asset_pose.h"
#include "dermis/asset/asset_validate.h"
#include "dermis/deform/deformer.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/plugins/gltf.h"
#include "render/raster.h"

namespace dermis::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::array<DeformerKind, 3> kKinds = {DeformerKind::kLbs, DeformerKind::kDqs,
                                                DeformerKind::kSweep};

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

/// One limb test on one asset.
struct LimbTest {
  const char* label;
  const char* parent;  ///< P: the joint before J (the bone P -> J is bent at J / twisted).
  const char* joint;   ///< J.
  const char* child;   ///< The joint after J (null: J is a leaf).
  Vec3 hint;           ///< World axis the bend axis is taken from when the rest limb is straight.
  bool bend = true;
  bool twist = true;
};

struct AssetTests {
  const char* file;
  std::vector<LimbTest> limbs;
};

std::vector<AssetTests> Tests() {
  // RiggedSimple: the two-bone cylinder of issue 16 (its last joint bent and twisted).
  // RiggedFigure and CesiumMan: the left elbow (inner joint), wrist (leaf joint: the hand) and
  // knee. Bend axes: the rest bend's plane where the limb is bent at rest, else the hint.
  return {
      {"RiggedSimple.glb", {{"Bone.001", "Bone", "Bone.001", nullptr, Vec3(1, 0, 0), true, true}}},
      {"RiggedFigure.glb",
       {{"elbow L", "arm_joint_L_1", "arm_joint_L_2", "arm_joint_L_3", Vec3(0, 1, 0), true, false},
        {"wrist L", "arm_joint_L_2", "arm_joint_L_3", nullptr, Vec3(0, 1, 0), true, true},
        {"knee L", "leg_joint_L_1", "leg_joint_L_2", "leg_joint_L_3", Vec3(1, 0, 0), true, false}}},
      {"CesiumMan.glb",
       {{"elbow L", "Skeleton_arm_joint_L__4_", "Skeleton_arm_joint_L__3_",
         "Skeleton_arm_joint_L__2_", Vec3(0, 1, 0), true, false},
        {"wrist L", "Skeleton_arm_joint_L__3_", "Skeleton_arm_joint_L__2_", nullptr, Vec3(0, 1, 0),
         true, true},
        {"knee L", "leg_joint_L_1", "leg_joint_L_2", "leg_joint_L_3", Vec3(1, 0, 0), true, false}}},
  };
}

Index NodeNamed(const Asset& a, const char* name) {
  if (name == nullptr) return kInvalidIndex;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    if (a.nodes[i].name == name) return static_cast<Index>(i);
  }
  return kInvalidIndex;
}

/// The posed lod surface of every drawn primitive as one triangle soup.
struct Soup {
  std::vector<Vec3> x, n;
  std::vector<std::uint32_t> tris;
};

void Gather(const CharacterPoser& poser, const std::vector<PosedPrimitive>& posed, Soup* out) {
  out->x.clear();
  out->n.clear();
  out->tris.clear();
  for (std::size_t d = 0; d < posed.size(); ++d) {
    const DrawnPrimitive& dp = poser.drawn()[d];
    const AssetPrimitive& prim = poser.asset()
                                     .meshes[static_cast<std::size_t>(dp.mesh)]
                                     .primitives[static_cast<std::size_t>(dp.primitive)];
    const auto base = static_cast<std::uint32_t>(out->x.size());
    out->x.insert(out->x.end(), posed[d].positions.begin(), posed[d].positions.end());
    out->n.insert(out->n.end(), posed[d].normals.begin(), posed[d].normals.end());
    out->n.resize(out->x.size(), Vec3(0.0, 1.0, 0.0));
    for (const std::uint32_t i : PrimitiveTriangles(prim)) out->tris.push_back(base + i);
  }
}

/// Signed volume enclosed by the triangles (about their vertex centroid).
double Volume(const Soup& s) {
  Vec3 c(0.0);
  for (const Vec3& p : s.x) c += p;
  c /= static_cast<double>(std::max<std::size_t>(1, s.x.size()));
  double v = 0.0;
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    v += glm::dot(s.x[s.tris[t]] - c, glm::cross(s.x[s.tris[t + 1]] - c, s.x[s.tris[t + 2]] - c));
  }
  return v / 6.0;
}

/// Occupied volume: the volume where the surface's winding number is at least 1, so that skin
/// pushed into skin counts once (the signed volume counts it twice) and inverted folds count
/// nothing. Rays along the bounding box's longest axis through the centres of a `grid` x `grid`
/// lattice of square cells over the other two; each ray's crossings sorted by depth, entering
/// (+1) where the triangle faces against the ray and leaving (-1) where it faces along it.
double OccupiedVolume(const Soup& s, int grid) {
  Vec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const Vec3& p : s.x) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Vec3 ext = hi - lo;
  const int c = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  const int a = (c + 1) % 3, b = (c + 2) % 3;
  const double cell = std::max(ext[a], ext[b]) / grid;
  if (!(cell > 0.0)) return 0.0;
  const int na = static_cast<int>(std::ceil(ext[a] / cell)) + 1;
  const int nb = static_cast<int>(std::ceil(ext[b] / cell)) + 1;
  // Sample points slightly off the cell centres, so that no ray meets a vertex or edge exactly.
  const double oa = 0.5 + 1.234e-4, ob = 0.5 + 2.345e-4;
  struct Hit {
    std::int64_t column;
    double depth;
    int sign;
  };
  std::vector<Hit> hits;
  for (std::size_t t = 0; t + 2 < s.tris.size(); t += 3) {
    const Vec3& p0 = s.x[s.tris[t]];
    const Vec3& p1 = s.x[s.tris[t + 1]];
    const Vec3& p2 = s.x[s.tris[t + 2]];
    const double area = (p1[a] - p0[a]) * (p2[b] - p0[b]) - (p2[a] - p0[a]) * (p1[b] - p0[b]);
    if (area == 0.0) continue;
    const int i0 = std::max(
        0, static_cast<int>(std::floor((std::min({p0[a], p1[a], p2[a]}) - lo[a]) / cell - oa)));
    const int i1 = std::min(
        na - 1, static_cast<int>(std::ceil((std::max({p0[a], p1[a], p2[a]}) - lo[a]) / cell - oa)));
    const int j0 = std::max(
        0, static_cast<int>(std::floor((std::min({p0[b], p1[b], p2[b]}) - lo[b]) / cell - ob)));
    const int j1 = std::min(
        nb - 1, static_cast<int>(std::ceil((std::max({p0[b], p1[b], p2[b]}) - lo[b]) / cell - ob)));
    for (int i = i0; i <= i1; ++i) {
      const double qa = lo[a] + (i + oa) * cell;
      for (int j = j0; j <= j1; ++j) {
        const double qb = lo[b] + (j + ob) * cell;
        // Barycentric coordinates of (qa, qb) in the projected triangle.
        const double l1 = ((qa - p0[a]) * (p2[b] - p0[b]) - (p2[a] - p0[a]) * (qb - p0[b])) / area;
        const double l2 = ((p1[a] - p0[a]) * (qb - p0[b]) - (qa - p0[a]) * (p1[b] - p0[b])) / area;
        if (l1 < 0.0 || l2 < 0.0 || l1 + l2 > 1.0) continue;
        const double depth = p0[c] + l1 * (p1[c] - p0[c]) + l2 * (p2[c] - p0[c]);
        // (a, b, c) is right-handed: area > 0 means the normal points along +c (leaving).
        hits.push_back({static_cast<std::int64_t>(i) * nb + j, depth, area > 0.0 ? -1 : 1});
      }
    }
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
    return x.column != y.column ? x.column < y.column : x.depth < y.depth;
  });
  double length = 0.0;
  for (std::size_t k = 0; k < hits.size();) {
    int winding = 0;
    std::size_t e = k;
    for (; e < hits.size() && hits[e].column == hits[k].column; ++e) {
      if (winding >= 1) length += hits[e].depth - hits[e - 1].depth;
      winding += hits[e].sign;
    }
    k = e;
  }
  return length * cell * cell;
}

/// Turns node `joint` of `pose` by `angle` about the world axis `axis` through the joint (the
/// axis taken into the parent's frame; the parent's world matrix is a similarity in these rigs).
void TurnJoint(const Asset& a, const std::vector<glm::dmat4>& rest_world, Index joint,
               const Vec3& axis, double angle, AssetPose* pose) {
  const Index parent = a.nodes[static_cast<std::size_t>(joint)].parent;
  const glm::dmat3 pw =
      parent >= 0 ? glm::dmat3(rest_world[static_cast<std::size_t>(parent)]) : glm::dmat3(1.0);
  const Vec3 local_axis = glm::normalize(glm::inverse(pw) * axis);
  NodeTransform& t = pose->local[static_cast<std::size_t>(joint)];
  t.rotation = glm::angleAxis(angle, local_axis) * t.rotation;
}

constexpr int kSlices = 20;
constexpr int kGrid = 600;      // rays per side of the occupied-volume lattice (limb tests)
constexpr int kClipGrid = 300;  // the same for the clips' many frames

/// Points near the bone P -> J (rest), in slices across its axis: each point's slice and its
/// rest distance from the slice's centroid.
struct BoneRegion {
  std::vector<std::size_t> points;
  std::vector<int> slice;
  std::vector<double> rest_radius;
  std::array<double, kSlices> slice_max{};
};

/// Rest points whose projection on the axis of the bone P -> J falls between 0.05 and 1.95 bone
/// lengths from P (the bone and as far again past J: the twist's transition straddles J) and
/// whose distance from the axis is at most `reach` bone lengths (the limb, not the torso).
BoneRegion MakeRegion(const Soup& rest, const Vec3& p, const Vec3& j, double reach) {
  BoneRegion r;
  const double len = glm::length(j - p);
  const Vec3 axis = (j - p) / len;
  for (std::size_t i = 0; i < rest.x.size(); ++i) {
    const Vec3 d = rest.x[i] - p;
    const double u = glm::dot(d, axis) / len;
    if (u < 0.05 || u > 1.95) continue;
    if (glm::length(d - glm::dot(d, axis) * axis) > reach * len) continue;
    r.points.push_back(i);
    r.slice.push_back(std::min(kSlices - 1, static_cast<int>((u - 0.05) / (1.9 / kSlices))));
  }
  std::array<Vec3, kSlices> centre{};
  std::array<double, kSlices> n{};
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    centre[static_cast<std::size_t>(r.slice[k])] += rest.x[r.points[k]];
    n[static_cast<std::size_t>(r.slice[k])] += 1.0;
  }
  for (int s = 0; s < kSlices; ++s) {
    if (n[static_cast<std::size_t>(s)] > 0.0)
      centre[static_cast<std::size_t>(s)] /= n[static_cast<std::size_t>(s)];
  }
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const auto s = static_cast<std::size_t>(r.slice[k]);
    const double d = glm::length(rest.x[r.points[k]] - centre[s]);
    r.rest_radius.push_back(d);
    r.slice_max[s] = std::max(r.slice_max[s], d);
  }
  return r;
}

/// The smallest ratio, over the slices, of a cross section's radius posed / rest: the mean
/// distance of its points from their centroid (posed or rest), so that a section turning rigidly
/// keeps 1 whatever the axis.
double TwistRadius(const BoneRegion& r, const Soup& posed) {
  std::array<Vec3, kSlices> centre{};
  std::array<double, kSlices> n{}, rest_sum{}, posed_sum{};
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    centre[static_cast<std::size_t>(r.slice[k])] += posed.x[r.points[k]];
    n[static_cast<std::size_t>(r.slice[k])] += 1.0;
  }
  for (std::size_t s = 0; s < centre.size(); ++s) {
    if (n[s] > 0.0) centre[s] /= n[s];
  }
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const auto s = static_cast<std::size_t>(r.slice[k]);
    rest_sum[s] += r.rest_radius[k];
    posed_sum[s] += glm::length(posed.x[r.points[k]] - centre[s]);
  }
  double radius = std::numeric_limits<double>::max();
  for (std::size_t s = 0; s < rest_sum.size(); ++s) {
    if (rest_sum[s] > 0.0) radius = std::min(radius, posed_sum[s] / rest_sum[s]);
  }
  return radius;
}

struct Fitted {
  std::string name;
  Character character;
  std::array<CharacterPoser, 3> posers;  // kKinds order
  AssetPose rest_pose;
  std::vector<glm::dmat4> rest_world;
  Soup rest;
  double rest_volume = 0.0;
  double rest_occupied = 0.0, rest_occupied_coarse = 0.0;
};

Status FitAndPose(const std::string& path, const RealRigOptions& o, Fitted* f) {
  Asset asset;
  Status s = ImportGltf(path, &asset);
  if (s.ok()) s = ValidateAsset(asset);
  if (!s.ok()) return s;
  CharacterFitOptions cfo;
  cfo.fit.threads = o.threads;
  if (o.input_quads >= 0.0) cfo.input_quads = o.input_quads;
  s = FitCharacter(asset, cfo, &f->character, nullptr);
  if (!s.ok()) return s;
  for (std::size_t k = 0; k < kKinds.size(); ++k) {
    CharacterPoseOptions po;
    po.deformer = kKinds[k];
    po.mode = CharacterPoseMode::kLod;
    po.level = o.level;
    po.threads = o.threads;
    s = CharacterPoser::Build(f->character, po, &f->posers[k]);
    if (!s.ok()) return s;
  }
  const Asset& a = f->posers[0].asset();
  RestPose(a, &f->rest_pose);
  ComputeWorldMatrices(a, f->rest_pose, &f->rest_world);
  std::vector<PosedPrimitive> posed;
  s = f->posers[0].PoseClip(-1, 0.0, 30.0, &posed);
  if (!s.ok()) return s;
  Gather(f->posers[0], posed, &f->rest);
  f->rest_volume = Volume(f->rest);
  f->rest_occupied = OccupiedVolume(f->rest, kGrid);
  f->rest_occupied_coarse = OccupiedVolume(f->rest, kClipGrid);
  return Status::Ok();
}

Status PoseAll(Fitted* f, std::size_t k, const AssetPose& pose, Soup* out) {
  std::vector<PosedPrimitive> posed;
  Status s = f->posers[k].SetPose(pose);
  if (s.ok()) s = f->posers[k].Evaluate(&posed);
  if (!s.ok()) return s;
  Gather(f->posers[k], posed, out);
  return Status::Ok();
}

/// A contact sheet of one limb test: one row per deformer, one column per pose.
struct Sheet {
  std::vector<render::Mesh> meshes;  // one per cell, row-major
  std::vector<std::string> captions;
};

render::Mesh ToMesh(const Soup& s) {
  render::Mesh m;
  for (const Vec3& p : s.x) m.positions.emplace_back(p);
  for (const Vec3& q : s.n) m.normals.emplace_back(q);
  m.triangles = s.tris;
  return m;
}

/// Writes the sheet (cells framed on the box of the points within `reach` of `centre`, seen
/// along `axis`) as `path`.
void WriteSheet(const Sheet& sheet, int columns, const Vec3& centre, double reach, const Vec3& axis,
                const std::string& path) {
  render::Box box;
  for (const render::Mesh& m : sheet.meshes) {
    for (const glm::vec3& p : m.positions) {
      if (glm::length(Vec3(p) - centre) <= reach) box.Add(p);
    }
  }
  render::View view;
  view.width = view.height = 220;
  view.frame = box;
  view.azimuth = static_cast<float>(std::atan2(axis.x, axis.z) * 180.0 / kPi);
  view.elevation = static_cast<float>(std::asin(std::clamp(axis.y, -1.0, 1.0)) * 180.0 / kPi);
  std::vector<render::Image> images;
  for (std::size_t i = 0; i < sheet.meshes.size(); ++i) {
    view.caption = sheet.captions[i];
    images.push_back(render::Render({sheet.meshes[i]}, view));
  }
  const Status s = render::WritePng(path, render::ContactSheet(images, columns));
  std::printf("  %s: %s\n", path.c_str(), s.ok() ? "written" : s.message().c_str());
}

void RunLimb(Fitted* f, const LimbTest& t, const RealRigOptions& o) {
  const Asset& a = f->posers[0].asset();
  const Index p = NodeNamed(a, t.parent), j = NodeNamed(a, t.joint), c = NodeNamed(a, t.child);
  if (p < 0 || j < 0 || (t.child != nullptr && c < 0) ||
      a.nodes[static_cast<std::size_t>(j)].has_matrix) {
    std::printf("  %-14s skipped (joints not found, or J has a matrix transform)\n", t.label);
    return;
  }
  const Vec3 pp(f->rest_world[static_cast<std::size_t>(p)][3]);
  const Vec3 pj(f->rest_world[static_cast<std::size_t>(j)][3]);
  const Vec3 bone = glm::normalize(pj - pp);
  // The bend axis: across the rest bend where J's next bone bends away from P -> J by more than
  // 10 degrees, else the hint made perpendicular to the bone.
  Vec3 axis = t.hint - glm::dot(t.hint, bone) * bone;
  if (c >= 0) {
    const Vec3 next = glm::normalize(Vec3(f->rest_world[static_cast<std::size_t>(c)][3]) - pj);
    const Vec3 cr = glm::cross(bone, next);
    if (glm::length(cr) > std::sin(10.0 * kPi / 180.0)) axis = cr;
  }
  axis = glm::normalize(axis);
  Soup posed;
  // Pictures: per deformer, the bends and the 180 degree twist.
  std::array<Sheet, 3> rows;
  auto picture = [&](std::size_t k, const Soup& s, const std::string& caption) {
    if (o.pictures.empty()) return;
    rows[k].meshes.push_back(ToMesh(s));
    rows[k].captions.push_back(caption);
  };
  char caption[96];
  if (t.bend) {
    for (const double deg : {90.0, 120.0, 150.0}) {
      std::printf("  %-14s bend %3.0f  vol / occ", t.label, deg);
      AssetPose pose = f->rest_pose;
      TurnJoint(a, f->rest_world, j, axis, deg * kPi / 180.0, &pose);
      for (std::size_t k = 0; k < kKinds.size(); ++k) {
        f->posers[k].ResetHistory();
        const Status s = PoseAll(f, k, pose, &posed);
        if (!s.ok()) {
          std::printf(" | %-6s n/a (%s)", DeformerName(kKinds[k]), s.message().c_str());
          continue;
        }
        const double vol = Volume(posed) / f->rest_volume;
        const double occ = OccupiedVolume(posed, kGrid) / f->rest_occupied;
        std::printf(" | %-6s %6.3f / %5.3f", DeformerName(kKinds[k]), vol, occ);
        std::snprintf(caption, sizeof(caption), "%s bend %.0f vol %.3f occ %.3f",
                      DeformerName(kKinds[k]), deg, vol, occ);
        picture(k, posed, caption);
      }
      std::printf("\n");
    }
  }
  auto write_sheet = [&] {
    if (o.pictures.empty() || rows[0].meshes.empty()) return;
    Sheet all;
    for (const Sheet& r : rows) {
      all.meshes.insert(all.meshes.end(), r.meshes.begin(), r.meshes.end());
      all.captions.insert(all.captions.end(), r.captions.begin(), r.captions.end());
    }
    std::string stem = f->name.substr(0, f->name.find('.')) + "_" + t.label;
    std::replace(stem.begin(), stem.end(), ' ', '_');
    std::replace(stem.begin(), stem.end(), '.', '_');
    // Seen along the bend axis, from the limb's side of the body.
    Vec3 centroid(0.0);
    for (const Vec3& x : f->rest.x) centroid += x / static_cast<double>(f->rest.x.size());
    const Vec3 eye = glm::dot(axis, pj - centroid) < 0.0 ? -axis : axis;
    WriteSheet(all, static_cast<int>(rows[0].meshes.size()), pj, 1.6 * glm::length(pj - pp), eye,
               o.pictures + "/" + stem + ".png");
  };
  if (!t.twist) {
    write_sheet();
    return;
  }
  // The region of the bone P -> J: the limb within 0.6 bone lengths of the axis (0.6: the
  // forearm's radius is well inside, the torso beside a hanging arm is not).
  const BoneRegion region = MakeRegion(f->rest, pp, pj, 0.6);
  {
    std::printf("  %-14s twist 180 radius", t.label);
    AssetPose pose = f->rest_pose;
    TurnJoint(a, f->rest_world, j, bone, kPi, &pose);
    for (std::size_t k = 0; k < kKinds.size(); ++k) {
      f->posers[k].ResetHistory();
      const Status s = PoseAll(f, k, pose, &posed);
      if (!s.ok()) {
        std::printf(" | %-6s n/a", DeformerName(kKinds[k]));
        continue;
      }
      const double radius = TwistRadius(region, posed);
      std::printf(" | %-6s %6.3f        ", DeformerName(kKinds[k]), radius);
      std::snprintf(caption, sizeof(caption), "%s twist 180 radius %.2f", DeformerName(kKinds[k]),
                    radius);
      picture(k, posed, caption);
    }
    std::printf("  (%zu points)\n", region.points.size());
  }
  {
    const int steps = std::max(1, static_cast<int>(std::lround(360.0 / o.twist_step)));
    const double step = 2.0 * kPi / steps;
    std::printf("  %-14s twist 0..360 r/jump", t.label);
    for (std::size_t k = 0; k < kKinds.size(); ++k) {
      f->posers[k].ResetHistory();
      Soup prev;
      double radius_min = std::numeric_limits<double>::max(), jump = 0.0;
      bool ok = true;
      for (int s = 0; s <= steps && ok; ++s) {
        AssetPose pose = f->rest_pose;
        TurnJoint(a, f->rest_world, j, bone, s * step, &pose);
        ok = PoseAll(f, k, pose, &posed).ok();
        radius_min = std::min(radius_min, TwistRadius(region, posed));
        if (s > 0) {
          for (const std::size_t i : region.points) {
            jump = std::max(jump, glm::length(posed.x[i] - prev.x[i]));
          }
        }
        std::swap(prev, posed);
      }
      if (!ok) {
        std::printf(" | %-6s n/a", DeformerName(kKinds[k]));
        continue;
      }
      double r_max = 0.0;
      for (const double m : region.slice_max) r_max = std::max(r_max, m);
      const double rigid = 2.0 * r_max * std::sin(0.5 * step);
      std::printf(" | %-6s %6.3f / %5.2f", DeformerName(kKinds[k]), radius_min, jump / rigid);
    }
    std::printf("\n");
  }
  write_sheet();
}

void RunClips(Fitted* f, const RealRigOptions& o) {
  const Asset& a = f->posers[0].asset();
  for (std::size_t clip = 0; clip < a.animations.size(); ++clip) {
    std::string name = a.animations[clip].name;
    if (name.empty()) name = "#" + std::to_string(clip);
    std::printf("  clip %-14s dvol/docc", name.substr(0, 14).c_str());
    const double duration = a.animations[clip].Duration();
    for (std::size_t k = 0; k < kKinds.size(); ++k) {
      f->posers[k].ResetHistory();
      double dvol = 0.0, docc = 0.0;
      bool ok = true;
      Soup posed;
      for (int q = 0; q < o.clip_frames && ok; ++q) {
        const double time = o.clip_frames > 1 ? duration * q / (o.clip_frames - 1) : 0.0;
        AssetPose pose;
        SamplePose(a, static_cast<int>(clip), time, &pose);
        ok = PoseAll(f, k, pose, &posed).ok();
        dvol = std::max(dvol, std::fabs(Volume(posed) / f->rest_volume - 1.0));
        docc = std::max(
            docc, std::fabs(OccupiedVolume(posed, kClipGrid) / f->rest_occupied_coarse - 1.0));
      }
      if (ok) {
        std::printf(" | %-6s %7.5f / %7.5f", DeformerName(kKinds[k]), dvol, docc);
      } else {
        std::printf(" | %-6s n/a", DeformerName(kKinds[k]));
      }
    }
    std::printf("\n");
  }
}

}  // namespace

void RunRealRigs(const RealRigOptions& o) {
  if (!o.pictures.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.pictures, ec);
  }
  std::printf(
      "== Real rigs (%s): fitted with dermis fit's defaults, posed as dermis animate --mode lod "
      "(level %d)\n"
      "   vol  = enclosed (signed) volume of the posed lod surface / rest (1: kept);\n"
      "   occ  = occupied volume (winding number >= 1: skin pushed into skin counts once) / rest;\n"
      "   clips: dvol / docc = largest |vol - 1| / |occ - 1| over the clip's frames;\n"
      "   radius = smallest ratio posed / rest, over twenty slices across the twisted bone\n"
      "          (0.05..1.95 bone lengths from its start), of a slice's mean distance from its\n"
      "          centroid; r = the smallest over the 0..360 twist's frames;\n"
      "   jump = largest frame-to-frame move near the bone / (2 r sin(step/2)), r the largest\n"
      "          rest distance from a slice centroid (<= 1: rigid turning)\n",
      o.data.c_str(), o.level);
  std::vector<AssetTests> tests = Tests();
  std::vector<std::string> files = {"RiggedSimple.glb", "RiggedFigure.glb", "CesiumMan.glb"};
  if (o.clips) files = {"RiggedSimple.glb", "RiggedFigure.glb", "CesiumMan.glb", "Fox.glb"};
  for (const std::string& file : files) {
    if (!o.only.empty() && file.find(o.only) == std::string::npos) continue;
    const auto start = std::chrono::steady_clock::now();
    const std::string path = o.data + "/" + file;
    if (!std::filesystem::exists(path)) {
      std::printf("%s: skipped (not found: %s)\n", file.c_str(), path.c_str());
      continue;
    }
    Fitted f;
    f.name = file;
    const Status s = FitAndPose(path, o, &f);
    if (!s.ok()) {
      std::printf("%s: skipped (%s)\n", file.c_str(), s.message().c_str());
      continue;
    }
    std::printf("%s: %zu lod vertices, %zu triangles, rest volume %.6g (fit %.1f s)\n",
                file.c_str(), f.rest.x.size(), f.rest.tris.size() / 3, f.rest_volume,
                Seconds(start));
    for (const AssetTests& at : tests) {
      if (file != at.file) continue;
      for (const LimbTest& t : at.limbs) RunLimb(&f, t, o);
    }
    if (o.clips) RunClips(&f, o);
    std::printf("  (%.1f s)\n", Seconds(start));
  }
}

}  // namespace dermis::bench
