#include "api/json_util.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "api/options/option_reader.h"

namespace surfaced::api::json {

std::string index_path(std::string_view path, std::size_t i) {
    std::string out(path);
    out += '[';
    out += std::to_string(i);
    out += ']';
    return out;
}

std::string member_path(std::string_view path, std::string_view name) {
    if (path.empty()) return std::string(name);
    std::string out(path);
    out += '.';
    out += name;
    return out;
}

ApiError invalid(const std::string& field, std::string detail) {
    return make_problem(Problem::InvalidField, std::move(detail), field);
}

ApiError geometry_error(ErrorCode code, const std::string& field, std::string detail) {
    ApiError error = from_geo_error(make_error(code, std::move(detail)));
    error.field = field;
    return error;
}

//! Parses `text`; nlohmann reports errors by exception, which must not leave this function.
std::optional<ApiError> parse(std::string_view text, Json& out) {
    try {
        out = Json::parse(text.begin(), text.end());
        return std::nullopt;
    } catch (const Json::parse_error& e) {
        // e.what() is "[json.exception.parse_error.101] parse error at line 1, column 2: ..."; the bracketed id
        // means nothing to a client.
        std::string message = e.what();
        if (const auto pos = message.find("] "); message.starts_with("[json.exception") && pos != std::string::npos)
            message.erase(0, pos + 2);
        ApiError error = make_problem(Problem::InvalidJson, "request body is not valid JSON: " + message);
        // nlohmann's `byte` counts from 1 (the byte it stopped at); ours is a 0-based offset into the body.
        error.offset = e.byte > 0 ? static_cast<std::int64_t>(e.byte - 1) : 0;
        return error;
    } catch (const Json::out_of_range& e) {
        // Not a parse_error: nlohmann throws out_of_range.406 for a literal that overflows a double ("1e999"),
        // without a position. It is a non-finite coordinate (or option), so it gets the NonFinite status.
        return from_geo_error(
            make_error(ErrorCode::NonFinite, std::string("a number in the body does not fit a double: ") + e.what()));
    } catch (const Json::exception& e) {
        return make_problem(Problem::InvalidJson, std::string("request body is not valid JSON: ") + e.what());
    }
}

std::optional<ApiError> check_members(const Json& object, std::string_view path,
                                      std::initializer_list<std::string_view> allowed) {
    return check_members(object, path, std::vector<std::string_view>(allowed));
}

std::optional<ApiError> check_members(const Json& object, std::string_view path,
                                      const std::vector<std::string_view>& allowed) {
    std::vector<std::string> unknown;
    for (const auto& item : object.items())
        if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end()) unknown.push_back(item.key());
    if (unknown.empty()) return std::nullopt;
    std::string names, allowed_names, suggestions;
    for (const auto& name : unknown) {
        names += (names.empty() ? "\"" : ", \"") + name + "\"";
        if (auto near = options::nearest_name(name, allowed))
            suggestions += (suggestions.empty() ? "\"" : ", \"") + std::string(*near) + "\" for \"" + name + "\"";
    }
    for (std::string_view name : allowed)
        allowed_names += (allowed_names.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    if (unknown.size() == 1 && !suggestions.empty()) suggestions = suggestions.substr(0, suggestions.find(" for "));
    const std::string where = path.empty() ? "at top level" : "in " + std::string(path);
    return make_problem(Problem::UnknownField,
                        "unknown field" + std::string(unknown.size() > 1 ? "s " : " ") + names + " " + where +
                            (suggestions.empty() ? "" : " (did you mean " + suggestions + "?)") +
                            " (allowed: " + allowed_names + ")",
                        member_path(path, unknown.front()));
}

ApiResult<std::int64_t> read_integer(const Json& value, const std::string& field) {
    if (value.is_number_unsigned()) {
        const auto v = value.get<std::uint64_t>();
        return v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())
                   ? std::numeric_limits<std::int64_t>::max()
                   : static_cast<std::int64_t>(v);
    }
    // nlohmann stores 2.0 as a float: an integer field must be written without a fraction or exponent.
    if (value.is_number_integer()) return value.get<std::int64_t>();
    return invalid(field, field + " must be an integer");
}

ApiResult<bool> read_bool(const Json& value, const std::string& field) {
    if (!value.is_boolean()) return invalid(field, field + " must be true or false");
    return value.get<bool>();
}

ApiResult<double> read_number(const Json& value, const std::string& field) {
    if (!value.is_number() || !std::isfinite(value.get<double>()))
        return invalid(field, field + " must be a finite number");
    return value.get<double>();
}

}  // namespace surfaced::api::json
