#include "server/cli/args.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace surfaced::cli {
namespace {

//! Edit distance with adjacent swaps (optimal string alignment): "levle" -> "levels" is 2.
std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

std::string_view without_dashes(std::string_view text) {
    while (text.starts_with('-')) text.remove_prefix(1);
    return text;
}

}  // namespace

std::optional<std::string_view> closest_match(std::string_view typed, const std::vector<std::string_view>& known) {
    std::optional<std::string_view> best;
    std::size_t best_distance = 0;
    for (const std::string_view word : known) {
        const std::size_t distance = edit_distance(typed, word);
        if (!best || distance < best_distance) best = word, best_distance = distance;
    }
    // Close enough to be a typo: a third of the word's letters at most (one for short words), and not every letter
    // of what was typed ("-x" is no typo of "-k").
    if (!best || best_distance == 0 || best_distance > std::max<std::size_t>(1, best->size() / 3) ||
        best_distance >= without_dashes(typed).size())
        return std::nullopt;
    return best;
}

UsageError unknown_value(std::string_view option, const std::string& text,
                         const std::vector<std::string_view>& allowed) {
    std::string message = std::string(option) + ": unknown value \"" + text + "\" (";
    if (const auto match = closest_match(text, allowed)) message += "did you mean \"" + std::string(*match) + "\"? ";
    message += "allowed: ";
    for (std::size_t i = 0; i < allowed.size(); ++i) message += (i ? ", \"" : "\"") + std::string(allowed[i]) + "\"";
    return UsageError{message + ")"};
}

UsageError unknown_option(std::string_view command, const std::string& arg,
                          const std::vector<std::string_view>& known) {
    std::string message = std::string(command) + ": unknown option \"" + arg + "\"";
    if (const auto match = closest_match(arg, known))
        message += " (did you mean " + std::string(*match) + "?)";
    else
        message += " (see surfaced " + std::string(command) + " --help)";
    return UsageError{message};
}

long long parse_number(std::string_view name, const std::string& text, long long min, long long max) {
    long long value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size())
        throw UsageError{std::string(name) + " needs an integer, got \"" + text + "\""};
    if (value < min || value > max)
        throw UsageError{std::string(name) + " must be between " + std::to_string(min) + " and " + std::to_string(max) +
                         ", got " + text};
    return value;
}

std::string checked_real(std::string_view name, const std::string& text) {
    double value = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value))
        throw UsageError{std::string(name) + " needs a number, got \"" + text + "\""};
    return text;
}

CheckValue integer(long long min, long long max) {
    return [=](std::string_view option, const std::string& text) {
        return std::to_string(parse_number(option, text, min, max));
    };
}
CheckValue real() { return checked_real; }

CheckValue one_of_names(std::vector<std::string_view> allowed) {
    return [allowed = std::move(allowed)](std::string_view option, const std::string& text) {
        if (std::find(allowed.begin(), allowed.end(), text) == allowed.end())
            throw unknown_value(option, text, allowed);
        return text;
    };
}

Option flag(std::string name, std::string param, std::string value) {
    return Option{.name = std::move(name), .param = std::move(param), .switch_value = std::move(value)};
}

std::optional<std::string> Parsed::option_for_field(std::string_view field) const {
    for (const auto& [name, option] : option_by_field) {
        if (field == name) return option;
        // an element of the option's value, or the option inside an object ("output.quantize_position")
        if (field.starts_with(name) && (field[name.size()] == '[' || field[name.size()] == '.')) return option;
        if (field.size() > name.size() && field.ends_with(name) && field[field.size() - name.size() - 1] == '.')
            return option;
    }
    return std::nullopt;
}

std::optional<Parsed> parse_file_command(Args& args, const std::string& command, std::string_view help,
                                         const std::vector<Option>& options, const std::string& input_name) {
    Parsed parsed;
    parsed.command = command;
    const bool complete = for_each_argument(args, [&](const std::string& arg,
                                                      std::optional<std::string>& inline_value) {
        if (arg == "-h" || arg == "--help") {
            std::cout << help;
            return false;
        }
        if (arg == "-o" || arg == "--output") {
            parsed.output = args.value(arg, inline_value);
            return true;
        }
        if (arg == "--format") {
            parsed.given[arg] = args.value(arg, inline_value);
            parsed.option_by_field["format"] = arg;
            return true;
        }
        for (const Option& option : options)
            if (arg == option.name) {
                std::string value;
                if (option.check) try {
                        value = option.check(arg, args.value(arg, inline_value));
                    } catch (const UsageError& e) {
                        throw UsageError{command + " " + e.message};
                    }
                if (option.param.empty()) {
                    parsed.given[arg] = value;
                    std::string field;
                    for (const char c : option.name.substr(2)) field += c == '-' ? '_' : c;
                    parsed.option_by_field[field] = arg;
                } else {
                    parsed.params[option.param] = option.check ? value : option.switch_value;
                    parsed.option_by_field[option.param] = arg;
                }
                return true;
            }
        if (arg.starts_with("-") && arg != "-") {
            std::vector<std::string_view> known = {"--output", "--format", "--help"};
            for (const Option& option : options) known.emplace_back(option.name);
            throw unknown_option(command, arg, known);
        }
        if (!parsed.input.empty())
            throw UsageError{command + ": unexpected argument \"" + arg + "\" (input is already " + parsed.input + ")"};
        parsed.input = arg;
        return true;
    });
    if (!complete) return std::nullopt;
    if (parsed.input.empty()) throw UsageError{command + ": missing " + input_name};
    if (parsed.output.empty()) throw UsageError{command + ": missing -o OUT"};
    return parsed;
}

}  // namespace surfaced::cli
