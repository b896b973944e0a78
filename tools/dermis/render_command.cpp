// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// dermis render: pictures of a fitted surface or a posed character, headless (tools/render):
// one view, a turntable or the frames of a clip as a contact sheet, optionally coloured by the
// fit error with a legend.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "character_args.h"
#include "commands.h"
#include "dermis/asset/asset_pose.h"
#include "dermis/core/file_io.h"
#include "dermis/core/path.h"
#include "dermis/offline/character/character_pose.h"
#include "dermis/offline/character/skin_transfer.h"
#include "dermis/offline/geometry/triangle_distance.h"
#include "dermis/offline/io/point_input.h"
#include "dermis/surface/bspline_displacement.h"
#include "dermis/surface/tessellation.h"
#include "importers.h"
#include "progress_bar.h"
#include "render/raster.h"

namespace dermis::cli {
namespace {

constexpr const char* kRenderCommand = "render";

struct RenderArgs {
  std::string input;
  std::string output;
  std::string clip;
  double time = 0.0;
  bool time_given = false;
  std::string deformer = "sweep";
  std::string compare;  // deformers (comma-separated) drawn as further rows
  std::string mode = kDefaultMode;
  int level = kDefaultLevel;
  int displacement_levels = kAllDisplacementLevels;
  std::string heatmap = "none";
  std::string reference;
  std::string size = "800x800";
  float azimuth = 30.0f, elevation = 15.0f;
  int frames = 0;
  int turntable = 0;
  int columns = 0;
  bool frame_files = false;
  double fps = kDefaultPoseStepsPerSecond;
  std::string caption;
  std::string series;      // surfaces: displacement levels, one view each
  bool wireframe = false;  // control-mesh edges over the tessellation
  bool force = false;
  bool quiet = false;
};

glm::vec3 F(const Vec3& v) { return glm::vec3(v); }

// Distance from each vertex of `meshes` to the reference triangles in `tree` (model units).
void DistanceMap(const TriangleDistanceTree& tree, std::vector<render::Mesh>* meshes) {
  for (render::Mesh& m : *meshes) {
    m.scalar.resize(m.positions.size());
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
      m.scalar[i] = static_cast<float>(tree.Query(Vec3(m.positions[i])).distance);
    }
  }
}

// The colour range of an error map: 0 to the 99th percentile (so one outlier does not wash the
// picture out; larger values show as the top colour).
float ErrorRange(const std::vector<render::Mesh>& meshes) {
  std::vector<float> all;
  for (const render::Mesh& m : meshes) all.insert(all.end(), m.scalar.begin(), m.scalar.end());
  if (all.empty()) return 1.0f;
  const std::size_t k =
      std::min(all.size() - 1, static_cast<std::size_t>(0.99 * static_cast<double>(all.size())));
  std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end());
  return all[k] > 0.0f ? all[k] : 1.0f;
}

// On an edge of its control face: one face coordinate exactly 0 or 1 (the tessellation puts
// vertex and edge samples there, face samples strictly inside).
template <class Location>
bool OnControlEdge(const Location& s) {
  return s.u == 0.0 || s.u == 1.0 || s.v == 0.0 || s.v == 1.0;
}

// The edges of `triangles` whose two ends lie on control edges (of the same part, `on_edge`
// decides): at 2 or more segments per face edge these are the control edges' segments, since
// every cell's diagonal has an end inside its face (docs/cli.md, "render"). Each once.
template <class OnEdge>
std::vector<std::uint32_t> ControlEdgeLines(const std::vector<std::uint32_t>& triangles,
                                            const OnEdge& on_edge) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = triangles[t + k], b = triangles[t + (k + 1) % 3];
      if (on_edge(a, b)) edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<std::uint32_t> lines;
  lines.reserve(2 * edges.size());
  for (const auto& [a, b] : edges) {
    lines.push_back(a);
    lines.push_back(b);
  }
  return lines;
}

// Prints the segments drawn and the control edges' segments there are (level per edge): the
// two agree unless a control edge went missing or a diagonal was taken for one.
void ReportWireframe(const std::vector<render::Mesh>& meshes, std::size_t expected, bool quiet) {
  if (quiet) return;
  std::size_t drawn = 0;
  for (const render::Mesh& m : meshes) drawn += m.lines.size() / 2;
  std::fprintf(stderr, "dermis render: wireframe: %zu segments drawn, %zu on the control edges\n",
               drawn, expected);
}

