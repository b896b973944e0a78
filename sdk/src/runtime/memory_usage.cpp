// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Memory a loaded runtime character holds (docs/engine-integration.md, "Memory"): the sum of
// the capacities of every array it owns, counted once, so an engine can budget with it.
#include <string>

#include "dermis/runtime/runtime.h"

namespace dermis {
namespace {

template <typename T>
std::size_t Bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

std::size_t Bytes(const std::string& s) { return s.capacity(); }

std::size_t AssetBytes(const Asset& a) {
  std::size_t n = Bytes(a.source) + Bytes(a.generator) + Bytes(a.copyright);
  n += Bytes(a.meshes) + Bytes(a.materials) + Bytes(a.textures) + Bytes(a.images) +
       Bytes(a.samplers) + Bytes(a.nodes) + Bytes(a.skins) + Bytes(a.animations) + Bytes(a.scenes);
  for (const AssetMesh& m : a.meshes) {
    n += Bytes(m.name) + Bytes(m.primitives) + Bytes(m.weights);
    for (const AssetPrimitive& p : m.primitives) {
      n += Bytes(p.positions) + Bytes(p.normals) + Bytes(p.tangents) + Bytes(p.indices) +
           Bytes(p.texcoords) + Bytes(p.colors) + Bytes(p.joints) + Bytes(p.weights) +
           Bytes(p.targets);
      for (const auto& t : p.texcoords) n += Bytes(t);
      for (const auto& c : p.colors) n += Bytes(c);
      for (const auto& j : p.joints) n += Bytes(j);
      for (const auto& w : p.weights) n += Bytes(w);
      for (const AssetMorphTarget& t : p.targets)
        n += Bytes(t.positions) + Bytes(t.normals) + Bytes(t.tangents);
    }
  }
  for (const AssetMaterial& m : a.materials) n += Bytes(m.name) + Bytes(m.json);
  for (const AssetTexture& t : a.textures) n += Bytes(t.name);
  for (const AssetImage& i : a.images) n += Bytes(i.name) + Bytes(i.mime_type) + Bytes(i.bytes);
  for (const AssetSampler& s : a.samplers) n += Bytes(s.name);
  for (const AssetNode& d : a.nodes) n += Bytes(d.name) + Bytes(d.children) + Bytes(d.weights);
  for (const AssetSkin& s : a.skins)
    n += Bytes(s.name) + Bytes(s.joints) + Bytes(s.inverse_bind_matrices);
  for (const AssetAnimation& an : a.animations) {
    n += Bytes(an.name) + Bytes(an.samplers) + Bytes(an.channels);
    for (const AssetAnimationSampler& s : an.samplers) n += Bytes(s.times) + Bytes(s.values);
  }
  for (const AssetScene& s : a.scenes) n += Bytes(s.name) + Bytes(s.nodes);
  return n;
}

std::size_t SurfaceBytes(const DisplacedSurface& s) {
  std::size_t n = Bytes(s.rest_positions);
  if (s.domain) n += s.domain->memory_bytes();
  if (s.displacement) n += s.displacement->memory_bytes();
  return n;
}

}  // namespace

std::size_t RuntimeCharacter::memory_bytes() const {
  const Character& c = character_;
  std::size_t n = sizeof(RuntimeCharacter) + AssetBytes(c.asset) + Bytes(c.parts) +
                  Bytes(c.bindings) + Bytes(c.unfitted);
  for (const CharacterPart& p : c.parts)
    n += SurfaceBytes(p.surface) + Bytes(p.control_joints) + Bytes(p.control_weights);
  for (const auto& mesh : c.bindings) {
    n += Bytes(mesh);
    for (const auto& prim : mesh) n += Bytes(prim);
  }
  for (const UnfittedPart& u : c.unfitted) n += Bytes(u.reason);
  n += Bytes(rigs_) + rig_ok_.capacity() / 8 + Bytes(bound_) + Bytes(locations_);
  for (const SkinRig& r : rigs_) {
    n += Bytes(r.parents) + Bytes(r.bind) + Bytes(r.names);
    for (const std::string& s : r.names) n += Bytes(s);
  }
  for (const auto& b : bound_) n += Bytes(b);
  for (const auto& l : locations_) n += Bytes(l);
  return n;
}

}  // namespace dermis
