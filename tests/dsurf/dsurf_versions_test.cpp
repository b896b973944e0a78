// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The .dsurf reader and writer (docs/file-format.md): a version-1 file written here byte by
// byte from the documented layout still loads and writes back identically; version 3 (sparse
// per-level corrections) round trips bit-exactly; damaged version-3 files fail with a message
// naming the file.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <string>

#include "dermis/dsurf/dsurf.h"
#include "dermis/runtime/character.h"
#include "support/fixtures.h"

namespace dermis {
namespace {

// Little-endian writing and FNV-1a 64, written here from docs/file-format.md (not the SDK's).
struct Bytes {
  std::string s;
  void Put(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void F64(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, 8);
    Put(b, 8);
  }
  void F32(float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    Put(b, 4);
  }
};

std::uint64_t Fnv(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (char c : s) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  return h;
}

// Deterministic uniform numbers in [0, 1).
class Lcg {
 public:
  explicit Lcg(std::uint64_t seed) : state_(seed * 2862933555777941757ULL + 3037000493ULL) {}
  double Next() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) * (1.0 / 9007199254740992.0);
  }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Next(); }

 private:
  std::uint64_t state_;
};

// A domain and its control positions: the test character's first fitted capsule.
struct TestSurface {
  const ManifoldDomain& domain;
  const std::vector<Vec3>& positions;
};

TestSurface FittedDomain() {
  const CharacterPart& part = test::CylindersFixture().parts[0];
  return {*part.surface.domain, part.surface.rest_positions};
}

// Recomputes the checksum of a file whose body was edited.
void Reseal(std::string* file) {
  file->resize(file->size() - 8);
  Bytes b;
  b.Put(Fnv(*file), 8);
  *file += b.s;
}

// Value of a dense lattice of `level` at z, by the B-spline sum over all its nodes.
double DenseLattice(const float* lattice, int level, double half, Vec2 z) {
  auto basis = [](double t) {  // B centred on 0, support (-2, 2)
    t = std::abs(t);
    if (t >= 2.0) return 0.0;
    if (t >= 1.0) return (2.0 - t) * (2.0 - t) * (2.0 - t) / 6.0;
    return (4.0 - 6.0 * t * t + 3.0 * t * t * t) / 6.0;
  };
  const int m = 1 << level, stride = m + 3;
  const double x = (z.x + half) * m / (2.0 * half), y = (z.y + half) * m / (2.0 * half);
  double f = 0.0;
  for (int j = -1; j <= m + 1; ++j) {
    for (int i = -1; i <= m + 1; ++i) {
      f += lattice[(j + 1) * stride + i + 1] * basis(x - i) * basis(y - j);
    }
  }
  return f;
}

}  // namespace

