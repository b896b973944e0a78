// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The importer registry (dermis/asset/importer.h).
#include "dermis/asset/importer.h"

#include "dermis/core/path.h"

namespace dermis {

Status Importer::ImportAsset(const std::string& path, ImportedAsset* /*out*/) const {
  return Status::Unsupported(path + ": the " + name() + " importer does not read assets");
}

Status Importer::ImportScan(const std::string& path, PolygonMesh* /*out*/) const {
  return Status::Unsupported(path + ": the " + name() + " importer does not read scans");
}

void ImporterRegistry::Add(std::unique_ptr<Importer> importer) {
  if (importer != nullptr) importers_.push_back(std::move(importer));
}

const Importer* ImporterRegistry::Find(const std::string& path, ImportKind kind) const {
  for (const auto& importer : importers_) {
    if (importer->Reads(kind) && importer->CanRead(path)) return importer.get();
  }
  return nullptr;
}

Status ImporterRegistry::NoImporter(const std::string& path, ImportKind kind) const {
  const char* what = kind == ImportKind::kAsset ? "assets" : "scans";
  const std::string ext = LowerExtension(path);
  std::string known;
  for (const auto& importer : importers_) {
    if (!importer->Reads(kind)) continue;
    known += (known.empty() ? "" : ", ") + importer->name();
    for (const std::string& e : importer->extensions()) known += " " + e;
  }
  return Status::Unsupported(
      path + ": no importer reads " +
      (ext.empty() ? std::string("files without an extension") : "'" + ext + "' files") + " as " +
      what + " (" + what + ": " + (known.empty() ? std::string("none registered") : known) + ")");
}

Status ImporterRegistry::ImportAsset(const std::string& path, ImportedAsset* out) const {
  const Importer* importer = Find(path, ImportKind::kAsset);
  if (importer == nullptr) return NoImporter(path, ImportKind::kAsset);
  return importer->ImportAsset(path, out);
}

Status ImporterRegistry::ImportScan(const std::string& path, PolygonMesh* out) const {
  const Importer* importer = Find(path, ImportKind::kScan);
  if (importer == nullptr) return NoImporter(path, ImportKind::kScan);
  return importer->ImportScan(path, out);
}

}  // namespace dermis
