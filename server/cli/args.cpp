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

Option flag(std::string_view name, std::string_view param, std::string_view value) {
    return Option{name, param, nullptr, value};
}

std::optional<Parsed> parse_file_command(Args& args, const std::string& command, std::string_view help,
                                         const std::vector<Option>& options, const std::string& input_name) {
    Parsed parsed;
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
