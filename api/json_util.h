// Reading request JSON with errors that name the field (internal to api/; includes nlohmann, so only the codec TUs
// include it). One copy of the rules: what counts as an integer, a finite number, an unknown member, and the output
// options object every endpoint shares.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/dto.h"
#include "api/errors.h"
#include "geometry/core/result.h"

namespace surfaced::api::json {

using Json = nlohmann::json;

std::string index_path(std::string_view path, std::size_t i);           //!< "a.b" + 3 -> "a.b[3]"
std::string member_path(std::string_view path, std::string_view name);  //!< "a" + "b" -> "a.b"; "" + "b" -> "b"

//! 400 invalid_field naming `field`.
ApiError invalid(const std::string& field, std::string detail);
//! The status of a geometry error code, naming `field`.
ApiError geometry_error(ErrorCode code, const std::string& field, std::string detail);

//! Parses a request body; a syntax error becomes 400 invalid_json with the byte offset (nlohmann reports errors by
//! exception, which does not leave this function).
std::optional<ApiError> parse(std::string_view text, Json& out);
//! Every member of `object` must be in `allowed`; otherwise one 400 unknown_field naming all unknown members (and
//! the nearest allowed name of each that looks like a typo).
std::optional<ApiError> check_members(const Json& object, std::string_view path,
                                      std::initializer_list<std::string_view> allowed);
std::optional<ApiError> check_members(const Json& object, std::string_view path,
                                      const std::vector<std::string_view>& allowed);

ApiResult<std::int64_t> read_integer(const Json& value, const std::string& field);  //!< no fraction or exponent
ApiResult<double> read_number(const Json& value, const std::string& field);         //!< finite
ApiResult<bool> read_bool(const Json& value, const std::string& field);
template <class E, std::size_t N>
ApiResult<E> read_enum(const Json& value, const std::string& field, const EnumName<E> (&table)[N]) {
    if (!value.is_string()) return invalid(field, field + " must be a string, one of " + enum_names(table));
    const auto& text = value.get_ref<const std::string&>();
    if (auto parsed = enum_from_name(table, text)) return *parsed;
    return invalid(field, field + ": unknown value \"" + text + "\" (allowed: " + enum_names(table) + ")");
}

//! Reads member `name` of `object` into `target` when it is there, by target's type (std::int64_t: integer, double:
//! finite number, bool; or a std::optional of one): nullopt when absent or read, else the error naming `name`.
//! `target` changes only when the member was read (the JSON counterpart of request_forms.h's read_parameter).
template <class T>
std::optional<ApiError> read_member(const Json& object, const std::string& name, T& target) {
    const auto it = object.find(name);
    if (it == object.end()) return std::nullopt;
    auto value = [&] {
        if constexpr (requires {
                          typename T::value_type;
                          target.reset();
                      }) {  // std::optional<U>
            using U = typename T::value_type;
            if constexpr (std::is_same_v<U, bool>)
                return read_bool(*it, name);
            else if constexpr (std::is_floating_point_v<U>)
                return read_number(*it, name);
            else
                return read_integer(*it, name);
        } else if constexpr (std::is_same_v<T, bool>) {
            return read_bool(*it, name);
        } else if constexpr (std::is_floating_point_v<T>) {
            return read_number(*it, name);
        } else {
            return read_integer(*it, name);
        }
    }();
    if (!value) return std::move(value.error());
    target = value.value();
    return std::nullopt;
}
//! The same for an enumerated member: one of the names in `table` (`target` an E or a std::optional<E>).
template <class E, std::size_t N, class Target>
std::optional<ApiError> read_member(const Json& object, const std::string& name, const EnumName<E> (&table)[N],
                                    Target& target) {
    const auto it = object.find(name);
    if (it == object.end()) return std::nullopt;
    auto value = read_enum(*it, name, table);
    if (!value) return std::move(value.error());
    target = value.value();
    return std::nullopt;
}

//! "output": {"format", "compression", "quantize_position", "normals"}; ranges are checked by the operations.
ApiResult<OutputOptions> decode_output(const Json& value);
//! Member "output" of `object` decoded into `target` when it is there (decode_output): nullopt when absent or read.
std::optional<ApiError> read_output(const Json& object, OutputOptions& target);

}  // namespace surfaced::api::json