// A surface (version 1 or 3) tessellated at `level` with `displacement_levels` (-1: all).
Status SurfaceMesh(const RenderArgs& a, const DisplacedSurface& surface, int displacement_levels,
                   std::vector<render::Mesh>* out) {
  std::vector<LocalPatch> patches(surface.rest_positions.size());
  surface.domain->FitPatches(surface.rest_positions.data(), patches.data());
  TessellationPattern pattern;
  const Status s = TessellationPattern::Build(surface.domain->topology(), a.level, &pattern);
  if (!s.ok()) return s;
  std::unique_ptr<TruncatedDisplacement> truncated;
  const Displacement* disp = surface.displacement.get();
  if (disp && displacement_levels >= 0) {
    truncated =
        std::make_unique<TruncatedDisplacement>(surface.displacement.get(), displacement_levels);
    disp = truncated.get();
  }
  const std::size_t n = pattern.samples.size();
  std::vector<Vec3> x(n), nrm(n);
  if (!EvaluateSamples(*surface.domain, patches.data(), disp, pattern.samples.data(), n, x.data(),
                       nrm.data())) {
    return Status::Internal(a.input + ": evaluation failed");
  }
  render::Mesh m;
  for (std::size_t i = 0; i < n; ++i) {
    m.positions.push_back(F(x[i]));
    m.normals.push_back(F(nrm[i]));
  }
  m.triangles = pattern.triangles;
  if (a.wireframe) {
    const std::vector<SampleLocation>& smp = pattern.samples;
    m.lines = ControlEdgeLines(m.triangles, [&](std::uint32_t i, std::uint32_t j) {
      return i < smp.size() && j < smp.size() && OnControlEdge(smp[i]) && OnControlEdge(smp[j]);
    });
  }
  out->push_back(std::move(m));
  return Status::Ok();
}

// The posed primitives of a character as render meshes (triangles only).
std::vector<render::Mesh> PosedMeshes(const CharacterPoser& poser,
                                      const std::vector<PosedPrimitive>& posed) {
  std::vector<render::Mesh> meshes;
  for (std::size_t d = 0; d < posed.size(); ++d) {
    const DrawnPrimitive& dp = poser.drawn()[d];
    const AssetPrimitive& prim = poser.asset()
                                     .meshes[static_cast<std::size_t>(dp.mesh)]
                                     .primitives[static_cast<std::size_t>(dp.primitive)];
    render::Mesh m;
    m.triangles = PrimitiveTriangles(prim);
    for (const Vec3& p : posed[d].positions) m.positions.push_back(F(p));
    for (const Vec3& n : posed[d].normals) m.normals.push_back(F(n));
    meshes.push_back(std::move(m));
  }
  return meshes;
}

// The lod tessellation's control edges as lines, per drawn primitive of `poser` (empty where no
// part replaces it): topology only, built once for every frame drawn.
std::vector<std::vector<std::uint32_t>> WireframeLines(const CharacterPoser& poser) {
  std::vector<std::vector<std::uint32_t>> lines(poser.drawn().size());
  for (std::size_t d = 0; d < lines.size(); ++d) {
    const DrawnPrimitive& dp = poser.drawn()[d];
    const AssetPrimitive& prim = poser.asset()
                                     .meshes[static_cast<std::size_t>(dp.mesh)]
                                     .primitives[static_cast<std::size_t>(dp.primitive)];
    const std::vector<VertexBinding>& loc = poser.surface_locations(d);
    lines[d] = ControlEdgeLines(PrimitiveTriangles(prim), [&](std::uint32_t i, std::uint32_t j) {
      return i < loc.size() && j < loc.size() && loc[i].part >= 0 && loc[i].part == loc[j].part &&
             OnControlEdge(loc[i]) && OnControlEdge(loc[j]);
    });
  }
  return lines;
}

