// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the lossless asset byte stream (ParseAsset) and the asset checks
// (ValidateAsset) (docs/reliability.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "dermis/asset/asset_io.h"
#include "dermis/asset/asset_validate.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  dermis::Asset asset;
  if (dermis::ParseAsset(bytes, "fuzz.asset", &asset).ok()) (void)dermis::ValidateAsset(asset);
  return 0;
}
