#include "server/cli/table_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <system_error>

#include <sstream>

#include <nlohmann/json.hpp>

#include "api/options/option_reader.h"

namespace surfaced::cli {
namespace {

using api::options::OperationOptions;
using api::options::OptionSpec;
using api::options::OptionType;

constexpr std::size_t kHelpWidth = 118;
constexpr std::size_t kDescriptionColumn = 28;

//! A usage error when `value` is outside the row's range (a limit's maximum is the operation's to check), worded as
//! the operation words it: "--ratio: ratio must be in (0, 1], got 2" (`field`: the option, or one item of a list).
void check_in_range(const OptionSpec& spec, const api::options::OptionValue& value, std::string_view flag,
                    const std::string& field) {
    if (auto error = api::options::check_range(spec, value, field))
        throw UsageError{std::string(flag) + ": " + error->detail};
}

std::optional<std::int64_t> parse_integer(const std::string& text) {
    std::int64_t value = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size()) return std::nullopt;
    return value;
}

CheckValue check_of(const OptionSpec& spec) {
    switch (spec.type) {
        case OptionType::Integer:
            return [&spec](std::string_view flag, const std::string& text) {
                const auto value = parse_integer(text);
                if (!value) throw UsageError{std::string(flag) + " needs an integer, got \"" + text + "\""};
                check_in_range(spec, *value, flag, std::string(spec.name));
                return std::to_string(*value);
            };
        case OptionType::Number:
            return [&spec](std::string_view flag, const std::string& text) {
                double value = 0;
                const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
                if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value))
                    throw UsageError{std::string(flag) + " needs a number, got \"" + text + "\""};
                check_in_range(spec, value, flag, std::string(spec.name));
                return text;
            };
        case OptionType::Enum:
            return [&spec](std::string_view flag, const std::string& text) {
                const std::vector<std::string_view> values(spec.values.begin(), spec.values.end());
                if (std::find(values.begin(), values.end(), text) == values.end())
                    throw unknown_value(flag, text, values);
                return text;
            };
        case OptionType::List:
            return [&spec](std::string_view flag, const std::string& text) {
                // comma-separated integers, each in range; empty: none
                if (text.empty()) return text;
                for (std::size_t start = 0, k = 0;; ++k) {
                    const std::size_t comma = std::min(text.find(',', start), text.size());
                    const std::string item = text.substr(start, comma - start);
                    const auto value = parse_integer(item);
                    if (!value)
                        throw UsageError{std::string(flag) + ": item " + std::to_string(k) + " (\"" + item +
                                         "\") must be an integer (" + std::string(flag) + " 0,5,100)"};
                    check_in_range(spec, *value, flag, std::string(spec.name) + "[" + std::to_string(k) + "]");
                    if (comma == text.size()) break;
                    start = comma + 1;
                }
                return text;
            };
        case OptionType::Bool: break;
    }
    return nullptr;
}

std::string metavar(const OptionSpec& spec) {
    switch (spec.type) {
        case OptionType::Integer: return "N";
        case OptionType::Number: return "X";
        case OptionType::Enum: return "NAME";
        case OptionType::List: return "N,N,...";
        case OptionType::Bool: return "";
    }
    return "";
}

std::string joined(const std::vector<std::string>& parts, std::string_view separator) {
    std::string out;
    for (const std::string& part : parts) out += (out.empty() ? "" : std::string(separator)) + part;
    return out;
}

//! "in [1, 24] bits; default 14": the values, range, units and default of a row, as its help states them.
std::string details(const OptionSpec& spec) {
    std::vector<std::string> parts;
    if (spec.type == OptionType::Enum)
        parts.push_back("one of " + joined({spec.values.begin(), spec.values.end()}, ", "));
    std::string range;
    if (spec.type == OptionType::Integer || spec.type == OptionType::Number || spec.type == OptionType::List) {
        OptionSpec shown = spec;
        if (spec.max_is_limit) shown.max.reset();
        if (shown.min || shown.max) range = api::options::range_text(shown);
        if (spec.max_is_limit && spec.max) {
            range += (range.empty() ? "" : ", ") + std::string("up to the limit, ") +
                     std::to_string(static_cast<std::int64_t>(spec.max->value));
        }
        if (spec.type == OptionType::List && !range.empty()) range = "each " + range;
    }
    if (!spec.units.empty()) range += (range.empty() ? "" : " ") + std::string(spec.units);
    if (!range.empty()) parts.push_back(range);
    if (!spec.default_json.empty()) {
        std::string value(spec.default_json);
        if (value.size() >= 2 && value.front() == '"') value = value.substr(1, value.size() - 2);
        parts.push_back("default " + value);
    }
    return joined(parts, "; ");
}

