#include "server/cli/args.h"

#include <cmath>
#include <iostream>

namespace surfaced::cli {

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
CheckValue any_text() {
    return [](std::string_view, const std::string& text) { return text; };
}

CheckValue one_of_names(std::vector<std::string_view> allowed) {
    return [allowed = std::move(allowed)](std::string_view option, const std::string& text) {
        for (const std::string_view name : allowed)
            if (text == name) return text;
        std::string list;
        for (const std::string_view name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
        throw UsageError{std::string(option) + ": unknown value \"" + text + "\" (allowed: " + list + ")"};
    };
}

Option flag(std::string_view name, std::string_view param, std::string_view value) {
    return Option{name, param, nullptr, value};
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
        for (const Option& option : options)
            if (arg == option.name) {
                parsed.given[arg] = option.check ? option.check(arg, args.value(arg, inline_value)) : std::string();
                std::string field(option.param);
                if (field.empty())
                    for (const char c : option.name.substr(2)) field += c == '-' ? '_' : c;
                parsed.option_by_field[field] = arg;
                return true;
            }
        if (arg.starts_with("-") && arg != "-") throw UsageError{command + ": unknown option \"" + arg + "\""};
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
