// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// KHR_draco_mesh_compression decoding (private to the glTF plugin; docs/gltf-compression.md).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "dermis/core/status.h"

namespace dermis::gltf_draco {

/// What a glTF accessor wants from a decoded Draco attribute.
struct AttributeRequest {
  int unique_id = -1;      // the extension's "attributes" value
  int component_type = 0;  // glTF componentType of the accessor (5120..5126)
  int components = 0;      // 1..4
};

/// A decoded Draco primitive: per requested attribute, `count` elements packed at a 4-byte
/// aligned stride (`strides`); triangle indices as u32.
struct DecodedPrimitive {
  std::size_t count = 0;
  std::map<std::string, std::string> attributes;
  std::map<std::string, std::size_t> strides;
  std::vector<std::uint32_t> indices;
};

/// Decodes the Draco mesh in `bytes` and converts the requested attributes (by glTF
/// semantic) to their accessors' component types. kInvalidInput if Draco cannot decode it or
/// an attribute id is missing or has too few components.
Status DecodePrimitive(const std::string& bytes,
                       const std::map<std::string, AttributeRequest>& requests,
                       DecodedPrimitive* out);

}  // namespace dermis::gltf_draco
