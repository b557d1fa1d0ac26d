// Reading an operation's options from either transport by its table (option_spec.h): unknown names (with the
// nearest known one suggested), types, enum names and ranges are checked here, once, so that every operation answers
// the same mistake with the same status, field and message:
//   400 unknown_parameter / unknown_field   a name not in the table ("did you mean ...?")
//   400 invalid_field, field = the option   a wrong type, an unknown enum name, or a value out of range; query
//                                           parameters are named as sent, JSON members by their path ("output.x")
// The message of a range error gives the range and the value, numbers printed shortest-round-trip.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "api/dto.h"
#include "api/errors.h"
#include "api/options/option_spec.h"

namespace surfaced::api::options {

//! Integer: int64; Number: double; Bool: bool; Enum: the name; List: the items.
using OptionValue = std::variant<std::int64_t, double, bool, std::string, std::vector<std::int64_t>>;

//! The options one request gave, by their names in the table (an alias is stored under the option's name), each of
//! its type and in range.
class OptionValues {
public:
    bool has(std::string_view name) const { return values_.find(name) != values_.end(); }
    void set(std::string_view name, OptionValue value) {
        values_.insert_or_assign(std::string(name), std::move(value));
    }

    //! The value of `name` into `target` when it was given (target: the option's C++ type or a std::optional of it).
    template <class T>
    void get(std::string_view name, T& target) const {
        const auto it = values_.find(name);
        if (it == values_.end()) return;
        if constexpr (requires {
                          typename T::value_type;
                          target.reset();
                      })
            target = std::get<typename T::value_type>(it->second);
        else
            target = std::get<T>(it->second);
    }
    //! An Enum option into `target` (an E or a std::optional<E>) through the EnumName table its `values` came from.
    template <class E, std::size_t N, class Target>
    void get(std::string_view name, const EnumName<E> (&table)[N], Target& target) const {
        const auto it = values_.find(name);
        if (it == values_.end()) return;
        if (auto value = enum_from_name(table, std::get<std::string>(it->second))) target = *value;
    }
    //! Whether Enum option `name` was given as `value` (for a name outside the EnumName table it reads into).
    bool given_as(std::string_view name, std::string_view value) const {
        const auto it = values_.find(name);
        return it != values_.end() && std::holds_alternative<std::string>(it->second) &&
               std::get<std::string>(it->second) == value;
    }
    //! format, compression, quantize_position, normals.
    void get_output(OutputOptions& out) const;

private:
    std::map<std::string, OptionValue, std::less<>> values_;
};

//! The query parameters of a file upload: every name known (400 unknown_parameter naming them, with suggestions,
//! and the allowed ones) and given once, each value of its type and in range.
ApiResult<OptionValues> read_query(const OperationOptions& operation,
                                   const std::multimap<std::string, std::string>& query);
//! The options among the members of a JSON body (an object whose members were checked with json_members()), and
//! of its nested option objects ("output"), each of its type and in range; fields are JSON paths.
ApiResult<OptionValues> read_json(const OperationOptions& operation, const nlohmann::json& body);
//! The members a JSON body may have: the operation's inputs, its JSON options, and their objects ("output").
std::vector<std::string_view> json_members(const OperationOptions& operation);

//! nullopt when `value` (a number, or one item of a list) is within the option's range; else 400 invalid_field naming
//! `field`, with the range and the value. For a member an operation reads itself.
std::optional<ApiError> check_range(const OptionSpec& option, const OptionValue& value, const std::string& field);
//! The candidate nearest to `name` by edit distance, when near enough to be a likely typo.
std::optional<std::string_view> nearest_name(std::string_view name, const std::vector<std::string_view>& candidates);
//! "in [1, 24]", "in (0, 1]", ">= 0", "> 0": the option's range, as error messages state it.
std::string range_text(const OptionSpec& option);

}  // namespace surfaced::api::options
