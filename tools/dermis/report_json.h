// Copyright (c) Dermis authors. SPDX-License-Identifier: MIT
// The start every JSON report of the dermis tool shares (fit --report, inspect --json,
// validate --json; docs/cli.md, "Reports"): its schema, the version that wrote it and the
// effective options, so that a run can be repeated.
#pragma once

#include <string>
#include <utility>

namespace dermis::cli {

/// Sets "schema", "dermis_version" (this build's) and "options" of `report` (in that order for
/// an ordered JSON object). `options` holds the options the run used after the defaults were
/// applied, each keyed by its command-line long name without the dashes ("control-vertices":
/// 540; a flag is true or false), so that passing `--NAME VALUE` for each (`--NAME` for a true
/// flag) with the same input repeats the run. `J` is nlohmann::json or nlohmann::ordered_json.
template <class J>
void StartReport(J* report, const std::string& schema, J options) {
  (*report)["schema"] = schema;
  (*report)["dermis_version"] = DERMIS_VERSION;
  (*report)["options"] = std::move(options);
}

}  // namespace dermis::cli
