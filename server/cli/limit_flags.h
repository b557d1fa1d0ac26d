// The request budgets of api/limits.h as `surfaced serve` flags: one table gives each budget its flag, range and
// help line, so `serve --help`, the option parser and the "did you mean" list cannot disagree.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/limits.h"
#include "server/cli/args.h"

namespace surfaced::cli {

//! The budget flags (`--max-input-faces`, ...), in help order.
const std::vector<std::string_view>& limit_flag_names();

//! Sets the budget of `flag` in `limits` from `text`; false when `flag` is not a budget flag. A value that is not an
//! integer in the flag's range throws UsageError.
bool apply_limit_flag(std::string_view flag, const std::string& text, api::Limits& limits);

//! The budget flag `flag` as an option of a file command (its range checked, its help line and default from the
//! table), to be applied with apply_limit_flag. `flag` must be one of limit_flag_names().
Option limit_option(std::string_view flag);

//! The help lines of the budget flags, each with the default from a default-constructed api::Limits.
std::string limit_flags_help();

}  // namespace surfaced::cli
