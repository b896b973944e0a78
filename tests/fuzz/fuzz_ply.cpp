// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the PLY reader (ParsePly: ASCII and both binary byte orders), then the
// polygon-mesh checks (docs/reliability.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/io/ply_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  dermis::PolygonMesh mesh;
  if (dermis::ParsePly(bytes, "fuzz.ply", &mesh).ok() && mesh.num_faces() > 0) {
    (void)dermis::ValidatePolygonMesh(mesh);
  }
  return 0;
}
