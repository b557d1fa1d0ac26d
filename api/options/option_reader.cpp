#include "api/options/option_reader.h"

#include <algorithm>
#include <charconv>
#include <set>
#include <system_error>

#include <nlohmann/json.hpp>

#include "api/json_util.h"
#include "api/operations/request_forms.h"

namespace surfaced::api::options {
namespace {

using json::Json;
using operations::format_double;

std::string quoted_list(const std::vector<std::string_view>& names) {
    std::string out;
    for (std::string_view name : names) out += (out.empty() ? "\"" : ", \"") + std::string(name) + "\"";
    return out;
}

std::string bound_text(const OptionSpec& option, double bound) {
    if (option.type == OptionType::Integer || option.type == OptionType::List)
        return std::to_string(static_cast<std::int64_t>(bound));
    return format_double(bound);
}

std::string value_text(const OptionValue& value) {
    if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
    if (const auto* d = std::get_if<double>(&value)) return format_double(*d);
    return {};
}

bool in_range(const OptionSpec& option, double value) {
    if (option.min && (option.min->exclusive ? !(value > option.min->value) : !(value >= option.min->value)))
        return false;
    if (option.max && !option.max_is_limit &&
        (option.max->exclusive ? !(value < option.max->value) : !(value <= option.max->value)))
        return false;
    return true;
}

std::vector<std::string_view> query_names(const OperationOptions& operation) {
    std::vector<std::string_view> out;
    for (const OptionSpec* option : all_options(operation))
        if (option->on_query()) out.push_back(option->name);
    return out;
}

std::optional<ApiError> unknown_enum(const OptionSpec& option, const std::string& field, const std::string& text,
                                     std::string_view prefix) {
    const std::vector<std::string_view> values(option.values.begin(), option.values.end());
    std::string detail = std::string(prefix) + field + ": unknown value \"" + text + "\"";
    if (auto near = nearest_name(text, values)) detail += " (did you mean \"" + std::string(*near) + "\"?)";
    return make_problem(Problem::InvalidField, detail + " (allowed: " + quoted_list(values) + ")", field);
}

//! "0,5,100": integers, comma-separated (empty: none), each named `name[k]` when wrong.
ApiResult<std::vector<std::int64_t>> parse_list(const OptionSpec& option, const std::string& text) {
    std::vector<std::int64_t> out;
    if (text.empty()) return out;
    const std::string name(option.name);
    for (std::size_t start = 0, k = 0;; ++k) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        const std::string field = name + "[" + std::to_string(k) + "]";
        std::int64_t value = 0;
        const auto parsed = std::from_chars(item.data(), item.data() + item.size(), value);
        if (item.empty() || parsed.ec != std::errc() || parsed.ptr != item.data() + item.size())
            return make_problem(Problem::InvalidField,
                                "query parameter " + name + ": item " + std::to_string(k) + " (\"" + item +
                                    "\") must be an integer (" + name + "=0,5,100)",
                                field);
        if (auto error = check_range(option, value, field)) return std::move(*error);
        out.push_back(value);
        if (comma == text.size()) return out;
        start = comma + 1;
    }
}

ApiResult<OptionValue> parse_query_value(const OptionSpec& option, const std::string& name, const std::string& text) {
    switch (option.type) {
        case OptionType::Integer: {
            auto value = operations::parse_integer_parameter(name, text);
            if (!value) return std::move(value.error());
            return OptionValue(value.value());
        }
        case OptionType::Number: {
            auto value = operations::parse_number_parameter(name, text);
            if (!value) return std::move(value.error());
            return OptionValue(value.value());
        }
        case OptionType::Bool: {
            auto value = operations::parse_bool_parameter(name, text);
            if (!value) return std::move(value.error());
            return OptionValue(value.value());
        }
        case OptionType::Enum:
            if (std::find(option.values.begin(), option.values.end(), text) == option.values.end())
                return std::move(*unknown_enum(option, name, text, "query parameter "));
            return OptionValue(text);
        case OptionType::List: {
            auto value = parse_list(option, text);
            if (!value) return std::move(value.error());
            return OptionValue(std::move(value.value()));
        }
    }
    return make_problem(Problem::Internal, "option " + name + " has no type");
}

ApiResult<OptionValue> read_json_value(const OptionSpec& option, const Json& value, const std::string& field) {
    switch (option.type) {
        case OptionType::Integer: {
            auto read = json::read_integer(value, field);
            if (!read) return std::move(read.error());
            return OptionValue(read.value());
        }
        case OptionType::Number: {
            auto read = json::read_number(value, field);
            if (!read) return std::move(read.error());
            return OptionValue(read.value());
        }
        case OptionType::Bool: {
            auto read = json::read_bool(value, field);
            if (!read) return std::move(read.error());
            return OptionValue(read.value());
        }
        case OptionType::Enum: {
            const std::vector<std::string_view> values(option.values.begin(), option.values.end());
            if (!value.is_string())
                return json::invalid(field, field + " must be a string, one of " + quoted_list(values));
            const auto& text = value.get_ref<const std::string&>();
            if (std::find(values.begin(), values.end(), text) == values.end())
                return std::move(*unknown_enum(option, field, text, ""));
            return OptionValue(text);
        }
        case OptionType::List: {
            if (!value.is_array()) return json::invalid(field, field + " must be an array of integers");
            std::vector<std::int64_t> items;
            items.reserve(value.size());
            for (std::size_t k = 0; k < value.size(); ++k) {
                const std::string item_field = json::index_path(field, k);
                auto item = json::read_integer(value[k], item_field);
                if (!item) return std::move(item.error());
                if (auto error = check_range(option, item.value(), item_field)) return std::move(*error);
                items.push_back(item.value());
            }
            return OptionValue(std::move(items));
        }
    }
    return make_problem(Problem::Internal, "option " + field + " has no type");
}

}  // namespace

