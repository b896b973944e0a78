// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief A small headless software rasteriser for pictures of surfaces (docs/cli.md,
/// "render"): z-buffered triangles with interpolated normals, two-sided Blinn-Phong shading,
/// an optional per-vertex scalar shown through a colour map with a legend, supersampled, and
/// PNG output (stb_image_write). Tool-level code: not part of the SDK.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "dermis/core/status.h"

namespace dermis::render {

/// One triangle mesh to draw. Positions in model units; normals per vertex (need not be unit).
struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> triangles;  ///< 3 indices each.
  /// Optional: one value per vertex, shown through the colour map instead of `color`.
  std::vector<float> scalar;
  glm::vec3 color{0.86f, 0.70f, 0.60f};
  /// Optional: segments drawn over the triangles (2 indices each), where they are not hidden
  /// by a triangle nearer the camera: the control mesh of a tessellated surface.
  std::vector<std::uint32_t> lines;
  glm::vec3 line_color{0.10f, 0.10f, 0.13f};
};

/// An axis-aligned box; empty when lo > hi.
struct Box {
  glm::vec3 lo{1e30f}, hi{-1e30f};
  void Add(const glm::vec3& p);
  bool empty() const { return lo.x > hi.x; }
};

/// Bounds of the meshes' positions.
Box Bounds(const std::vector<Mesh>& meshes);

/// How to draw.
struct View {
  int width = 800, height = 800;
  /// Orthographic camera on a sphere around the framed box: azimuth about +y from +z, elevation
  /// above the xz plane (glTF is y-up), degrees.
  float azimuth = 30.0f, elevation = 15.0f;
  /// The box to frame (empty: the meshes' bounds). Fixing it keeps the scale across frames.
  Box frame;
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  int supersample = 3;  ///< Samples per pixel along each axis.
  /// Colour map range for Mesh::scalar; a legend bar with `legend` as its title is drawn
  /// when show_legend is set.
  float scalar_min = 0.0f, scalar_max = 1.0f;
  bool show_legend = false;
  std::string legend;
  std::string caption;  ///< Text at the top left (may be empty).
};

/// An 8-bit RGB image, rows top to bottom.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Renders the meshes. Degenerate or non-finite triangles are skipped.
Image Render(const std::vector<Mesh>& meshes, const View& view);

/// Colour of t in [0, 1] (clamped) on the map used for scalars: dark blue, blue, teal, yellow,
/// red.
glm::vec3 ColorMap(float t);

/// Places images on a grid of `columns` (rows as needed), each with its own size, on a white
/// background: a contact sheet.
Image ContactSheet(const std::vector<Image>& images, int columns);

/// Encodes PNG bytes.
std::string EncodePng(const Image& image);

/// Writes a PNG atomically (temporary file, then rename). Errors name the path.
Status WritePng(const std::string& path, const Image& image);

}  // namespace dermis::render
