// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
/// \file
/// \brief File importers and their registry: the one seam between file formats and the rest of
/// Dermis. Each format is an Importer; a tool or application fills an ImporterRegistry with
/// explicit calls (plugins::gltf::Register(&registry), plugins::assimp::Register(&registry),
/// io::Register(&registry) for OBJ and PLY), never through self-registering statics, and picks
/// the importer of a file by asking the registry. A new format: docs/overview.md.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dermis/asset/asset.h"
#include "dermis/asset/polygon_mesh.h"
#include "dermis/core/status.h"

namespace dermis {

/// What an importer makes of a file.
enum class ImportKind : std::uint8_t {
  /// A scene as an Asset: meshes, materials, images, nodes, skins, clips (glTF, FBX, ...).
  kAsset = 0,
  /// A dense mesh or point cloud as a PolygonMesh, every vertex exactly as written, in double
  /// precision, with the source line of each element for messages (OBJ, PLY): what
  /// `dermis fit` fits a single surface to.
  kScan = 1,
};

/// An imported asset and what the file carries besides it.
struct ImportedAsset {
  Asset asset;
  /// The bytes of a Dermis surface the file carries (a .dsurf of any version), so that fitting
  /// an export of Dermis gives back the surface it was made from; empty if there is none. glTF
  /// carries one in the DERMIS_displaced_surface extension (docs/file-format.md).
  std::string embedded_dsurf;
};

/// One file format. Implementations are stateless after construction: the registry calls them
/// from any thread.
class Importer {
 public:
  virtual ~Importer() = default;
  /// Short name for messages and tools: "gltf", "assimp", "obj", "ply".
  virtual std::string name() const = 0;
  /// The extensions it reads, lower case with the dot (".gltf", ".glb"), for messages; empty
  /// for an importer that recognises files by other means.
  virtual std::vector<std::string> extensions() const = 0;
  /// Whether it makes a `kind` of what it reads.
  virtual bool Reads(ImportKind kind) const = 0;
  /// Whether it takes `path` (decided from the name alone; the file is not opened).
  virtual bool CanRead(const std::string& path) const = 0;
  /// Imports an asset. Errors name the file (kIoError when it cannot be read). The default
  /// returns kUnsupported.
  virtual Status ImportAsset(const std::string& path, ImportedAsset* out) const;
  /// Imports a scan. Errors name the file and, where there is one, the line. The default
  /// returns kUnsupported.
  virtual Status ImportScan(const std::string& path, PolygonMesh* out) const;
};

/// The importers of a tool or application, in the order they were added: for a file, the
/// first one that reads the kind asked for and CanRead() it is used.
class ImporterRegistry {
 public:
  /// Adds `importer` after those already registered (an earlier one wins a shared extension).
  void Add(std::unique_ptr<Importer> importer);
  /// The importer of `path` for `kind`, or null if none takes it.
  const Importer* Find(const std::string& path, ImportKind kind) const;
  /// Find() and ImportAsset(). Without an importer: kUnsupported "PATH: no importer reads
  /// '.EXT' files as assets (assets: gltf .gltf .glb, ...)".
  Status ImportAsset(const std::string& path, ImportedAsset* out) const;
  /// Find() and ImportScan(); without an importer, kUnsupported as ImportAsset() says.
  Status ImportScan(const std::string& path, PolygonMesh* out) const;
  /// Every importer, in registration order.
  const std::vector<std::unique_ptr<Importer>>& importers() const { return importers_; }

 private:
  Status NoImporter(const std::string& path, ImportKind kind) const;
  std::vector<std::unique_ptr<Importer>> importers_;
};

}  // namespace dermis