// The source character as a glTF viewer draws it at the rest pose (world space), as one
// triangle soup: the reference of a character's error map.
void SourceAtRest(const Asset& asset, std::vector<Vec3>* positions,
                  std::vector<std::uint32_t>* triangles) {
  AssetPose pose;
  RestPose(asset, &pose);
  std::vector<glm::dmat4> world;
  ComputeWorldMatrices(asset, pose, &world);
  for (std::size_t node = 0; node < asset.nodes.size(); ++node) {
    const Index mesh = asset.nodes[node].mesh;
    if (mesh < 0) continue;
    for (const AssetPrimitive& prim : asset.meshes[static_cast<std::size_t>(mesh)].primitives) {
      std::vector<glm::dvec3> p;
      PosePrimitive(asset, pose, world, static_cast<Index>(node), prim, &p, nullptr);
      const auto base = static_cast<std::uint32_t>(positions->size());
      positions->insert(positions->end(), p.begin(), p.end());
      for (std::uint32_t i : PrimitiveTriangles(prim)) triangles->push_back(base + i);
    }
  }
}

bool ParseSize(const std::string& s, int* w, int* h) {
  const std::size_t x = s.find('x');
  if (x == std::string::npos) return false;
  try {
    std::size_t used = 0;
    *w = std::stoi(s.substr(0, x), &used);
    if (used != x) return false;
    *h = std::stoi(s.substr(x + 1), &used);
    if (used != s.size() - x - 1) return false;
  } catch (...) {
    return false;
  }
  return *w >= 16 && *h >= 16 && *w <= 8192 && *h <= 8192;
}

// The displacement levels of --series "0,2,-1" (each in -1..kMaxBsplineLevels, the range of
// --displacement-levels); false if it is malformed.
bool ParseSeries(const std::string& series, std::vector<int>* levels) {
  levels->clear();
  std::size_t at = 0;
  while (at <= series.size()) {
    const std::size_t comma = std::min(series.find(',', at), series.size());
    const std::string item = series.substr(at, comma - at);
    int L = -2;
    const auto r = std::from_chars(item.data(), item.data() + item.size(), L);
    if (r.ec != std::errc() || r.ptr != item.data() + item.size() || L < -1 ||
        L > kMaxBsplineLevels) {
      return false;
    }
    levels->push_back(L);
    at = comma + 1;
  }
  return true;
}

// Colours every surface of `surfaces` by its distance to the --reference mesh; *stats receives
// "mean M max X" per surface and *range the top of the shared colour scale.
Status ErrorMaps(const RenderArgs& a, std::vector<std::vector<render::Mesh>>* surfaces,
                 std::vector<std::string>* stats, float* range) {
  PolygonMesh ref;
  Index dropped = 0;
  const Status s = ReadFitInput(a.reference, &ref, &dropped, &Importers());
  if (!s.ok()) return s;
  std::vector<std::uint32_t> tris;
  for (Index f = 0; f < ref.num_faces(); ++f) {
    const Index* fv = ref.face_vertices.data() + ref.face_offsets[f];
    for (Index k = 1; k + 1 < ref.face_size(f); ++k) {
      tris.insert(tris.end(), {static_cast<std::uint32_t>(fv[0]), static_cast<std::uint32_t>(fv[k]),
                               static_cast<std::uint32_t>(fv[k + 1])});
    }
  }
  if (tris.empty()) return Status::InvalidInput(a.reference + ": has no faces");
  TriangleDistanceTree tree;  // once for every level
  tree.Build(ref.positions, tris);
  *range = 0.0f;
  stats->assign(surfaces->size(), std::string());
  for (std::size_t k = 0; k < surfaces->size(); ++k) {
    DistanceMap(tree, &(*surfaces)[k]);
    *range = std::max(*range, ErrorRange((*surfaces)[k]));
    double sum = 0.0, worst = 0.0;
    std::size_t n = 0;
    for (const render::Mesh& m : (*surfaces)[k]) {
      for (float e : m.scalar) {
        sum += e;
        worst = std::max(worst, static_cast<double>(e));
        ++n;
      }
    }
    char line[160];
    std::snprintf(line, sizeof(line), "mean %.3g max %.3g", n ? sum / static_cast<double>(n) : 0.0,
                  worst);
    (*stats)[k] = line;
  }
  return Status::Ok();
}