std::optional<ApiError> check_range(const OptionSpec& option, const OptionValue& value, const std::string& field) {
    double number = 0;
    if (const auto* i = std::get_if<std::int64_t>(&value))
        number = static_cast<double>(*i);
    else if (const auto* d = std::get_if<double>(&value))
        number = *d;
    else
        return std::nullopt;
    if (in_range(option, number)) return std::nullopt;
    std::string detail = field + " must be " + range_text(option);
    if (!option.units.empty()) detail += " (" + std::string(option.units) + ")";
    return make_problem(Problem::InvalidField, detail + ", got " + value_text(value), field);
}

void OptionValues::get_output(OutputOptions& out) const {
    get("format", kOutputFormatNames, out.format);
    if (has("format")) out.format_given = true;
    get("compression", kCompressionNames, out.draco);
    get("quantize_position", out.quantize_position);
    get("normals", out.normals);
}

std::string range_text(const OptionSpec& option) {
    const auto& lo = option.min;
    const auto& hi = option.max;
    if (lo && hi)
        return std::string("in ") + (lo->exclusive ? "(" : "[") + bound_text(option, lo->value) + ", " +
               bound_text(option, hi->value) + (hi->exclusive ? ")" : "]");
    if (lo) return (lo->exclusive ? "> " : ">= ") + bound_text(option, lo->value);
    if (hi) return (hi->exclusive ? "< " : "<= ") + bound_text(option, hi->value);
    return "any value";
}

std::optional<std::string_view> nearest_name(std::string_view name, const std::vector<std::string_view>& candidates) {
    // Levenshtein distance, one row at a time
    const auto distance = [](std::string_view a, std::string_view b) {
        std::vector<std::size_t> row(b.size() + 1);
        for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
        for (std::size_t i = 1; i <= a.size(); ++i) {
            std::size_t diagonal = row[0];
            row[0] = i;
            for (std::size_t j = 1; j <= b.size(); ++j) {
                const std::size_t above = row[j];
                row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
                diagonal = above;
            }
        }
        return row[b.size()];
    };
    std::optional<std::string_view> best;
    std::size_t best_distance = 0;
    for (std::string_view candidate : candidates) {
        const std::size_t d = distance(name, candidate);
        if (!best || d < best_distance) {
            best = candidate;
            best_distance = d;
        }
    }
    // a typo: at most a third of the longer name differs (and at least one edit is allowed)
    if (best && best_distance <= std::max<std::size_t>(1, std::max(name.size(), best->size()) / 3)) return best;
    return std::nullopt;
}

