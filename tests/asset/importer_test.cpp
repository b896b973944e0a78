// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The importer registry (dermis/asset/importer.h) with importers written here: the order of
// registration decides, the kind asked for filters, messages list what is registered.
#include "dermis/asset/importer.h"

#include <catch2/catch.hpp>
#include <memory>
#include <string>
#include <vector>

#include "dermis/core/path.h"

using namespace dermis;

namespace {

// Reads `ext` files as `kind`; records what it imported in the asset's or mesh's source name.
class FakeImporter final : public Importer {
 public:
  FakeImporter(std::string name, std::string ext, ImportKind kind)
      : name_(std::move(name)), ext_(std::move(ext)), kind_(kind) {}
  std::string name() const override { return name_; }
  std::vector<std::string> extensions() const override { return {ext_}; }
  bool Reads(ImportKind kind) const override { return kind == kind_; }
  bool CanRead(const std::string& path) const override { return LowerExtension(path) == ext_; }
  Status ImportAsset(const std::string& path, ImportedAsset* out) const override {
    if (kind_ != ImportKind::kAsset) return Importer::ImportAsset(path, out);
    out->asset.source = name_ + ":" + path;
    out->embedded_dsurf = "bytes of " + name_;
    return Status::Ok();
  }
  Status ImportScan(const std::string& path, PolygonMesh* out) const override {
    if (kind_ != ImportKind::kScan) return Importer::ImportScan(path, out);
    out->source_name = name_ + ":" + path;
    return Status::Ok();
  }

 private:
  std::string name_, ext_;
  ImportKind kind_;
};

ImporterRegistry Registry() {
  ImporterRegistry r;
  r.Add(std::make_unique<FakeImporter>("pts", ".xyz", ImportKind::kScan));
  r.Add(std::make_unique<FakeImporter>("scene", ".scn", ImportKind::kAsset));
  r.Add(std::make_unique<FakeImporter>("mesh", ".xyz", ImportKind::kAsset));
  r.Add(std::make_unique<FakeImporter>("late", ".scn", ImportKind::kAsset));
  return r;
}

}  // namespace

TEST_CASE("importers: the first registered importer of the kind asked for wins") {
  const ImporterRegistry r = Registry();
  REQUIRE(r.importers().size() == 4);
  REQUIRE(r.Find("a/b.SCN", ImportKind::kAsset) != nullptr);
  CHECK(r.Find("a/b.SCN", ImportKind::kAsset)->name() == "scene");  // not "late"
  CHECK(r.Find("b.scn", ImportKind::kScan) == nullptr);
  CHECK(r.Find("c.xyz", ImportKind::kScan)->name() == "pts");
  CHECK(r.Find("c.xyz", ImportKind::kAsset)->name() == "mesh");
  CHECK(r.Find("c.obj", ImportKind::kAsset) == nullptr);

  ImportedAsset asset;
  REQUIRE(r.ImportAsset("c.xyz", &asset).ok());
  CHECK(asset.asset.source == "mesh:c.xyz");
  CHECK(asset.embedded_dsurf == "bytes of mesh");
  PolygonMesh scan;
  REQUIRE(r.ImportScan("c.xyz", &scan).ok());
  CHECK(scan.source_name == "pts:c.xyz");
}

TEST_CASE("importers: a file no importer takes is refused with what is registered") {
  const ImporterRegistry r = Registry();
  ImportedAsset asset;
  Status s = r.ImportAsset("dir/model.FBX", &asset);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message() ==
        "dir/model.FBX: no importer reads '.fbx' files as assets (assets: scene .scn, mesh .xyz, "
        "late .scn)");
  PolygonMesh scan;
  s = r.ImportScan("dir.d/noext", &scan);
  CHECK(s.message() ==
        "dir.d/noext: no importer reads files without an extension as scans (scans: pts .xyz)");
  const ImporterRegistry empty;
  CHECK(empty.ImportScan("a.obj", &scan).message() ==
        "a.obj: no importer reads '.obj' files as scans (scans: none registered)");
  CHECK(empty.Find("a.obj", ImportKind::kScan) == nullptr);
}

TEST_CASE("importers: the default import of a kind an importer does not read") {
  const FakeImporter scans("pts", ".xyz", ImportKind::kScan);
  ImportedAsset asset;
  const Status s = scans.ImportAsset("p.xyz", &asset);
  CHECK(s.code() == StatusCode::kUnsupported);
  CHECK(s.message() == "p.xyz: the pts importer does not read assets");
  const FakeImporter assets("scene", ".scn", ImportKind::kAsset);
  PolygonMesh scan;
  CHECK(assets.ImportScan("s.scn", &scan).message() ==
        "s.scn: the scene importer does not read scans");
}
