// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// OBJ and PLY as scan importers: thin adapters of obj_io.cpp and ply_io.cpp to the Importer
// interface, chosen by extension.
#include "dermis/offline/io/scan_importers.h"

#include "dermis/core/path.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"

namespace dermis::io {
namespace {

class ObjImporter final : public Importer {
 public:
  std::string name() const override { return "obj"; }
  std::vector<std::string> extensions() const override { return {".obj"}; }
  bool Reads(ImportKind kind) const override { return kind == ImportKind::kScan; }
  bool CanRead(const std::string& path) const override { return LowerExtension(path) == ".obj"; }
  Status ImportScan(const std::string& path, PolygonMesh* out) const override {
    return ReadObj(path, out, /*require_faces=*/false);
  }
};

class PlyImporter final : public Importer {
 public:
  std::string name() const override { return "ply"; }
  std::vector<std::string> extensions() const override { return {".ply"}; }
  bool Reads(ImportKind kind) const override { return kind == ImportKind::kScan; }
  bool CanRead(const std::string& path) const override { return LowerExtension(path) == ".ply"; }
  Status ImportScan(const std::string& path, PolygonMesh* out) const override {
    return ReadPly(path, out);
  }
};

}  // namespace

void Register(ImporterRegistry* registry) {
  registry->Add(std::make_unique<ObjImporter>());
  registry->Add(std::make_unique<PlyImporter>());
}

}  // namespace dermis::io