//! `synopsis` and `description` as help lines: the description from column kDescriptionColumn, wrapped at
//! kHelpWidth; a synopsis too long for its column gets a line of its own.
std::string help_entry(const std::string& synopsis, const std::string& description,
                       std::size_t indent = kDescriptionColumn) {
    std::string out = "  " + synopsis;
    if (!synopsis.empty() && out.size() + 1 > indent)
        out += "\n" + std::string(indent, ' ');
    else
        out += std::string(indent - out.size(), ' ');
    std::size_t column = indent;
    std::size_t at = 0;
    bool first = true;
    while (at < description.size()) {
        std::size_t end = description.find(' ', at);
        if (end == std::string::npos) end = description.size();
        const std::string word = description.substr(at, end - at);
        if (!first && column + 1 + word.size() > kHelpWidth) {
            out += "\n" + std::string(indent, ' ');
            column = indent;
            first = true;
        }
        if (!first) out += ' ', ++column;
        out += word;
        column += word.size();
        first = false;
        at = end + 1;
    }
    return out + "\n";
}

std::string bool_synopsis(std::string_view name) { return flag_name(name) + ", --no-" + flag_name(name).substr(2); }

}  // namespace

std::string flag_name(std::string_view option_name) {
    std::string out = "--";
    for (const char c : option_name) out += c == '_' ? '-' : c;
    return out;
}

std::vector<Option> table_options(const OperationOptions& operation, unsigned transport) {
    std::vector<Option> out;
    const auto add = [&](const OptionSpec& spec, std::string_view name, std::string replaced_by) {
        if (spec.type == OptionType::Bool) {
            Option on = flag(flag_name(name), std::string(spec.name), "true");
            Option off = flag("--no-" + flag_name(name).substr(2), std::string(spec.name), "false");
            on.spec = off.spec = &spec;
            if (!replaced_by.empty()) {
                on.replaced_by = flag_name(spec.name);
                off.replaced_by = "--no-" + flag_name(spec.name).substr(2);
            }
            out.push_back(std::move(on));
            out.push_back(std::move(off));
            return;
        }
        out.push_back(Option{.name = flag_name(name),
                             .param = std::string(spec.name),
                             .check = check_of(spec),
                             .spec = &spec,
                             .replaced_by = std::move(replaced_by)});
    };
    for (const OptionSpec* spec : api::options::all_options(operation)) {
        if ((spec->transports & transport) == 0 || spec->name == "format") continue;
        add(*spec, spec->name, "");
        for (const std::string_view alias : spec->aliases) add(*spec, alias, flag_name(spec->name));
    }
    return out;
}

const OptionSpec& table_option(const OperationOptions& operation, std::string_view name) {
    const OptionSpec* spec = api::options::find_option(operation, name);
    if (!spec)
        throw std::logic_error("the option table of " + std::string(operation.operation) + " has no " +
                               std::string(name));
    return *spec;
}

Option deprecated_switch(const OperationOptions& operation, std::string name, std::string_view option,
                         std::string value) {
    const OptionSpec& spec = table_option(operation, option);
    Option out = flag(std::move(name), std::string(spec.name), value);
    out.spec = &spec;
    if (spec.type == OptionType::Bool)
        out.replaced_by = value == "true" ? flag_name(spec.name) : "--no-" + flag_name(spec.name).substr(2);
    else
        out.replaced_by = flag_name(spec.name) + " " + value;
    return out;
}

std::string options_help(const OperationOptions& operation, const std::vector<Option>& options) {
    std::string out = "Options:\n";
    out += help_entry("-o, --output OUT", "output file (required); - for standard output");
    if (const OptionSpec* format = api::options::find_option(operation, "format")) {
        std::vector<std::string> parts = {"one of " + joined({format->values.begin(), format->values.end()}, ", ")};
        parts.push_back("default: OUT's extension; needed with -o -");
        out += help_entry("--format NAME", std::string(format->description) + " [" + joined(parts, "; ") + "]");
    }
    for (const Option& option : options)
        if (!option.synopsis.empty()) out += help_entry(option.synopsis, option.description);
    std::vector<std::string> deprecated;
    for (std::size_t i = 0; i < options.size(); ++i) {
        const Option& option = options[i];
        if (!option.spec) continue;
        if (!option.replaced_by.empty()) {
            deprecated.push_back(option.name + " (use " + option.replaced_by + ")");
            continue;
        }
        if (option.spec->type == OptionType::Bool) {
            // the pair --name / --no-name: one entry
            if (option.switch_value != "true") continue;
            out += help_entry(bool_synopsis(option.spec->name),
                              std::string(option.spec->description) + " [" + details(*option.spec) + "]");
            continue;
        }
        const std::string more = details(*option.spec);
        out += help_entry(option.name + " " + metavar(*option.spec),
                          std::string(option.spec->description) + (more.empty() ? "" : " [" + more + "]"));
    }
    out += help_entry("-h, --help", "this text");
    if (!deprecated.empty())
        out += "\nDeprecated spellings, still accepted:\n" + help_entry("", joined(deprecated, ", "), 2);
    return out;
}

nlohmann::json option_json_value(const api::options::OptionSpec& spec, const std::string& text) {
    using api::options::OptionType;
    switch (spec.type) {
        case OptionType::Integer: return std::stoll(text);
        case OptionType::Number: return std::stod(text);
        case OptionType::Bool: return text == "true";
        case OptionType::Enum: return text;
        case OptionType::List: {
            nlohmann::json items = nlohmann::json::array();
            std::istringstream in(text);
            for (std::string item; std::getline(in, item, ',');) items.push_back(std::stoll(item));
            return items;
        }
    }
    return text;
}

}  // namespace surfaced::cli
