// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Disjoint sets over 0..n-1 (private to the offline build library): path halving, and every
// set's representative its smallest element, so the classes and their representatives do not
// depend on the order of the unions.
#pragma once

#include <algorithm>
#include <numeric>
#include <vector>

#include "dermis/core/types.h"

namespace dermis {

class UnionFind {
 public:
  explicit UnionFind(Index n) : parent_(static_cast<std::size_t>(n)) {
    std::iota(parent_.begin(), parent_.end(), Index{0});
  }
  /// The smallest element of x's set.
  Index Find(Index x) {
    while (parent_[static_cast<std::size_t>(x)] != x) {
      parent_[static_cast<std::size_t>(x)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(x)])];
      x = parent_[static_cast<std::size_t>(x)];
    }
    return x;
  }
  void Unite(Index a, Index b) {
    a = Find(a), b = Find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace dermis
