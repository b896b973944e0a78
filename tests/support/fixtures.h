// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: the fixtures written at build time by support/make_fixtures.cpp, read with the
// runtime's own .dsurf reader. Links dermis::runtime only.
#pragma once

#include <string>

#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"

namespace dermis::test {

/// The path of fixture `name` (e.g. "cylinders.dsurf") in the build tree.
std::string FixturePath(const std::string& name);

/// The bytes of a fixture (REQUIREs that it reads).
std::string FixtureBytes(const std::string& name);

/// The fitted two-capsule character (cylinders.dsurf), parsed once per test executable.
const Character& CylindersFixture();

/// The domain and rest positions of a built-in control mesh ("house", "prism7", "torus"),
/// without displacement.
DisplacedSurface SurfaceFixture(const std::string& builtin);

}  // namespace dermis::test
