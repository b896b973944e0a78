// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
#include "support/characters.h"

#include <catch2/catch.hpp>

#include "dermis/offline/character/character_fit.h"

namespace dermis::test {

const Character& FittedCylinders() {
  static const Character ch = [] {
    Character c;
    CharacterFitOptions options;
    options.fit.threads = 2;
    REQUIRE(FitCharacter(TwoCylinders(), options, &c, nullptr).ok());
    return c;
  }();
  return ch;
}

}  // namespace dermis::test
