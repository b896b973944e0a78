// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The glTF plugin as an importer of assets (dermis/asset/importer.h): ImportGltf behind the
// Importer interface, chosen by extension.
#include "dermis/core/path.h"
#include "dermis/plugins/gltf.h"

namespace dermis {
namespace {

class GltfImporter final : public Importer {
 public:
  std::string name() const override { return "gltf"; }
  std::vector<std::string> extensions() const override { return {".gltf", ".glb"}; }
  bool Reads(ImportKind kind) const override { return kind == ImportKind::kAsset; }
  bool CanRead(const std::string& path) const override { return IsGltfPath(path); }
  Status ImportAsset(const std::string& path, ImportedAsset* out) const override {
    return ImportGltf(path, &out->asset, &out->embedded_dsurf);
  }
};

}  // namespace

bool IsGltfPath(const std::string& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".gltf" || ext == ".glb";
}

namespace plugins::gltf {

void Register(ImporterRegistry* registry) { registry->Add(std::make_unique<GltfImporter>()); }

}  // namespace plugins::gltf
}  // namespace dermis
