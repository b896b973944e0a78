// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "dermis/plugins/plugins.h"

namespace dermis::plugins {

void Register(ImporterRegistry* registry) {
  gltf::Register(registry);
  assimp::Register(registry);
}

}  // namespace dermis::plugins
