// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief glTF 2.0 import and export (tinygltf 2.7) to and from the neutral asset module.
#pragma once

#include <cstddef>
#include <string>

#include "dermis/asset/asset.h"
#include "dermis/asset/importer.h"
#include "dermis/core/status.h"

namespace dermis {

/// Name of the root-level glTF extension that carries a .dsurf file (docs/file-format.md).
constexpr const char* kDsurfGltfExtension = "DERMIS_displaced_surface";

/// Reads a .gltf (embedded or external buffers and images) or .glb into `out`.
/// Every accessor encoding is decoded (byteStride, normalised integers, sparse,
/// KHR_mesh_quantization); all JOINTS_n/WEIGHTS_n sets are read and weights renormalised per
/// vertex; skins without inverseBindMatrices get identities; images stay encoded bytes.
/// Triangle strips and fans stay as they are (AssetPrimitive::mode).
/// \param dsurf_bytes  if non-null, receives the bytes of the DERMIS_displaced_surface
///                     extension (empty if the file has none).
/// Errors (kIoError for unreadable files, kInvalidInput otherwise) name the file and a JSON
/// pointer, e.g. "x.glb: /accessors/3: byteOffset + size exceeds bufferView 2".
/// Nothing in `out` is valid after an error.
Status ImportGltf(const std::string& path, Asset* out, std::string* dsurf_bytes = nullptr);

/// True for the extensions of glTF files (.gltf, .glb, any case).
bool IsGltfPath(const std::string& path);

namespace plugins::gltf {
/// Adds the glTF importer to `registry`: assets from .gltf and .glb through ImportGltf(), the
/// DERMIS_displaced_surface extension as ImportedAsset::embedded_dsurf.
void Register(ImporterRegistry* registry);
}  // namespace plugins::gltf

/// Options of ExportGltf().
struct GltfExportOptions {
  /// Largest number of joint influences per vertex written (multiple of 4 -> JOINTS_0..n).
  /// Extra influences are dropped smallest first and the rest renormalised in float32.
  int max_influences = 4;
  /// If non-empty, stored as the root extension DERMIS_displaced_surface (a bufferView).
  std::string dsurf_bytes;
  /// Written as asset.generator ("Dermis <version>" by default).
  std::string generator = "Dermis";
  /// KHR_mesh_quantization (docs/gltf-compression.md): positions as u16 integers on a grid
  /// whose step is chosen from the model (GltfQuantizeReport), normals and tangents as
  /// normalised i16, texture coordinates and colours in [0, 1] as normalised u16, weights as
  /// normalised u16 summing to exactly 65535. The dequantising transform goes into the inverse
  /// bind matrices of skinned meshes and into a child node of every other mesh node. Listed in
  /// extensionsRequired.
  bool quantize = false;
  /// EXT_meshopt_compression (docs/gltf-compression.md): every vertex, index and animation
  /// bufferView encoded with meshoptimizer; the extension is required and its fallback buffer
  /// holds no data (the file is not meant for readers without the extension).
  bool compress = false;
};

/// What ExportGltf() did to the data with GltfExportOptions::quantize / compress.
struct GltfExportReport {
  bool quantized = false;
  /// Bits of the position grid (10..16) and its step in model units.
  int position_bits = 0;
  double position_step = 0.0;
  /// Largest distance between a written and a dequantised position (base and morphed).
  double max_position_error = 0.0;
  /// Largest angle (degrees) between a unit normal and its dequantised direction.
  double max_normal_error_degrees = 0.0;
  /// Largest change of a skin weight.
  double max_weight_error = 0.0;
  /// Largest change of a texture coordinate.
  double max_texcoord_error = 0.0;
  /// Morph target accessors left float32 because a value was outside the normalised range.
  std::size_t float_target_accessors = 0;
  /// With compress as well: those of them encoded through the EXPONENTIAL filter (16-bit
  /// mantissa per element) and the largest change of a value it made.
  std::size_t filtered_target_accessors = 0;
  double max_filtered_target_error = 0.0;
  bool compressed = false;
  /// Bytes of the bufferViews given to meshoptimizer, before and after encoding.
  std::size_t bytes_before_compression = 0;
  std::size_t bytes_after_compression = 0;
};

/// Writes `asset` as .glb (binary) or .gltf (JSON with buffers and images as data URIs),
/// chosen by the extension of `path`, atomically (temporary file, then rename). Obeys the
/// Khronos validator's rules: exact accessor min/max for POSITION and animation inputs,
/// float32 weights summing to 1 within float rounding with joint 0 padding, inverse bind
/// matrices with last row (0, 0, 0, 1), image bytes passed through untouched.
/// `report`, if non-null, receives what quantize and compress did.
Status ExportGltf(const Asset& asset, const GltfExportOptions& options, const std::string& path,
                  GltfExportReport* report = nullptr);

/// As ExportGltf() but returns the bytes of a .glb (binary = true) or a .gltf.
Status SerializeGltf(const Asset& asset, const GltfExportOptions& options, bool binary,
                     std::string* bytes, GltfExportReport* report = nullptr);

}  // namespace dermis
