// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Built with nothing but `pkg-config --cflags --libs dermis-runtime` (runtime, deform, core and
// the GLM headers): deforms one point by LBS.
#include <cstdio>
#include <memory>
#include <vector>

#include "dermis/deform/deformer.h"

int main() {
  dermis::SkinRig rig;
  rig.parents = {-1};
  rig.bind = {glm::dmat4(1.0)};
  std::vector<dermis::Vec3> rest = {{1.0, 0.0, 0.0}};
  std::vector<dermis::VertexWeights> weights(1);
  weights[0].weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
  std::unique_ptr<dermis::Deformer> d;
  if (!dermis::MakeDeformer(dermis::DeformerKind::kDqs, rig, rest.data(), nullptr, weights.data(),
                            1, &d)
           .ok()) {
    return 1;
  }
  glm::dmat4 moved(1.0);
  moved[3] = glm::dvec4(0.0, 1.0, 0.0, 1.0);
  if (!d->SetPose(&moved).ok()) return 1;
  dermis::Vec3 x;
  d->Deform(0, 1, &x, nullptr);
  if (x != dermis::Vec3(1.0, 1.0, 0.0)) return 1;
  std::printf("runtime-only ok\n");
  return 0;
}
