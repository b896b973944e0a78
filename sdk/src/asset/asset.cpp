// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/asset/asset.h"

#include <algorithm>

namespace dermis {

double AssetAnimation::Duration() const {
  double duration = 0.0;
  for (const AssetAnimationSampler& sampler : samplers) {
    if (!sampler.times.empty()) duration = std::max(duration, double(sampler.times.back()));
  }
  return duration;
}

}  // namespace dermis
