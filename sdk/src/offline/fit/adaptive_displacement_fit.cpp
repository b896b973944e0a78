// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// Adaptive multilevel displacement fitting (docs/fitting.md, "Adaptive displacement levels"):
// coarse-to-fine levels fitted by DisplacementLevelFitter (density and residual criteria,
// joint penalised least squares), a fixed-seed validation split that stops adding levels when
// they stop helping points the fit has not seen, then the fit on every point with the levels
// kept, less those after the last that brought the check points (if any) closer, stored as
// per-level sparse corrections (BsplineLevelForm::kAdditive).
#include "dermis/offline/fit/adaptive_displacement_fit.h"

#include <algorithm>
#include <cmath>

#include "dermis/core/hash.h"
#include "dermis/core/parallel.h"

namespace dermis {
bool IsValidationPoint(std::size_t i, double fraction, std::uint64_t seed) {
  if (!(fraction > 0.0)) return false;
  const double u = HashToUnit(SplitMix64(seed ^ SplitMix64(i)));
  return u < fraction;
}

Status FitAdaptiveDisplacement(const std::vector<double>& half_extent,
                               const std::vector<DisplacementTarget>& targets,
                               const AdaptiveDisplacementOptions& options,
                               BsplineDisplacementData* out, AdaptiveDisplacementReport* report) {
  if (!(options.validation >= 0.0 && options.validation < 1.0)) {
    return Status::InvalidInput("displacement fit: the validation fraction must lie in [0, 1)");
  }
  if (!(options.min_node_weight > 0.0) || !(options.smoothing >= 0.0) ||
      !(options.residual_threshold >= 0.0) || !(options.min_improvement >= 0.0) ||
      !(options.check_improvement >= 0.0 && options.check_improvement < 1.0)) {
    return Status::InvalidInput(
        "displacement fit: the node weight must be positive; smoothing, residual threshold "
        "and improvements must not be negative (a check improvement below 1)");
  }
  const std::size_t nc = half_extent.size();
  for (double r : half_extent) {
    if (!(r > 0.0) || !std::isfinite(r)) {
      return Status::InvalidInput("displacement fit: a chart's half extent is not positive");
    }
  }
  for (const DisplacementTarget& t : targets) {
    if (t.count < 1 || t.count > 4) {
      return Status::InvalidInput("displacement fit: a point has no chart");
    }
    if (!(t.weight > 0.0) || !std::isfinite(t.weight)) {
      return Status::InvalidInput("displacement fit: a point's weight is not positive and finite");
    }
    for (int s = 0; s < t.count; ++s) {
      if (t.chart[s] < 0 || static_cast<std::size_t>(t.chart[s]) >= nc) {
        return Status::InvalidInput("displacement fit: a point's chart is out of range");
      }
    }
  }
  LevelFitOptions lopt;
  lopt.min_node_weight = options.min_node_weight;
  lopt.smoothing = options.smoothing;
  lopt.iterations = options.solver_iterations;
  lopt.tolerance = options.solver_tolerance;
  lopt.consistency = options.consistency;
  lopt.threads = ResolveThreadCount(options.threads);
  const int max_levels = std::clamp(options.max_levels, 1, kMaxBsplineLevels);
  AdaptiveDisplacementReport rep;
  // The fitted points, and the check points (measured only).
  std::vector<std::uint32_t> all, checks;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    (targets[i].check ? checks : all).push_back(static_cast<std::uint32_t>(i));
  }
  // The residual criterion's threshold for a level: a multiple of the mean error the levels
  // before it left (for level 0: of the domain surface's error).
  auto threshold = [&](double mean_error) { return options.residual_threshold * mean_error; };

  // The coefficient budget left for the next level when fitting `points` of the targets (-1:
  // no budget). An absolute budget is scaled to the share of the targets fitted.
  auto budget = [&](std::size_t points, std::int64_t used) -> std::int64_t {
    double total = -1.0;
    if (options.max_coefficients >= 0) {
      total = static_cast<double>(options.max_coefficients) * static_cast<double>(points) /
              static_cast<double>(std::max<std::size_t>(all.size(), 1));
    } else if (options.max_coefficients_per_point > 0.0) {
      total = options.max_coefficients_per_point * static_cast<double>(points);
    }
    if (total < 0.0) return -1;
    return std::max<std::int64_t>(static_cast<std::int64_t>(std::floor(total)) - used, 0);
  };

  // 1. The stopping rule: fit the points outside the validation split level by level, and
  // keep a level only while it lowers the validation error by min_improvement.
  int levels = max_levels;
  rep.stopped_by = "max levels";
  // Why a level found no node: the budget was spent, or the data support none.
  auto NoNodes = [](std::int64_t left) {
    return left == 0 ? std::string("budget") : std::string("no supported node");
  };
  std::vector<std::uint32_t> train, validation;
  for (std::uint32_t i : all) {
    (IsValidationPoint(i, options.validation, options.validation_seed) ? validation : train)
        .push_back(i);
  }
  const bool trial_run = !validation.empty() && !train.empty();
  if (trial_run) {
    // The trial only compares levels: half the solver steps.
    LevelFitOptions topt = lopt;
    topt.iterations = std::max(1, lopt.iterations / 2);
    DisplacementLevelFitter trial(half_extent, targets, train, validation, topt);
    double previous = trial.EvalError();
    std::int64_t used = 0;
    levels = 0;
    for (int k = 0; k < max_levels; ++k) {
      AdaptiveLevelReport lr;
      lr.level = k;
      lr.nodes = trial.FitLevel(k, threshold(trial.FitError()), budget(train.size(), used),
                                &lr.iterations);
      used += lr.nodes;
      lr.train_mean = trial.FitError();
      lr.validation_mean = trial.EvalError();
      rep.trial.push_back(lr);
      if (lr.nodes == 0) {
        rep.stopped_by = NoNodes(budget(train.size(), used));
        break;
      }
      if (!(lr.validation_mean < (1.0 - options.min_improvement) * previous)) {
        rep.stopped_by = "validation";
        break;
      }
      previous = lr.validation_mean;
      levels = k + 1;
    }
  }

