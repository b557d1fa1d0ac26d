#include "api/json_util.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <new>
#include <limits>
#include <type_traits>
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

namespace {

//! nlohmann's DOM builder, except that a parse error is recorded (where, and whether a number overflowed) instead of
//! thrown: the exception's text is the library's, and its out_of_range.406 ("1e400") carries no position.
class RecordingSax : public nlohmann::detail::json_sax_dom_parser<Json> {
public:
    explicit RecordingSax(Json& result) : json_sax_dom_parser(result, false) {}

    template <class Exception>
    bool parse_error(std::size_t position, const std::string& last_token, const Exception& ex) {
        failed = true;
        end = position;
        token_size = last_token.size();
        overflow = std::is_same_v<Exception, nlohmann::detail::out_of_range>;
        static_cast<void>(ex);
        return false;
    }

    bool failed = false;
    bool overflow = false;  //!< a number does not fit a double
    std::size_t end = 0;    //!< bytes read when the error was found (the end of the offending token)
    std::size_t token_size = 0;
};

//! "line 3, column 7" (both 1-based) of byte `offset` in `text`.
std::string line_and_column(std::string_view text, std::size_t offset) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

std::optional<ApiError> parse(std::string_view text, Json& out) {
    try {
        RecordingSax sax(out);
        const bool ok = Json::sax_parse(text.begin(), text.end(), &sax);
        if (ok && !sax.failed) return std::nullopt;
        if (sax.overflow) {
            // The number token ends where the error was found.
            const std::size_t start = sax.end >= sax.token_size ? sax.end - sax.token_size : 0;
            const std::string number(text.substr(start, std::min<std::size_t>(sax.token_size, 40)));
            ApiError error = make_problem(Problem::NumberOutOfRange,
                                          "number out of range at " + line_and_column(text, start) + ": " + number +
                                              " is beyond the largest double (about 1.8e308)");
            error.offset = static_cast<std::int64_t>(start);
            return error;
        }
        // The offset is that of the byte the parser stopped at (it had read `end` bytes).
        const std::size_t at = sax.end > 0 ? std::min(sax.end - 1, text.size()) : 0;
        std::string what;
        if (text.empty())
            what = "the body is empty";
        else if (sax.end > text.size())  // the parser asked for a byte past the end
            what = "the body ends too early, at " + line_and_column(text, text.size());
        else
            what = "syntax error at " + line_and_column(text, at);
        ApiError error = make_problem(Problem::InvalidJson, "request body is not valid JSON: " + what);
        error.offset = static_cast<std::int64_t>(at);
        return error;
    } catch (const std::bad_alloc&) {
        throw;  // the operation's guard answers 500 out of memory
    } catch (const std::exception&) {
        return make_problem(Problem::InvalidJson, "request body is not valid JSON");
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

ApiResult<Vec3> read_vec3(const Json& value, const std::string& field) {
    if (!value.is_array() || value.size() != 3) return invalid(field, field + " must be [x, y, z]");
    Vec3 p;
    for (std::size_t c = 0; c < 3; ++c) {
        auto x = read_number(value[c], index_path(field, c));
        if (!x) return std::move(x.error());
        p[static_cast<int>(c)] = x.value();
    }
    return p;
}

Json vec3_json(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

ApiResult<double> read_number(const Json& value, const std::string& field) {
    if (!value.is_number() || !std::isfinite(value.get<double>()))
        return invalid(field, field + " must be a finite number");
    return value.get<double>();
}

}  // namespace surfaced::api::json
