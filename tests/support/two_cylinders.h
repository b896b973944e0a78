// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Test support: a small skinned character, two capsules and a lone triangle on two joints, as a
// neutral asset (the asset module only; no Catch, so the fixture generator uses it too).
#pragma once

#include "dermis/asset/asset.h"

namespace dermis::test {

/// Appends a closed capsule to `prim` (which must have one JOINTS/WEIGHTS set and one TEXCOORD
/// set): a cylinder along y in [0, 2] with hemispherical caps, radius 0.5, whose side and caps
/// have their own vertices (split at the junctions, as UV seams do), skinned to joints 0 and 1
/// with smoothstep weights over y in [0.7, 1.3]. Placed at x0 along x.
void AddCylinder(double x0, AssetPrimitive* prim);

/// Two capsules (two components) and a lone triangle (too small to fit) in one mesh drawn by a
/// skinned node; skeleton root -> j0 (at the origin) -> j1 (at y = 1), both joints of the skin.
Asset TwoCylinders();

}  // namespace dermis::test
