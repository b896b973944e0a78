// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The level structure of sparse displacement lattices (docs/file-format.md, version 3 and the
// runtime archive): half extents, level counts, each level's coefficient count, the node runs
// of the sparse levels as varints. Shared by the version-3 surface body (dsurf.cpp) and the
// runtime archive (runtime_archive.cpp), which differ only in how the coefficients follow.
#include "dsurf/dsurf_container.h"

namespace dermis {
namespace dsurf {

void WriteVarint(std::uint32_t v, ByteWriter* w) {
  while (v >= 0x80) {
    w->U8(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  w->U8(static_cast<std::uint8_t>(v));
}

std::uint32_t ReadVarint(ByteReader* r, const char* what) {
  std::uint64_t v = 0;
  for (int shift = 0; shift < 35; shift += 7) {
    const std::uint8_t b = r->U8(what);
    if (!r->ok()) return 0;
    v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) {
      if (v > 0xffffffffull) break;
      return static_cast<std::uint32_t>(v);
    }
  }
  r->Fail(std::string("malformed ") + what);
  return 0;
}

void WriteSparseStructure(const BsplineDisplacementData& b, bool compact, ByteWriter* w) {
  for (double r : b.half_extent) {
    if (compact) {
      w->F32(static_cast<float>(r));
    } else {
      w->F64(r);
    }
  }
  for (std::uint8_t l : b.num_levels) w->U8(l);
  for (std::int32_t c : b.level_counts) {
    if (compact) {
      WriteVarint(static_cast<std::uint32_t>(c), w);
    } else {
      w->U32(static_cast<std::uint32_t>(c));
    }
  }
  std::size_t g = 0, node = 0;
  for (std::uint8_t levels : b.num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      const auto count = static_cast<std::size_t>(b.level_counts[g]);
      if (static_cast<std::int64_t>(count) == BsplineLatticeSize(k)) continue;  // dense
      // Runs of consecutive node indices: (first, length).
      std::vector<std::uint32_t> runs;
      for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t n = b.nodes[node + i];
        if (!runs.empty() && runs[runs.size() - 2] + runs.back() == n) {
          ++runs.back();
        } else {
          runs.push_back(n);
          runs.push_back(1);
        }
      }
      node += count;
      // Each run as (gap after the previous run's end, length - 1).
      WriteVarint(static_cast<std::uint32_t>(runs.size() / 2), w);
      std::uint32_t end = 0;
      for (std::size_t i = 0; i < runs.size(); i += 2) {
        WriteVarint(runs[i] - end, w);
        WriteVarint(runs[i + 1] - 1, w);
        end = runs[i] + runs[i + 1];
      }
    }
  }
}

std::uint64_t ReadSparseStructure(ByteReader* r, std::uint32_t nv, bool compact,
                                  int coefficient_bits, BsplineDisplacementData* d) {
  d->form = BsplineLevelForm::kAdditive;
  if (!r->Need(nv, compact ? 4 + 1 : 8 + 1, "displacement charts")) return 0;
  d->half_extent.resize(nv);
  for (double& x : d->half_extent)
    x = compact ? static_cast<double>(r->F32("half extent")) : r->F64("half extent");
  d->num_levels.resize(nv);
  std::uint64_t total_levels = 0;
  for (std::uint8_t& l : d->num_levels) {
    l = r->U8("level count");
    if (l > kMaxBsplineLevels) {
      r->Fail("a chart has " + std::to_string(l) + " displacement levels, at most " +
              std::to_string(kMaxBsplineLevels));
      return 0;
    }
    total_levels += l;
  }
  if (!r->Need(total_levels, compact ? 1 : 4, "level coefficient counts")) return 0;
  d->level_counts.resize(static_cast<std::size_t>(total_levels));
  std::uint64_t total = 0;
  std::size_t g = 0;
  for (std::uint8_t levels : d->num_levels) {
    for (int k = 0; k < levels && r->ok(); ++k, ++g) {
      const std::uint32_t c =
          compact ? ReadVarint(r, "level coefficient count") : r->U32("level coefficient count");
      if (c > static_cast<std::uint64_t>(BsplineLatticeSize(k))) {
        r->Fail("a level-" + std::to_string(k) + " lattice has " + std::to_string(c) +
                " coefficients, more than its " + std::to_string(BsplineLatticeSize(k)) + " nodes");
        return 0;
      }
      d->level_counts[g] = static_cast<std::int32_t>(c);
      total += c;
    }
  }
  // Refuse counts the file cannot hold before allocating node lists for them.
  const std::uint64_t bits = total * static_cast<std::uint64_t>(coefficient_bits);
  if (!r->Need(coefficient_bits % 8 == 0 ? total : (bits + 7) / 8,
               coefficient_bits % 8 == 0 ? static_cast<std::uint64_t>(coefficient_bits / 8) : 1,
               "displacement coefficients"))
    return 0;
  g = 0;
  for (std::uint8_t levels : d->num_levels) {
    for (int k = 0; k < levels; ++k, ++g) {
      const auto count = static_cast<std::uint64_t>(d->level_counts[g]);
      const auto size = static_cast<std::uint64_t>(BsplineLatticeSize(k));
      if (count == size) continue;
      const std::uint32_t nruns = ReadVarint(r, "node run count");
      if (!r->Need(nruns, 2, "node runs")) return 0;
      std::uint64_t covered = 0, next = 0;
      for (std::uint32_t i = 0; i < nruns && r->ok(); ++i) {
        const std::uint64_t first = next + ReadVarint(r, "node run gap");
        const std::uint64_t length = std::uint64_t{ReadVarint(r, "node run length")} + 1;
        if (!r->ok()) return 0;
        if (first + length > size || covered + length > count) {
          r->Fail("node runs of a level-" + std::to_string(k) +
                  " lattice leave the lattice or exceed its coefficient count");
          return 0;
        }
        for (std::uint64_t n = first; n < first + length; ++n) {
          d->nodes.push_back(static_cast<std::uint32_t>(n));
        }
        covered += length;
        next = first + length;
      }
      if (covered != count) {
        r->Fail("node runs of a level-" + std::to_string(k) + " lattice cover " +
                std::to_string(covered) + " nodes, not its " + std::to_string(count) +
                " coefficients");
        return 0;
      }
    }
  }
  d->offsets.assign(static_cast<std::size_t>(nv) + 1, 0);
  g = 0;
  for (std::uint32_t c = 0; c < nv; ++c) {
    std::int64_t chart = 0;
    for (int k = 0; k < d->num_levels[c]; ++k, ++g) chart += d->level_counts[g];
    d->offsets[c + 1] = d->offsets[c] + chart;
  }
  return r->ok() ? total : 0;
}

}  // namespace dsurf
}  // namespace dermis