// A surface (version 1 or 3; no pose): one view per displacement level of --series, or per
// turntable angle. Returns an exit status.
int RenderSurface(const RenderArgs& a, const DisplacedSurface& surface, render::View* view_out,
                  std::vector<render::Image>* images) {
  render::View& view = *view_out;
  const bool error_map = a.heatmap == "error";
  // A plain surface: no pose; the error map needs the data it was fitted to.
  if (a.frames > 0 || !a.clip.empty() || a.time_given || !a.compare.empty()) {
    return Usage(kRenderCommand, a.input +
                                     " is a surface without a skeleton: --clip, --time, --frames "
                                     "and --compare apply to characters");
  }
  if (error_map && a.reference.empty()) {
    return Usage(kRenderCommand,
                 "--heatmap error on a surface needs --reference MESH (the data it was fitted to)");
  }
  // One surface per displacement level of --series (or the one --displacement-levels).
  std::vector<int> levels = {a.displacement_levels};
  if (!a.series.empty() && !ParseSeries(a.series, &levels)) {
    return Usage(kRenderCommand, "--series '" + a.series + "' must list displacement levels -1.." +
                                     std::to_string(kMaxBsplineLevels) + ", e.g. 0,2,4");
  }
  std::vector<std::vector<render::Mesh>> surfaces(levels.size());
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const Status s = SurfaceMesh(a, surface, levels[k], &surfaces[k]);
    if (!s.ok()) return Fail(kRenderCommand, s);
  }
  std::vector<std::string> stats(levels.size());
  if (error_map) {
    float range = 0.0f;
    const Status s = ErrorMaps(a, &surfaces, &stats, &range);
    if (!s.ok()) return Fail(kRenderCommand, s);
    view.show_legend = true;
    view.scalar_max = range;  // one scale for every level
    view.legend = "distance to data";
  }
  if (a.wireframe) {
    ReportWireframe(surfaces[0],
                    static_cast<std::size_t>(surface.domain->topology().num_edges()) *
                        static_cast<std::size_t>(a.level),
                    a.quiet);
  }
  const int views = std::max(1, a.turntable);
  ProgressBar bar(kRenderCommand, a.quiet);
  for (std::size_t k = 0; k < levels.size(); ++k) {
    if (!a.series.empty()) {
      const std::string name =
          levels[k] < 0 ? std::string("all levels") : "levels " + std::to_string(levels[k]);
      view.caption =
          a.caption.empty() ? name + (error_map ? ": " + stats[k] : std::string()) : a.caption;
      if (error_map && !a.quiet) {
        std::fprintf(stderr, "dermis render: displacement %s: distance to data %s\n", name.c_str(),
                     stats[k].c_str());
      }
    }
    for (int v = 0; v < views; ++v) {
      bar.Update("drawing views", images->size(), levels.size() * static_cast<std::size_t>(views));
      if (a.turntable > 0)
        view.azimuth = a.azimuth + 360.0f * static_cast<float>(v) / static_cast<float>(views);
      images->push_back(render::Render(surfaces[k], view));
    }
  }
  return kExitOk;
}

// The deformers of --compare, in order ("dqs,lbs" -> {"dqs", "lbs"}).
std::vector<std::string> CompareList(const std::string& compare) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (!compare.empty() && at <= compare.size()) {
    const std::size_t comma = std::min(compare.find(',', at), compare.size());
    out.push_back(compare.substr(at, comma - at));
    at = comma + 1;
  }
  return out;
}

