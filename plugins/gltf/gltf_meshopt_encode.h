// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// EXT_meshopt_compression for the glTF exporter (private to the plugin): a GLB rewritten with
// its vertex, index and animation bufferViews encoded by meshoptimizer
// (docs/gltf-compression.md, "Compression").
#pragma once

#include <cstddef>
#include <string>

#include "dermis/core/status.h"

namespace dermis::gltf_meshopt {

/// What CompressGlb() did.
struct CompressStats {
  /// Bytes of the encoded views before and after encoding.
  std::size_t before = 0;
  std::size_t after = 0;
  /// Float morph target NORMAL / TANGENT views given the EXPONENTIAL filter, and the largest
  /// change of a value it made.
  std::size_t filtered_views = 0;
  double max_filter_error = 0.0;
};

/// Rewrites the GLB `glb` (as tinygltf wrote it: one buffer, the BIN chunk) with
/// EXT_meshopt_compression: every bufferView read by exactly one accessor at offset 0 whose
/// elements are a multiple of 4 bytes (ATTRIBUTES) or whose target is the index buffer
/// (TRIANGLES for triangle lists, INDICES otherwise) is encoded into buffer 0; the view itself
/// points into buffer 1, the fallback buffer, which has a byteLength and no data. The
/// extension is added to extensionsUsed and extensionsRequired. With `exp_filter_bits` > 0,
/// float32 morph target NORMAL and TANGENT deltas (those quantisation left float32) go through
/// the extension's EXPONENTIAL filter with that many mantissa bits (lossy). Output: a GLB, or
/// with `binary` false a .gltf whose buffer 0 is a base64 data URI.
Status CompressGlb(const std::string& glb, bool binary, int exp_filter_bits, std::string* out,
                   CompressStats* stats);

}  // namespace dermis::gltf_meshopt
