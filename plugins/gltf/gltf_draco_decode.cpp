// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// KHR_draco_mesh_compression: a primitive's Draco bitstream decoded with Debian's libdraco
// (draco::Decoder) into per-attribute arrays in the accessors' component types and u32
// triangle indices (docs/gltf-compression.md, "Import").
#include "gltf_draco_decode.h"

#include <draco/compression/decode.h>

#include <cstdint>
#include <cstring>
#include <memory>

namespace dermis::gltf_draco {
namespace {

std::size_t ComponentBytes(int type) {
  switch (type) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    default:
      return 4;
  }
}

template <typename T>
bool Convert(const draco::PointAttribute& att, std::size_t points, int components,
             std::size_t stride, std::string* out) {
  out->assign(points * stride, '\0');
  T value[4] = {};
  for (std::size_t p = 0; p < points; ++p) {
    const draco::AttributeValueIndex index =
        att.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(p)));
    if (!att.ConvertValue<T>(index, static_cast<std::int8_t>(components), value)) return false;
    std::memcpy(&(*out)[p * stride], value, sizeof(T) * static_cast<std::size_t>(components));
  }
  return true;
}

}  // namespace

Status DecodePrimitive(const std::string& bytes,
                       const std::map<std::string, AttributeRequest>& requests,
                       DecodedPrimitive* out) {
  draco::DecoderBuffer buffer;
  buffer.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) {
    return Status::InvalidInput("Draco cannot decode the mesh: " +
                                decoded.status().error_msg_string());
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  if (mesh == nullptr) return Status::InvalidInput("Draco decoded no mesh");
  out->count = mesh->num_points();
  out->indices.resize(3 * static_cast<std::size_t>(mesh->num_faces()));
  for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
    const draco::Mesh::Face& face = mesh->face(f);
    for (int k = 0; k < 3; ++k) {
      out->indices[3 * f.value() + static_cast<std::size_t>(k)] = face[k].value();
    }
  }
  for (const auto& [name, request] : requests) {
    const draco::PointAttribute* att =
        mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(request.unique_id));
    if (att == nullptr || request.unique_id < 0) {
      return Status::InvalidInput("attribute " + name + ": Draco id " +
                                  std::to_string(request.unique_id) + " is not in the mesh");
    }
    if (request.components < 1 || request.components > 4 ||
        att->num_components() < request.components) {
      return Status::InvalidInput(
          "attribute " + name + ": Draco has " + std::to_string(int{att->num_components()}) +
          " components, the accessor wants " + std::to_string(request.components));
    }
    const std::size_t element =
        ComponentBytes(request.component_type) * static_cast<std::size_t>(request.components);
    const std::size_t stride = (element + 3) / 4 * 4;
    std::string data;
    bool ok;
    switch (request.component_type) {
      case 5120:
        ok = Convert<std::int8_t>(*att, out->count, request.components, stride, &data);
        break;
      case 5121:
        ok = Convert<std::uint8_t>(*att, out->count, request.components, stride, &data);
        break;
      case 5122:
        ok = Convert<std::int16_t>(*att, out->count, request.components, stride, &data);
        break;
      case 5123:
        ok = Convert<std::uint16_t>(*att, out->count, request.components, stride, &data);
        break;
      case 5125:
        ok = Convert<std::uint32_t>(*att, out->count, request.components, stride, &data);
        break;
      case 5126:
        ok = Convert<float>(*att, out->count, request.components, stride, &data);
        break;
      default:
        return Status::InvalidInput("attribute " + name + ": component type " +
                                    std::to_string(request.component_type) + " is not glTF's");
    }
    if (!ok) return Status::InvalidInput("attribute " + name + ": Draco cannot convert it");
    out->attributes[name] = std::move(data);
    out->strides[name] = stride;
  }
  return Status::Ok();
}

}  // namespace dermis::gltf_draco