// A character posed at --time or over --frames of a clip, with --compare's deformers as further
// rows. Returns an exit status.
int RenderCharacter(const RenderArgs& a, const Character& ch, render::View* view_out,
                    std::vector<render::Image>* images) {
  render::View& view = *view_out;
  const bool error_map = a.heatmap == "error";
  if (a.wireframe && a.mode != "lod") {
    return Usage(kRenderCommand,
                 "--wireframe on a character needs --mode lod (the bound mode draws the "
                 "original triangles)");
  }
  std::vector<std::string> captions;
  int clip = -1;
  Status s = ResolveClip(ch.asset, a.input, a.clip, &clip);
  if (!s.ok()) return Fail(kRenderCommand, s);
  if (clip < 0 && (a.frames > 0 || (a.time_given && a.time != 0.0))) {
    return Fail(kRenderCommand,
                Status::InvalidInput(a.input + ": --time and --frames apply to a clip (" +
                                     ClipList(ch.asset) + ")"));
  }
  // One poser per deformer drawn: the primary one, and --compare's as further rows.
  std::vector<std::string> deformers = {a.deformer};
  for (const std::string& d : CompareList(a.compare)) deformers.push_back(d);
  std::vector<CharacterPoser> posers(deformers.size());
  for (std::size_t k = 0; k < deformers.size(); ++k) {
    CharacterPoseOptions po;
    s = MakePoseOptions(deformers[k], a.mode, a.level, a.displacement_levels, 0, &po);
    if (!s.ok()) return Fail(kRenderCommand, s);
    s = CharacterPoser::Build(ch, po, &posers[k]);
    if (!s.ok()) return Fail(kRenderCommand, s);
  }
  CharacterPoser& poser = posers[0];
  // The times to draw.
  std::vector<double> times;
  if (a.frames > 0) {
    const double duration = ch.asset.animations[static_cast<std::size_t>(clip)].Duration();
    for (int k = 0; k < a.frames; ++k) {
      times.push_back(a.frames == 1 ? 0.0 : duration * k / (a.frames - 1));
    }
  } else {
    times.push_back(a.time);
  }
  std::vector<float> error;  // per vertex of the drawn primitives, concatenated
  if (error_map) {
    std::vector<PosedPrimitive> rest;
    s = poser.PoseClip(-1, 0.0, a.fps, &rest);
    if (!s.ok()) return Fail(kRenderCommand, s);
    std::vector<render::Mesh> rest_meshes = PosedMeshes(poser, rest);
    std::vector<Vec3> ref;
    std::vector<std::uint32_t> tris;
    SourceAtRest(ch.asset, &ref, &tris);
    TriangleDistanceTree tree;
    tree.Build(ref, tris);
    DistanceMap(tree, &rest_meshes);
    for (const render::Mesh& m : rest_meshes)
      error.insert(error.end(), m.scalar.begin(), m.scalar.end());
    view.show_legend = true;
    view.scalar_max = ErrorRange(rest_meshes);
    view.legend = "distance to source";
  }
  // The control edges, once: every poser draws the same lod asset (same mode and level).
  std::vector<std::vector<std::uint32_t>> wire;
  if (a.wireframe) wire = WireframeLines(poser);
  std::vector<std::vector<render::Mesh>> frames;
  render::Box box;
  ProgressBar bar(kRenderCommand, a.quiet);
  for (std::size_t k = 0; k < posers.size(); ++k) {
    for (double t : times) {
      bar.Update("posing frames", frames.size(), posers.size() * times.size());
      std::vector<PosedPrimitive> posed;
      s = posers[k].PoseClip(clip, t, a.fps, &posed);
      if (!s.ok()) return Fail(kRenderCommand, s);
      std::vector<render::Mesh> meshes = PosedMeshes(posers[k], posed);
      for (std::size_t d = 0; d < meshes.size() && d < wire.size(); ++d) meshes[d].lines = wire[d];
      std::size_t at = 0;
      for (render::Mesh& m : meshes) {
        if (error_map) {
          m.scalar.assign(error.begin() + static_cast<std::ptrdiff_t>(at),
                          error.begin() + static_cast<std::ptrdiff_t>(at + m.positions.size()));
        }
        at += m.positions.size();
      }
      const render::Box b = render::Bounds(meshes);
      if (!b.empty()) {
        box.Add(b.lo);
        box.Add(b.hi);
      }
      frames.push_back(std::move(meshes));
      char cap[96];
      std::snprintf(cap, sizeof(cap), "%s t=%.2fs", deformers[k].c_str(), t);
      captions.push_back(clip >= 0 ? std::string(cap) : deformers[k] + " rest");
    }
  }
  if (a.wireframe && !frames.empty()) {
    std::size_t expected = 0;  // every drawn part's control edges, `level` segments each
    for (std::size_t d = 0; d < poser.drawn().size(); ++d) {
      const std::vector<VertexBinding>& loc = poser.surface_locations(d);
      if (loc.empty() || loc[0].part < 0) continue;
      const DisplacedSurface& surf = ch.parts[static_cast<std::size_t>(loc[0].part)].surface;
      expected += static_cast<std::size_t>(surf.domain->topology().num_edges()) *
                  static_cast<std::size_t>(a.level);
    }
    ReportWireframe(frames[0], expected, a.quiet);
  }
  view.frame = box;  // one scale for every frame
  const int views = std::max(1, a.turntable);
  for (std::size_t f = 0; f < frames.size(); ++f) {
    for (int k = 0; k < views; ++k) {
      bar.Update("drawing views", images->size(), frames.size() * static_cast<std::size_t>(views));
      if (a.turntable > 0)
        view.azimuth = a.azimuth + 360.0f * static_cast<float>(k) / static_cast<float>(views);
      if (a.caption.empty() && (frames.size() > 1 || !a.compare.empty())) {
        view.caption = captions[f];
      }
      images->push_back(render::Render(frames[f], view));
    }
  }
  return kExitOk;
}

