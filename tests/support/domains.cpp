// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/domains.h"

#include <catch2/catch.hpp>

namespace dermis::test {

ControlSurface Build(const PolygonMesh& mesh, const DomainOptions& options) {
  ControlSurface cs;
  const Status s = BuildControlSurface(mesh, options, &cs);
  INFO(s.message());
  REQUIRE(s.ok());
  return cs;
}

}  // namespace dermis::test
