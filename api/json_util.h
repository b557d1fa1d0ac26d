// Reading request JSON with errors that name the field (internal to api/; includes nlohmann, so only the codec TUs
// include it). One copy of the rules: what counts as an integer, a finite number, an unknown member. Options (the
// output object included) are read by their tables: api/options/option_reader.h.
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
#include "geometry/io/json_text.h"  // json_text(): JSON outputs with numbers as every output prints them

namespace surfaced::api::json {

using Json = nlohmann::json;

std::string index_path(std::string_view path, std::size_t i);           //!< "a.b" + 3 -> "a.b[3]"
std::string member_path(std::string_view path, std::string_view name);  //!< "a" + "b" -> "a.b"; "" + "b" -> "b"

//! 400 invalid_field naming `field`.
ApiError invalid(const std::string& field, std::string detail);
//! The status of a geometry error code, naming `field`.
ApiError geometry_error(ErrorCode code, const std::string& field, std::string detail);

//! Parses a request body; a syntax error becomes 400 invalid_json, a number beyond a double's range ("1e400") 400
//! number_out_of_range, both with the byte offset in `offset` and the line and column in the detail, in our words
//! (nothing of nlohmann's exception text).
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
ApiResult<Vec3> read_vec3(const Json& value, const std::string& field);  //!< [x, y, z], each finite
Json vec3_json(const Vec3& v);                                           //!< [x, y, z]
template <class E, std::size_t N>
ApiResult<E> read_enum(const Json& value, const std::string& field, const EnumName<E> (&table)[N]) {
    if (!value.is_string()) return invalid(field, field + " must be a string, one of " + enum_names(table));
    const auto& text = value.get_ref<const std::string&>();
    if (auto parsed = enum_from_name(table, text)) return *parsed;
    return invalid(field, field + ": unknown value \"" + text + "\" (allowed: " + enum_names(table) + ")");
}

}  // namespace surfaced::api::json