TEST_CASE("dsurf: a version-1 file of merged lattices still loads and writes back identically",
          "[dsurf]") {
  const TestSurface cs = FittedDomain();
  const DomainData& d = cs.domain.data();
  const MeshTopology& topo = d.topology;
  const auto nv = static_cast<std::uint32_t>(topo.num_vertices());
  // Two merged levels per chart (16 + 25 coefficients), chart 3 without levels.
  Lcg rng(4);
  std::vector<std::vector<float>> lattices(nv);
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (v == 3) continue;
    for (int n = 0; n < 16 + 25; ++n)
      lattices[v].push_back(static_cast<float>(rng.Uniform(-0.1, 0.1)));
  }
  Bytes b;
  b.s = std::string("DSURF\r\n\x1a", 8);
  b.Put(1, 4);  // version
  b.Put(0, 4);  // flags
  b.Put(static_cast<std::uint64_t>(d.options.chart_type), 1);
  b.Put(static_cast<std::uint64_t>(d.options.blend_type), 1);
  b.F64(d.options.blend_lb);
  b.Put(nv, 4);
  b.Put(static_cast<std::uint64_t>(topo.num_faces()), 4);
  for (const Vec3& p : cs.positions) b.F64(p.x), b.F64(p.y), b.F64(p.z);
  for (Index f = 0; f < topo.num_faces(); ++f) {
    for (int k = 0; k < 4; ++k) b.Put(static_cast<std::uint32_t>(topo.face_vertex(f, k)), 4);
  }
  for (VertexKind k : d.vertex_kind) b.Put(static_cast<std::uint64_t>(k), 1);
  b.Put(d.operator_offsets.size() - 1, 4);
  for (Index o : d.operator_offsets) b.Put(static_cast<std::uint32_t>(o), 4);
  for (double x : d.operator_values) b.F64(x);
  for (Index o : d.vertex_operator) b.Put(static_cast<std::uint32_t>(o), 4);
  b.Put(1, 1);  // has displacement
  for (std::uint32_t v = 0; v < nv; ++v) b.F64(1.25);
  for (std::uint32_t v = 0; v < nv; ++v) b.Put(v == 3 ? 0 : 2, 1);
  std::uint64_t offset = 0;
  b.Put(0, 8);
  for (std::uint32_t v = 0; v < nv; ++v) {
    offset += lattices[v].size();
    b.Put(offset, 8);
  }
  for (std::uint32_t v = 0; v < nv; ++v)
    for (float x : lattices[v]) b.F32(x);
  b.Put(Fnv(b.s), 8);

  DisplacedSurface s;
  const Status st = ParseDsurf(b.s, "old.dsurf", &s);
  INFO(st.message());
  REQUIRE(st.ok());
  REQUIRE(s.displacement);
  CHECK(s.displacement->data().form == BsplineLevelForm::kMerged);
  CHECK(s.data_points == 0);
  CHECK(s.displacement->num_coefficients() == 41 * (nv - 1));
  // One level reads lattice 0, two levels read the merged lattice 1.
  for (int n = 0; n < 40; ++n) {
    const Vec2 z(rng.Uniform(-1.2, 1.2), rng.Uniform(-1.2, 1.2));
    for (std::uint32_t v = 0; v < nv; ++v) {
      double value = 0.0;
      Vec2 g;
      s.displacement->EvaluateLevels(static_cast<Index>(v), z, 1, &value, &g);
      CHECK(value ==
            Approx(v == 3 ? 0.0 : DenseLattice(lattices[v].data(), 0, 1.25, z)).margin(1e-12));
      s.displacement->Evaluate(static_cast<Index>(v), z, &value, &g);
      CHECK(value ==
            Approx(v == 3 ? 0.0 : DenseLattice(lattices[v].data() + 16, 1, 1.25, z)).margin(1e-12));
    }
  }
  // Written back: version 1, the same bytes.
  CHECK(SerializeDsurf(*s.domain, s.rest_positions.data(), s.displacement.get()) == b.s);
  // Packed as a runtime archive (version 4): the merged form and its coefficients kept, exactly
  // in f32, within the quantisation tolerance (2e-6 of the control mesh's diagonal) in 16 bits.
  Character ch;
  REQUIRE(ParseCharacter(b.s, "old.dsurf", &ch).ok());
  Vec3 lo(1e300), hi(-1e300);
  for (const Vec3& p : s.rest_positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  for (const bool quantize : {false, true}) {
    RuntimeArchiveOptions options;
    options.quantize_displacements = quantize;
    Character packed;
    const Status ps =
        ParseCharacter(SerializeRuntimeArchive(ch, options), "old.runtime.dsurf", &packed);
    INFO(ps.message());
    REQUIRE(ps.ok());
    const BsplineDisplacementData& in = s.displacement->data();
    const BsplineDisplacementData& out = packed.parts[0].surface.displacement->data();
    CHECK(out.form == BsplineLevelForm::kMerged);
    CHECK(out.num_levels == in.num_levels);
    CHECK(out.offsets == in.offsets);
    REQUIRE(out.values.size() == in.values.size());
    for (std::size_t i = 0; i < in.values.size(); ++i) {
      CHECK(std::abs(out.values[i] - in.values[i]) <=
            (quantize ? 2e-6 * glm::length(hi - lo) * 1.01 : 0.0));
    }
  }
}

