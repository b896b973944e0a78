// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Lossless binary serialisation of an Asset, used inside character .dsurf files.
/// Layout (little-endian, versioned) in docs/asset-stream.md.
#pragma once

#include <string>
#include <string_view>

#include "dermis/asset/asset.h"
#include "dermis/core/status.h"

namespace dermis {

/// Current asset serialisation version.
constexpr std::uint32_t kAssetStreamVersion = 1;

/// Serialises every field of `asset` except `source`. The same asset always gives the same
/// bytes; ParseAsset(SerializeAsset(a)) == a field by field, floats bit for bit.
std::string SerializeAsset(const Asset& asset);

/// Parses bytes from SerializeAsset(). Counts are checked against the bytes present before
/// anything is allocated, then ValidateAsset() runs; errors name `name` and the part at fault.
/// Sets out->source = name. On failure `*out` is left unchanged.
Status ParseAsset(std::string_view bytes, const std::string& name, Asset* out);

}  // namespace dermis
