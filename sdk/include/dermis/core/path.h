// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief File-name helpers shared by the readers, the importer registry and the tools.
#pragma once

#include <string>
#include <string_view>

namespace dermis {

/// `text` with ASCII letters lower-cased (other bytes unchanged; no locale involved).
std::string AsciiLower(std::string_view text);

/// The extension of the file name in `path`, lower-cased, with its dot: ".glb" for
/// "dir/Fox.GLB", "" when the file name (after the last '/' or '\\') has no dot. A file name
/// that is all extension counts as one (".obj" for "dir/.obj").
std::string LowerExtension(std::string_view path);

}  // namespace dermis
