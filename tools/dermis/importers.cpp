// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "importers.h"

#include "dermis/offline/io/scan_importers.h"
#include "dermis/plugins/plugins.h"

namespace dermis::cli {

const ImporterRegistry& Importers() {
  static const ImporterRegistry registry = [] {
    ImporterRegistry r;
    io::Register(&r);
    plugins::Register(&r);
    return r;
  }();
  return registry;
}

}  // namespace dermis::cli
