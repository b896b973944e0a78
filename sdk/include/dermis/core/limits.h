// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief The budgets every reader and command of the SDK enforces on untrusted input, in one
/// place (docs/reliability.md, "Limits"). A file past a limit is refused with a message that
/// names the file, the limit and how far it went, never read until memory or time runs out.
#pragma once

#include <cstdint>

namespace dermis::limits {

/// Largest input file any reader loads whole (bytes). Larger files are refused before reading.
constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{4} << 30;

/// Largest magnitude of an input coordinate. Products of coordinates (cross products, squared
/// distances, their products in normals and fits) must stay finite in double and in the float
/// outputs: |x| <= 1e12 keeps |x|^2 <= 1e24 (float max 3.4e38) and |x|^4 <= 1e48 (double).
constexpr double kMaxCoordinate = 1e12;

/// Deepest nesting of JSON arrays and objects a glTF document may have. Checked on the bytes
/// before any JSON library sees the document (tinygltf converts values recursively).
constexpr int kMaxJsonDepth = 64;

/// Deepest nesting of XML elements a file handed to Assimp may have (its Collada reader
/// recurses per node).
constexpr int kMaxXmlDepth = 256;

/// Most nodes of an imported scene, and the deepest parent chain (converters and poses walk the
/// hierarchy; no real skeleton comes near).
constexpr std::uint64_t kMaxNodes = std::uint64_t{1} << 20;
constexpr int kMaxNodeDepth = 1024;

/// Decoded-bytes budget of one import: every value an importer decodes (accessor values as
/// doubles, each time one is decoded) is counted; the total may not pass
/// kImportBudgetBaseBytes + kImportBudgetBytesPerFileByte * (file bytes + external buffer
/// bytes). A legitimate file decodes each value a few times at 8 bytes per value from at
/// least 1 byte in the file; a 200-byte file declaring a billion values does not.
constexpr std::uint64_t kImportBudgetBaseBytes = std::uint64_t{64} << 20;
constexpr std::uint64_t kImportBudgetBytesPerFileByte = 64;

/// Most baked vertex-frames (frames x posed vertices) one bake may produce: 2^25 morph-target
/// vertices (position and normal deltas, 24 bytes each) are 800 MB, and each frame is posed
/// (the tool warns from 2^24). The Khronos characters bake a few hundred thousand.
constexpr std::uint64_t kMaxBakedVertexFrames = std::uint64_t{1} << 25;

/// Most bytes one tessellation (vertices, normals, triangles) may take; the tool also refuses
/// more than half the machine's physical memory.
constexpr std::uint64_t kMaxTessellationBytes = std::uint64_t{8} << 30;

}  // namespace dermis::limits