ApiResult<OptionValues> read_query(const OperationOptions& operation,
                                   const std::multimap<std::string, std::string>& query) {
    const std::vector<std::string_view> allowed = query_names(operation);
    std::set<std::string> unknown;
    for (const auto& [name, text] : query) {
        const OptionSpec* option = find_option(operation, name);
        if (!option || !option->on_query()) unknown.insert(name);
    }
    if (!unknown.empty()) {
        std::string names, suggestions;
        for (const auto& name : unknown) {
            names += (names.empty() ? "\"" : ", \"") + name + "\"";
            if (auto near = nearest_name(name, allowed))
                suggestions += (suggestions.empty() ? "" : ", ") + std::string("\"") + std::string(*near) +
                               "\" for \"" + name + "\"";
        }
        std::string detail = "unknown query parameter" + std::string(unknown.size() > 1 ? "s " : " ") + names;
        if (!suggestions.empty()) {
            if (unknown.size() == 1) suggestions = suggestions.substr(0, suggestions.find(" for "));
            detail += " (did you mean " + suggestions + "?)";
        }
        std::string allowed_names;
        for (std::string_view name : allowed) allowed_names += (allowed_names.empty() ? "" : ", ") + std::string(name);
        return make_problem(Problem::UnknownParameter, detail + " (allowed: " + allowed_names + ")", *unknown.begin());
    }
    OptionValues values;
    std::map<std::string_view, std::string_view> given_as;  // option -> the name it was given under
    for (const auto& [name, text] : query) {
        const OptionSpec& option = *find_option(operation, name);
        if (const auto it = given_as.find(option.name); it != given_as.end()) {
            if (it->second == name)
                return make_problem(Problem::InvalidField, "query parameter " + name + " is given more than once",
                                    name);
            const std::string alias(it->second == option.name ? std::string_view(name) : it->second);
            return make_problem(Problem::InvalidField,
                                "query parameters " + std::string(it->second) + " and " + name + " both give " +
                                    std::string(option.name) + " (" + alias + " is its deprecated name): give one",
                                name);
        }
        given_as.emplace(option.name, name);
        auto value = parse_query_value(option, name, text);
        if (!value) return std::move(value.error());
        if (auto error = check_range(option, value.value(), name)) return std::move(*error);
        values.set(option.name, std::move(value.value()));
    }
    return values;
}

std::vector<std::string_view> json_members(const OperationOptions& operation) {
    std::vector<std::string_view> out(operation.json_inputs.begin(), operation.json_inputs.end());
    for (const OptionSpec* option : all_options(operation)) {
        if (!option->on_json()) continue;
        const std::string_view member = option->json_object.empty() ? option->name : option->json_object;
        if (std::find(out.begin(), out.end(), member) == out.end()) out.push_back(member);
        if (option->json_object.empty())
            for (std::string_view alias : option->aliases) out.push_back(alias);
    }
    return out;
}

ApiResult<OptionValues> read_json(const OperationOptions& operation, const Json& body) {
    OptionValues values;
    // the nested option objects ("output"): each an object with only its options as members
    std::vector<std::string_view> objects;
    for (const OptionSpec* option : all_options(operation))
        if (option->on_json() && !option->json_object.empty() &&
            std::find(objects.begin(), objects.end(), option->json_object) == objects.end())
            objects.push_back(option->json_object);
    for (std::string_view object : objects) {
        const auto it = body.find(object);
        if (it == body.end()) continue;
        std::vector<std::string_view> members;
        for (const OptionSpec* option : all_options(operation))
            if (option->on_json() && option->json_object == object) members.push_back(option->name);
        const std::string path(object);
        if (!it->is_object()) return json::invalid(path, path + " must be an object {" + quoted_list(members) + "}");
        if (auto error = json::check_members(*it, path, members)) return std::move(*error);
    }
    for (const OptionSpec* option_ptr : all_options(operation)) {
        const OptionSpec& option = *option_ptr;
        if (!option.on_json()) continue;
        const Json* container = &body;
        if (!option.json_object.empty()) {
            const auto it = body.find(option.json_object);
            if (it == body.end()) continue;
            container = &*it;
        }
        std::vector<std::string_view> names{option.name};
        if (option.json_object.empty()) names.insert(names.end(), option.aliases.begin(), option.aliases.end());
        for (std::string_view name : names) {
            const auto it = container->find(name);
            if (it == container->end()) continue;
            const std::string field = json::member_path(option.json_object, name);
            if (values.has(option.name))
                return json::invalid(field, json::member_path(option.json_object, option.name) + " and " + field +
                                                " both give " + std::string(option.name) + " (" + std::string(name) +
                                                " is its deprecated name): give one");
            auto value = read_json_value(option, *it, field);
            if (!value) return std::move(value.error());
            if (auto error = check_range(option, value.value(), field)) return std::move(*error);
            values.set(option.name, std::move(value.value()));
        }
    }
    return values;
}

}  // namespace surfaced::api::options
