// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The GLB container for the compression passes of the glTF plugin (private): split into the
// JSON and BIN chunks, joined back, and base64 for data URIs.
#pragma once

#include <string>

#include "dermis/core/status.h"

namespace dermis::gltf_glb {

/// The JSON text and the BIN chunk (empty if none) of a GLB; kInvalidInput if malformed.
Status Split(const std::string& glb, std::string* json, std::string* bin);
/// A GLB of `json` (padded with spaces) and `bin` (padded with zeros; no chunk if empty).
std::string Join(const std::string& json, const std::string& bin);
/// Standard base64 with padding.
std::string Base64(const std::string& bytes);
/// Decodes standard base64 (padding optional); false on a character outside the alphabet.
bool DecodeBase64(const std::string& text, std::string* bytes);

}  // namespace dermis::gltf_glb
