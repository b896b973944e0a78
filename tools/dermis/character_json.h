// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// JSON descriptions shared by `dermis fit` (its report) and `dermis inspect` (.dsurf files and
// glTF files carrying one), so both say the same thing in the same units.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"

namespace dermis::cli {

using Json = nlohmann::ordered_json;

/// Control vertices, charts, faces and displacement levels of a surface.
Json DescribeSurface(const DisplacedSurface& surface);

/// Vertices bound, then per fitted part its mesh, component, skin, surface and fit errors
/// (model units, and percent of the part's largest bounding-box side), then the unfitted parts
/// with their reasons.
Json DescribeCharacter(const Character& ch);

}  // namespace dermis::cli
