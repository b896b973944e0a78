// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief Basic vector types shared by every Dermis module.
#pragma once

#include <cstdint>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace dermis {

/// A 3-D point or vector in double precision (model units).
using Vec3 = glm::dvec3;
/// A 2-D point: face coordinates (u, v) in [0,1]^2 or chart coordinates (x, y).
using Vec2 = glm::dvec2;

/// Index type used for vertices, faces and half-edges. -1 means "none".
using Index = std::int32_t;
constexpr Index kInvalidIndex = -1;

}  // namespace dermis
