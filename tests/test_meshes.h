// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// All the test support of the offline and plugin tests: meshes, domains, the test character.
// Tests of core, surface, dsurf and runtime include only the parts they link (support/*.h).
#pragma once

#include "support/characters.h"
#include "support/domains.h"
#include "support/meshes.h"
