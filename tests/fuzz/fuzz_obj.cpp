// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// libFuzzer harness: the OBJ reader (ParseObj), then the polygon-mesh checks every command runs
// on a control mesh (docs/reliability.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "dermis/offline/geometry/polygon_mesh.h"
#include "dermis/offline/io/obj_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  dermis::PolygonMesh mesh;
  if (dermis::ParseObj(text, "fuzz.obj", &mesh, false).ok() && mesh.num_faces() > 0) {
    (void)dermis::ValidatePolygonMesh(mesh);
  }
  return 0;
}
