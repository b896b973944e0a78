// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: the two-capsule character (support/two_cylinders.h) fitted in the test
// process. Links dermis::offline_character.
#pragma once

#include "dermis/runtime/character.h"
#include "support/two_cylinders.h"

namespace dermis::test {

/// TwoCylinders() fitted once with the default character options (2 threads), shared by the
/// tests of one executable.
const Character& FittedCylinders();

}  // namespace dermis::test
