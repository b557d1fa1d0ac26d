// The options of a command that runs an operation, generated from the operation's option table
// (api/options/option_spec.h): one flag per option, checked as the table says, and the Options section of the
// command's help. A table row added, renamed (its old name an alias) or given another default or range reaches the
// command line without edits here.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "api/options/option_spec.h"
#include "server/cli/args.h"

namespace surfaced::cli {

//! "--quantize-position" for "quantize_position".
std::string flag_name(std::string_view option_name);

//! The flags of `operation`'s options that travel on `transport` (api::options::kQuery for a command that sends a
//! query, kJson for one that builds a JSON body), except `format` (the output format: --format or OUT's extension):
//!   --kebab-name VALUE   checked from the row: an integer or number in its range (a limit's maximum is left to
//!                        the operation), one of an enum's values (with a suggestion), a list of integers
//!   --name / --no-name   for a boolean
//!   each alias of a row  as a deprecated flag of the same kind
std::vector<Option> table_options(const api::options::OperationOptions& operation, unsigned transport);

//! A deprecated switch `name` that sets the option `option` of `operation` (found by its name or an alias, so that it
//! survives a rename in the table) to `value`; null `check`: a switch.
Option deprecated_switch(const api::options::OperationOptions& operation, std::string name, std::string_view option,
                         std::string value);

//! The table row of `name` (or an alias) of `operation`; throws std::logic_error when the table has none (a
//! programming error: the command names an option its operation lacks).
const api::options::OptionSpec& table_option(const api::options::OperationOptions& operation, std::string_view name);
//! The JSON value of a table option given on the command line as `text` (already checked by its flag).
nlohmann::json option_json_value(const api::options::OptionSpec& spec, const std::string& text);

//! The Options section of a command's help: -o, --format (the values and default of `operation`'s format row),
//! the hand-written `options` that have a synopsis, the table's options with their description, values, range,
//! units and default, the deprecated spellings, and -h.
std::string options_help(const api::options::OperationOptions& operation, const std::vector<Option>& options);

}  // namespace surfaced::cli
