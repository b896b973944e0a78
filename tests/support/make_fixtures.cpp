// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Writes the test fixtures that only the offline stages can make, so that the tests of the
// runtime-side modules (dsurf, runtime) read them as files and link no offline code:
//   cylinders.dsurf           the two-capsule test character, fitted (2 threads)
//   house.dsurf, prism7.dsurf, torus.dsurf   built-in control meshes' domains, no displacement
// Run by the build (tests/CMakeLists.txt) into the build tree: make_fixtures OUT_DIR.
#include <cstdio>
#include <string>

#include "dermis/core/file_io.h"
#include "dermis/dsurf/dsurf.h"
#include "dermis/offline/build/domain_builder.h"
#include "dermis/offline/character/character_fit.h"
#include "dermis/offline/geometry/builtin_meshes.h"
#include "support/two_cylinders.h"

namespace {

int Fail(const dermis::Status& s) {
  std::fprintf(stderr, "make_fixtures: %s\n", s.message().c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_fixtures OUT_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  dermis::Character ch;
  dermis::CharacterFitOptions options;
  options.fit.threads = 2;
  dermis::Status s = dermis::FitCharacter(dermis::test::TwoCylinders(), options, &ch, nullptr);
  if (s.ok()) s = dermis::WriteFileAtomically(dir + "/cylinders.dsurf", SerializeCharacter(ch));
  if (!s.ok()) return Fail(s);
  for (const char* name : {"house", "prism7", "torus"}) {
    dermis::PolygonMesh mesh;
    dermis::ControlSurface cs;
    s = dermis::MakeBuiltinMesh(name, &mesh);
    if (s.ok()) s = dermis::BuildControlSurface(mesh, dermis::DomainOptions{}, &cs);
    if (s.ok()) {
      s = dermis::WriteFileAtomically(
          dir + "/" + name + ".dsurf",
          dermis::SerializeDsurf(*cs.domain, cs.control.positions.data(), nullptr));
    }
    if (!s.ok()) return Fail(s);
  }
  return 0;
}
