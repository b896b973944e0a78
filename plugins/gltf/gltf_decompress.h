// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Import of compressed glTF (private to the plugin): a document that uses
// EXT_meshopt_compression or KHR_draco_mesh_compression rewritten as a plain GLB in memory,
// which the importer then reads as any other (docs/gltf-compression.md, "Import").
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "dermis/core/status.h"

namespace dermis::gltf_decompress {

/// True if `doc` lists EXT_meshopt_compression or KHR_draco_mesh_compression in
/// extensionsUsed.
bool UsesCompression(const nlohmann::json& doc);

/// Decodes every EXT_meshopt_compression bufferView (meshoptimizer's decoder, with its
/// OCTAHEDRAL / QUATERNION / EXPONENTIAL filters) and every KHR_draco_mesh_compression
/// primitive (Draco's decoder; attributes and indices become plain accessors), and gathers
/// every buffer (the GLB's `bin`, data URIs, files under `base_dir`) into the one BIN chunk
/// of the GLB written to `glb`; the two extensions leave extensionsUsed/Required. Images keep
/// their URIs (relative to `base_dir`). Errors (kInvalidInput, kIoError) start with a JSON
/// pointer, e.g. "/bufferViews/3: meshopt data does not decode".
Status Decompress(const nlohmann::json& doc, const std::string& bin, const std::string& base_dir,
                  std::string* glb);

}  // namespace dermis::gltf_decompress