int RunRender(const RenderArgs& a) {
  int width = 0, height = 0;
  if (!ParseSize(a.size, &width, &height)) {
    return Usage(kRenderCommand, "--size '" + a.size + "' must be WxH with 16 <= W, H <= 8192");
  }
  if (LowerExtension(a.output) != ".png")
    return Usage(kRenderCommand, a.output + ": the output must be a .png file");
  if (a.frames > 0 && a.turntable > 0)
    return Usage(kRenderCommand, "--frames and --turntable exclude each other");
  if (!a.compare.empty() && a.turntable > 0)
    return Usage(kRenderCommand, "--compare and --turntable exclude each other");
  if (a.wireframe && a.level < 2) {
    return Usage(kRenderCommand,
                 "--wireframe needs --level 2 or more (the control edges are the tessellation's "
                 "face borders)");
  }
  if (const int rc = CheckOverwrite(kRenderCommand, {a.output}, a.force); rc != kExitOk) return rc;
  std::string bytes;
  {
    const Status s = ReadFileBytes(a.input, "the input", &bytes);
    if (!s.ok()) return Fail(kRenderCommand, s);
  }
  if (DsurfFileVersion(bytes) == 0) {
    return Fail(kRenderCommand,
                Status::InvalidInput(a.input + ": not a .dsurf file (fit a mesh or character "
                                               "with 'dermis fit' first)"));
  }
  Character ch;
  std::uint32_t version = 0;
  if (const Status s = ParseCharacter(bytes, a.input, &ch, &version); !s.ok())
    return Fail(kRenderCommand, s);
  render::View view;
  view.width = width;
  view.height = height;
  view.azimuth = a.azimuth;
  view.elevation = a.elevation;
  view.caption = a.caption;
  std::vector<render::Image> images;
  const int rc = IsSurfaceDsurfVersion(version)
                     ? RenderSurface(a, ch.parts[0].surface, &view, &images)
                     : RenderCharacter(a, ch, &view, &images);
  if (rc != kExitOk) return rc;

  MakeParentFolder(a.output);
  const std::filesystem::path parent = std::filesystem::path(a.output).parent_path();
  if (a.frame_files && images.size() > 1) {
    const std::string stem = (parent / std::filesystem::path(a.output).stem()).string();
    for (std::size_t k = 0; k < images.size(); ++k) {
      char suffix[32];
      std::snprintf(suffix, sizeof(suffix), "_%03zu.png", k);
      const Status s = render::WritePng(stem + suffix, images[k]);
      if (!s.ok()) return Fail(kRenderCommand, s);
    }
  }
  // Default layout: one row per deformer with --compare, else about square.
  const int columns =
      a.columns > 0 ? a.columns
      : !a.compare.empty()
          ? static_cast<int>(images.size() / (1 + CompareList(a.compare).size()))
          : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(images.size()))));
  const render::Image out = images.size() == 1 ? images[0] : render::ContactSheet(images, columns);
  const Status s = render::WritePng(a.output, out);
  if (!s.ok()) return Fail(kRenderCommand, s);
  if (!a.quiet) {
    std::fprintf(
        stderr, "dermis render: %zu view%s, %dx%d%s\nwrote %s\n", images.size(),
        images.size() == 1 ? "" : "s", out.width, out.height,
        view.show_legend
            ? (", error map 0.." + std::to_string(view.scalar_max) + " model units").c_str()
            : "",
        a.output.c_str());
  }
  return kExitOk;
}

}  // namespace

