// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The Assimp plugin as an importer of assets (dermis/asset/importer.h): every file that is not
// glTF goes to ImportAssimp, which recognises formats by extension and by content (glTF is
// tinygltf's: Assimp 5.2 misreads normalised weights and quantised positions). Register it
// after the importers it must not shadow.
#include "dermis/core/path.h"
#include "dermis/plugins/assimp.h"

namespace dermis {
namespace {

class AssimpImporter final : public Importer {
 public:
  std::string name() const override { return "assimp"; }
  std::vector<std::string> extensions() const override { return {}; }
  bool Reads(ImportKind kind) const override { return kind == ImportKind::kAsset; }
  bool CanRead(const std::string& path) const override {
    const std::string ext = LowerExtension(path);
    return ext != ".gltf" && ext != ".glb";
  }
  Status ImportAsset(const std::string& path, ImportedAsset* out) const override {
    out->embedded_dsurf.clear();
    return ImportAssimp(path, &out->asset);
  }
};

}  // namespace

namespace plugins::assimp {

void Register(ImporterRegistry* registry) { registry->Add(std::make_unique<AssimpImporter>()); }

}  // namespace plugins::assimp
}  // namespace dermis