TEST_CASE("dsurf: version 3 stores sparse levels and round trips bit-exactly", "[dsurf]") {
  const TestSurface cs = FittedDomain();
  const Index nv = cs.domain.num_vertices();
  Lcg rng(8);
  BsplineDisplacementData d;
  d.form = BsplineLevelForm::kAdditive;
  d.offsets.push_back(0);
  for (Index v = 0; v < nv; ++v) {
    d.half_extent.push_back(1.0 + 0.01 * v);
    const int levels = v % 4;  // 0 .. 3 levels, level 0 dense, finer ones sparse
    d.num_levels.push_back(static_cast<std::uint8_t>(levels));
    for (int k = 0; k < levels; ++k) {
      std::int32_t count = 0;
      for (std::int64_t n = 0; n < BsplineLatticeSize(k); ++n) {
        if (k > 0 && rng.Next() < 0.6) continue;
        if (k > 0) d.nodes.push_back(static_cast<std::uint32_t>(n));
        d.values.push_back(static_cast<float>(rng.Uniform(-0.05, 0.05)));
        ++count;
      }
      d.level_counts.push_back(count);
    }
    d.offsets.push_back(static_cast<std::int64_t>(d.values.size()));
  }
  Status st;
  auto disp = BsplineDisplacement::Create(d, nv, &st);
  INFO(st.message());
  REQUIRE(disp);
  const std::string bytes = SerializeDsurf(cs.domain, cs.positions.data(), disp.get(), 12345);
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + 8, 4);
  CHECK(version == 3);
  DisplacedSurface s;
  REQUIRE(ParseDsurf(bytes, "sparse.dsurf", &s).ok());
  CHECK(s.data_points == 12345);
  REQUIRE(s.displacement);
  const BsplineDisplacementData& e = s.displacement->data();
  CHECK(e.form == BsplineLevelForm::kAdditive);
  CHECK(e.level_counts == d.level_counts);
  CHECK(e.nodes == d.nodes);
  CHECK(e.values == d.values);
  CHECK(e.offsets == d.offsets);
  CHECK(SerializeDsurf(*s.domain, s.rest_positions.data(), s.displacement.get(), s.data_points) ==
        bytes);

  SECTION("every truncation and corruption fails cleanly, naming the file") {
    for (std::size_t n = 0; n < bytes.size(); n += 13) {
      DisplacedSurface t;
      const Status r = ParseDsurf(bytes.substr(0, n), "cut.dsurf", &t);
      CHECK_FALSE(r.ok());
      CHECK(r.message().find("cut.dsurf") != std::string::npos);
    }
    std::string flipped = bytes;
    flipped[bytes.size() / 2] ^= 0x10;
    DisplacedSurface t;
    CHECK_FALSE(ParseDsurf(flipped, "flipped.dsurf", &t).ok());
    // Edits with a valid checksum reach the parser: a node run past the lattice, a level
    // count above its lattice size. The coefficients are the last f32s before the data points
    // and the checksum; the node runs sit just before them.
    const std::size_t coefficients =
        bytes.size() - 8 - 8 - 4 * d.values.size();  // start of the coefficients
    std::string bad = bytes;
    bad[coefficients - 2] = static_cast<char>(0x7f);  // last run's gap: far past the lattice
    Reseal(&bad);
    const Status r = ParseDsurf(bad, "runs.dsurf", &t);
    CHECK_FALSE(r.ok());
    CHECK(r.message().find("runs.dsurf") != std::string::npos);
  }
}

TEST_CASE("dsurf: versions are dispatched by kind", "[dsurf]") {
  CHECK(IsSurfaceDsurfVersion(1));
  CHECK(IsSurfaceDsurfVersion(3));
  CHECK_FALSE(IsSurfaceDsurfVersion(2));  // a character
  CHECK_FALSE(IsSurfaceDsurfVersion(4));
  const TestSurface cs = FittedDomain();
  std::string bytes = SerializeDsurf(cs.domain, cs.positions.data(), nullptr);
  bytes[8] = 9;  // version 9
  Reseal(&bytes);
  DisplacedSurface s;
  const Status r = ParseDsurf(bytes, "future.dsurf", &s);
  CHECK(r.code() == StatusCode::kUnsupported);
  CHECK(r.message().find("version 9") != std::string::npos);
}

}  // namespace dermis
