// What the JSON query endpoints (POST /mesh/query, POST /limit/evaluate) share, so that they take and answer batches
// alike: the request as a JSON body or as multipart/form-data (the mesh file in the part "file", the JSON body
// without the mesh in the part "request"); batches of items either as JSON arrays or as {"float32" | "float64":
// base64} of packed little-endian numbers, counted against a budget before they are decoded; and answer columns
// written as JSON or packed the same way ("encoding"). Internal to api/operations (includes nlohmann).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/json_util.h"
#include "api/operation.h"
#include "api/operations/request_forms.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::api::operations {

//! How number arrays travel: JSON numbers, or base64 of packed little-endian float32 / float64.
enum class Encoding { Json, Float32, Float64 };
inline constexpr EnumName<Encoding> kEncodingNames[] = {
    {"json", Encoding::Json}, {"float32", Encoding::Float32}, {"float64", Encoding::Float64}};

//! A batch of items of a fixed number of numbers each: a JSON array, or {"float32" | "float64": base64} of packed
//! little-endian numbers.
struct Batch {
    const json::Json* array = nullptr;  //!< the JSON form (the items are read by the endpoint or batch_item)
    std::vector<double> packed;         //!< the packed form, decoded
    std::size_t count = 0;
};

//! The shape and count of `field` (no numbers decoded yet, so that the budget is checked first): `components`
//! numbers per item. `what` names an item in messages ("[x, y, z]").
ApiResult<Batch> batch_shape(const json::Json& value, const std::string& field, std::size_t components,
                             std::string_view what);
//! Decodes a packed batch's numbers (after the budget check); each must be finite unless `finite_only` is false
//! (then the endpoint checks them per item). Nothing to do for a JSON batch.
std::optional<ApiError> decode_packed(const json::Json& value, const std::string& field, std::size_t components,
                                      Batch& batch, bool finite_only = true);
//! Item i of a batch as `components` numbers into `out`; a JSON item must be an array of that many finite numbers.
std::optional<ApiError> batch_item(const Batch& batch, std::size_t i, const std::string& field, std::size_t components,
                                   std::string_view what, double* out);

//! Answers collected before encoding: booleans, numbers, 3-vectors, 2-vectors (NaN where there is none) and indices
//! (-1).
struct Column {
    enum Kind { Bool, Real, Vector, Index, Vector2 } kind;
    std::vector<double> values;  //!< one per item (three for Vector, two for Vector2)
};

//! A column as JSON numbers (null for NaN / -1), or base64 of packed little-endian values: uint8 for booleans, int32
//! for indices (-1 for none), float32 or float64 for numbers and vectors (NaN for none).
json::Json encode_column(const Column& column, Encoding encoding);
//! Item i of a JSON-encoded column as a JSON value (what encode_column writes for it).
json::Json column_item(const Column& column, std::size_t i);

//! 503 cancelled when the request's compute deadline has passed.
std::optional<ApiError> deadline_passed(const Cancel& cancel);

//! The request in either form: a JSON body with the mesh in it, or a multipart/form-data body whose part "file" is a
//! mesh file and whose part "request" is the JSON body without the mesh.
struct QueryIntake {
    json::Json root;
    bool multipart = false;
    ApiRequest file;  //!< multipart: the mesh part as a raw upload (body, content type)
    std::string file_media_type;
};

//! Reads the body of `request` (to `endpoint`, "POST /mesh/query") in either form. `items` says what the "request"
//! part holds besides options ("the points and rays"), for messages.
std::optional<ApiError> take_query_request(const ApiRequest& request, const Limits& limits, std::string_view endpoint,
                                           std::string_view items, QueryIntake& in);

//! The mesh of a request taken by take_query_request: the member "mesh" of a JSON body, or the file part (a JSON mesh
//! or any mesh file format), within the input budget and valid under `rules`. `source` says which.
ApiResult<PolygonMesh> query_mesh(const QueryIntake& in, const Limits& limits, MeshRules rules, Source& source);

}  // namespace surfaced::api::operations