  // 2. The fit on every point with that many levels, each level's active nodes and values
  // kept per chart; with check points, the levels that no longer bring them closer are then
  // dropped (the check points' rule).
  BsplineDisplacementData data;
  data.form = BsplineLevelForm::kAdditive;
  data.half_extent = half_extent;
  data.num_levels.assign(nc, 0);
  std::vector<std::vector<std::vector<std::uint32_t>>> nodes(static_cast<std::size_t>(levels));
  std::vector<std::vector<std::vector<float>>> values(static_cast<std::size_t>(levels));
  {
    DisplacementLevelFitter fit(half_extent, targets, all, checks, lopt);
    rep.check_points = static_cast<std::int64_t>(checks.size());
    if (!checks.empty()) rep.check_mean.push_back(fit.EvalError());
    std::int64_t used = 0;
    for (int k = 0; k < levels; ++k) {
      int iterations = 0;
      const double before = fit.FitError();
      const std::int64_t n =
          fit.FitLevel(k, threshold(before), budget(all.size(), used), &iterations);
      used += n;
      // Without a validation split the rule watches the fitted points: a level that lowers
      // their error by less than min_improvement ends the fit
      // (and is dropped).
      if (!trial_run && !(fit.FitError() < (1.0 - options.min_improvement) * before)) {
        rep.stopped_by = "fitted points";
        levels = k;
        break;
      }
      rep.level_nodes.push_back(n);
      nodes[static_cast<std::size_t>(k)].resize(nc);
      values[static_cast<std::size_t>(k)].resize(nc);
      if (n == 0) {
        if (rep.stopped_by.empty() || rep.stopped_by == "max levels") {
          rep.stopped_by = NoNodes(budget(all.size(), used));
        }
        levels = k;
        break;
      }
      if (!checks.empty()) rep.check_mean.push_back(fit.EvalError());
      for (std::size_t c = 0; c < nc; ++c) {
        if (fit.nodes(c).empty()) continue;
        nodes[static_cast<std::size_t>(k)][c] = fit.nodes(c);
        values[static_cast<std::size_t>(k)][c] = fit.values(c);
      }
    }
  }
  // The check points' rule: check_mean[L] is their error with the first L levels (additive
  // levels: each prefix is exactly the fit with that many levels). The levels after the last
  // one that brought them closer by check_improvement are dropped.
  if (!checks.empty()) {
    int keep = levels;
    while (keep > 0 && !(rep.check_mean[static_cast<std::size_t>(keep)] <
                         (1.0 - options.check_improvement) *
                             rep.check_mean[static_cast<std::size_t>(keep - 1)])) {
      --keep;
    }
    // Only where the levels kept bring the check points closer than the domain surface alone:
    // where none does, the check points' mean cannot see what the levels are for (a bulge at
    // a fold, on a surface already closest to them without a level), and every level stays.
    const bool telling = keep > 0 && rep.check_mean[static_cast<std::size_t>(keep)] <
                                         (1.0 - options.check_improvement) * rep.check_mean[0];
    if (telling && keep < levels) {
      rep.stopped_by = "check points";
      levels = keep;
      rep.level_nodes.resize(static_cast<std::size_t>(keep));
    }
  }
  // Each chart's levels: up to its last non-empty one among those kept.
  for (std::size_t c = 0; c < nc; ++c) {
    for (int k = 0; k < levels; ++k) {
      if (!nodes[static_cast<std::size_t>(k)][c].empty()) {
        data.num_levels[c] = static_cast<std::uint8_t>(k + 1);
      }
    }
  }
  // 3. Storage: each chart's levels up to its last non-empty one; a level with every node
  // active is dense (no node list).
  data.offsets.assign(nc + 1, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    for (int k = 0; k < data.num_levels[c]; ++k) {
      const std::vector<std::uint32_t>& ln = nodes[static_cast<std::size_t>(k)][c];
      const std::vector<float>& lv = values[static_cast<std::size_t>(k)][c];
      data.level_counts.push_back(static_cast<std::int32_t>(ln.size()));
      if (static_cast<std::int64_t>(ln.size()) != BsplineLatticeSize(k)) {
        data.nodes.insert(data.nodes.end(), ln.begin(), ln.end());
      }
      data.values.insert(data.values.end(), lv.begin(), lv.end());
    }
    data.offsets[c + 1] = static_cast<std::int64_t>(data.values.size());
  }
  rep.levels = levels;
  rep.coefficients = static_cast<std::int64_t>(data.values.size());
  *out = std::move(data);
  if (report) *report = std::move(rep);
  return Status::Ok();
}

}  // namespace dermis