void AddRenderCommand(CLI::App* app, std::function<int()>* run) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app->add_subcommand(
      "render",
      "Render a fitted surface or a posed character (.dsurf) to PNG, headless: one view, a "
      "turntable, or the frames of a clip as a contact sheet, optionally coloured by the fit "
      "error.");
  cmd->add_option("INPUT", args->input, "Fitted surface or character (.dsurf)")->required();
  cmd->add_option("-o,--output", args->output, "Picture (.png)")->required();
  cmd->add_option("--clip", args->clip,
                  "Clip name or index (default: 0, or the rest pose when there are no clips; "
                  "'rest': the rest pose)");
  cmd->add_option("--time", args->time, "Seconds from the clip's start")
      ->check(CLI::Range(0.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Draw N frames evenly over the clip as a contact sheet")
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--frame-files", args->frame_files,
                "With --frames, --turntable or --series: also write OUTPUT_000.png, "
                "OUTPUT_001.png, ...");
  cmd->add_option("--turntable", args->turntable, "Draw N views around the vertical axis")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--columns", args->columns, "Columns of the contact sheet (default: square)")
      ->check(CLI::Range(1, 64));
  AddDeformerOption(cmd, "--deformer", "Deformer of the control vertices", &args->deformer)
      ->capture_default_str();
  cmd->add_option("--compare", args->compare,
                  "Characters: draw the same frames with these deformers too (comma-separated, "
                  "e.g. dqs,lbs), one row each")
      ->check(CLI::Validator(
          [](std::string& value) {
            for (const std::string& d : CompareList(value)) {
              DeformerKind kind;
              const Status s = DeformerFromName(d, &kind);
              if (!s.ok()) return s.message();
            }
            return std::string();
          },
          "DEFORMER[,DEFORMER...]"));
  AddEvaluationOptions(cmd, "the original vertices on the surface", &args->mode, &args->level,
                       &args->displacement_levels);
  cmd->add_option("--heatmap", args->heatmap,
                  "Colour by: none, or error (distance to the source mesh at the rest pose for a "
                  "character, to --reference for a surface; 0..99th percentile, legend)")
      ->check(CLI::IsMember({"none", "error"}))
      ->capture_default_str();
  cmd->add_option("--reference", args->reference,
                  "The data a surface was fitted to (.obj or .ply), for --heatmap error");
  cmd->add_option("--size", args->size, "Picture size WxH (pixels, per view)")
      ->capture_default_str();
  cmd->add_option("--azimuth", args->azimuth, "Camera azimuth about +y (degrees)")
      ->capture_default_str();
  cmd->add_option("--elevation", args->elevation, "Camera elevation (degrees)")
      ->check(CLI::Range(-89.0, 89.0))
      ->capture_default_str();
  cmd->add_option("--fps", args->fps, "Steps per second of the clip replay (the sweep's history)")
      ->check(CLI::Range(0.001, 1000.0))
      ->capture_default_str();
  cmd->add_option("--caption", args->caption, "Text at the top left");
  cmd->add_option("--series", args->series,
                  "Surfaces: one view per displacement level listed (e.g. 0,2,4,-1; -1: all), "
                  "as a contact sheet; with --heatmap error each is captioned with its error");
  cmd->add_flag("--wireframe", args->wireframe,
                "Draw the control mesh's edges on the tessellated surface (surfaces; characters "
                "with --mode lod; --level 2 or more)");
  cmd->add_flag("-f,--force", args->force, "Overwrite output files that exist");
  AddQuietFlag(cmd, &args->quiet);
  CLI::Option* time = cmd->get_option("--time");
  cmd->callback([run, args, time]() {
    args->time_given = time->count() > 0;
    *run = [args]() { return RunRender(*args); };
  });
}

}  // namespace dermis::cli
