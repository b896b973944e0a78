// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: manifold domains built from polygon meshes (the build stage makes them, as only
// it can), and a smooth displacement per chart. Links dermis::offline_build.
#pragma once

#include <cmath>

#include "dermis/offline/build/domain_builder.h"
#include "support/meshes.h"
#include "support/wavy_displacement.h"

namespace dermis::test {

/// Builds the control surface, failing the test on error.
ControlSurface Build(const PolygonMesh& mesh, const DomainOptions& options = DomainOptions{});

}  // namespace dermis::test
