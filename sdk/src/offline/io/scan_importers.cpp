// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// OBJ and PLY as scan importers: thin adapters of obj_io.cpp and ply_io.cpp to the Importer
// interface, chosen by extension.
#include "dermis/offline/io/scan_importers.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dermis/core/path.h"
#include "dermis/offline/io/obj_io.h"
#include "dermis/offline/io/ply_io.h"

namespace dermis::io {
namespace {

// A scan importer: one extension, one reader.
class ScanImporter final : public Importer {
 public:
  using Reader = Status (*)(const std::string& path, PolygonMesh* out);
  ScanImporter(std::string name, std::string extension, Reader read)
      : name_(std::move(name)), extension_(std::move(extension)), read_(read) {}
  std::string name() const override { return name_; }
  std::vector<std::string> extensions() const override { return {extension_}; }
  bool Reads(ImportKind kind) const override { return kind == ImportKind::kScan; }
  bool CanRead(const std::string& path) const override {
    return LowerExtension(path) == extension_;
  }
  Status ImportScan(const std::string& path, PolygonMesh* out) const override {
    return read_(path, out);
  }

 private:
  std::string name_, extension_;
  Reader read_;
};

Status ReadObjScan(const std::string& path, PolygonMesh* out) {
  return ReadObj(path, out, /*require_faces=*/false);
}

}  // namespace

void Register(ImporterRegistry* registry) {
  registry->Add(std::make_unique<ScanImporter>("obj", ".obj", ReadObjScan));
  registry->Add(std::make_unique<ScanImporter>("ply", ".ply", ReadPly));
}

}  // namespace dermis::io
