// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// ManifoldDomain::Create checks every operator offset it will dereference (issue 19, finding 1:
// offsets outside the operator array were accepted, then every consumer crashed), and the
// tessellation refuses sizes that cannot fit in memory before allocating (finding 3).
#include <catch2/catch.hpp>
#include <limits>
#include <string>

#include "dermis/surface/manifold_domain.h"
#include "dermis/surface/tessellation.h"
#include "support/domains.h"

using namespace dermis;

namespace {

// The cube's domain data with a second, unused operator block appended: offsets {0, 48, 96}.
DomainData CubeData() {
  const ControlSurface cs = test::Build(test::Builtin("cube"));
  DomainData d = cs.domain->data();
  REQUIRE(d.operator_offsets.size() == 2);
  REQUIRE(d.operator_offsets[1] == 48);  // valence 3, interior: 8 rows x 6 ring vertices
  d.operator_values.insert(d.operator_values.end(), d.operator_values.begin(),
                           d.operator_values.end());
  d.operator_offsets.push_back(96);
  return d;
}

std::string CreateError(DomainData d) {
  Status s;
  const auto domain = ManifoldDomain::Create(std::move(d), &s);
  CHECK(domain == nullptr);
  CHECK_FALSE(s.ok());
  return s.message();
}

}  // namespace

TEST_CASE("domain: operator offsets outside the operator values are refused") {
  {
    DomainData d = CubeData();
    Status s;
    REQUIRE(ManifoldDomain::Create(d, &s) != nullptr);
    for (Index& op : d.vertex_operator) op = 1;  // the appended block is as good
    REQUIRE(ManifoldDomain::Create(d, &s) != nullptr);
  }
  // What the fuzzer found: the used block has the right size (48) but starts outside the
  // values (past the end, negative), so only the first and last offsets were right.
  const std::vector<std::vector<Index>> bad = {
      {0, 500, 548, 96},   // past the end
      {0, -100, -52, 96},  // negative
      {0, 96, 144, 96},    // starts at the end
      {0, std::numeric_limits<Index>::max() - 10, std::numeric_limits<Index>::max(), 96},
      {0, std::numeric_limits<Index>::min(), std::numeric_limits<Index>::min() + 48, 96}};
  for (const std::vector<Index>& offsets : bad) {
    DomainData d = CubeData();
    d.operator_offsets = offsets;
    for (Index& op : d.vertex_operator) op = 1;
    const std::string message = CreateError(d);
    INFO(message);
    CHECK(message.find("operator offset") != std::string::npos);
    CHECK(message.find("outside the operator values (0..96)") != std::string::npos);
  }
  // A decreasing pair where the used block looks right.
  DomainData d = CubeData();
  d.operator_offsets = {0, 60, 12, 96};
  for (Index& op : d.vertex_operator) op = 2;
  CHECK(CreateError(d).find("outside the operator values") != std::string::npos);
}

TEST_CASE("tessellation: a pattern larger than memory allows is refused before allocating") {
  const ControlSurface cs = test::Build(test::Builtin("cube"));
  TessellationPattern p;
  // 6 faces at level 4096: 1e8 samples, about 9 GiB with what is evaluated into them.
  const Status s = TessellationPattern::Build(cs.domain->topology(), 4096, &p);
  INFO(s.message());
  REQUIRE_FALSE(s.ok());
  CHECK(s.message().find("MiB") != std::string::npos);
  CHECK(s.message().find("lower --level") != std::string::npos);
  CHECK(p.samples.empty());
  REQUIRE(TessellationPattern::Build(cs.domain->topology(), 64, &p).ok());
  CHECK(p.samples.size() == 8 + 12 * 63 + 6 * 63 * 63);
}
