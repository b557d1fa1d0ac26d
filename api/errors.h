// The API's one error type and its one wire form.
//
// Every failure a client can see is an ApiError, rendered as RFC 9457 `application/problem+json`:
//   {"type": "/problems/<code>", "title": ..., "status": ..., "detail": ..., "code": "<code>",
//    "field": "mesh.faces[12][3]"  (when the problem is at a known place in a JSON request)
//    "line": 12 / "offset": 345     (when it is at a known place in an uploaded file or a JSON body)
//    "hint": "..."                  (when another option would make the request work)}
// `code` is stable and machine-readable (snake_case); `title` is the same for every occurrence of a code; `detail`
// describes this occurrence. `type` is a relative URI reserved for a future documentation page per code.
//
// Status codes are chosen in errors.cpp and nowhere else:
//   400  the request cannot be read: no body (empty_body), malformed JSON / mesh file (parse_error, invalid_json), a
//        JSON number beyond a double (number_out_of_range), a field of the wrong type or an unknown enum value
//        (invalid_field), unknown JSON fields (unknown_field) or query parameters (unknown_parameter), a
//        multipart/form-data body that does not parse or has not exactly one file part (malformed_multipart)
//   404  no such route (not_found); 405 known route, other method (method_not_allowed)
//   406  no `format` was given and the Accept header accepts none of the endpoint's output types (not_acceptable)
//   413  the request body is over Limits::max_body_bytes (payload_too_large). Only the byte size of the body.
//   415  the Content-Type is not one we read (unsupported_media_type)
//   422  the request is well formed but its geometry or size cannot be processed: index_out_of_range,
//        degenerate_face, non_finite, not_triangle_mesh, non_manifold, invalid_argument, unsupported,
//        coordinate_out_of_range (a coordinate beyond float32 for a glTF output), and budget_exceeded (levels over the
//        limit, input or *predicted output* over the face budget). We chose 422 over 413 for budgets because the
//        body itself was accepted; it is the work it asks for that is too large.
//   500  internal (a bug)
//   503  cancelled: the request's compute deadline passed or the server is shutting down (Retry-After is set)
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

#include "geometry/core/result.h"

namespace surfaced::api {

inline constexpr std::string_view kProblemJsonMediaType = "application/problem+json";

struct ApiError {
    int status = 500;
    std::string code;                    //!< stable, snake_case ("index_out_of_range")
    std::string title;                   //!< short summary of `code`
    std::string detail;                  //!< this occurrence, human-readable
    std::optional<std::string> field;    //!< path into a JSON request: "mesh.faces[12][3]", "levels"
    std::optional<std::int64_t> line;    //!< 1-based line in an uploaded text file
    std::optional<std::int64_t> offset;  //!< byte offset in an uploaded binary file or a JSON body
    std::optional<std::string> hint;     //!< what would make the request work ("repair=auto repairs it")
};

//! Problems raised by the API itself (as opposed to GeoErrors from geometry/).
enum class Problem {
    BadRequest,            //!< 400 the HTTP request itself is malformed (rejected by the HTTP layer)
    EmptyBody,             //!< 400 the endpoint needs a body and none was sent
    InvalidJson,           //!< 400 the body is not JSON
    NumberOutOfRange,      //!< 400 a JSON number does not fit a double (1e400)
    InvalidField,          //!< 400 a field/parameter has the wrong type or an unknown value, or is missing
    UnknownField,          //!< 400 a JSON object has a member we do not know
    UnknownParameter,      //!< 400 a query parameter we do not know
    MalformedMultipart,    //!< 400 a multipart/form-data body that does not parse, or without exactly one file part
    NotFound,              //!< 404
    MethodNotAllowed,      //!< 405
    NotAcceptable,         //!< 406 the Accept header accepts none of the endpoint's output media types
    PayloadTooLarge,       //!< 413
    UnsupportedMediaType,  //!< 415
    CoordinateOutOfRange,  //!< 422 a coordinate a float32 output format cannot hold
    BudgetExceeded,        //!< 422
    Internal,              //!< 500
};

//! HTTP status for a geometry error code (see the table at the top of this file).
int http_status(ErrorCode code);

//! An ApiError for a GeoError: status from http_status(), code from to_string(code), detail = message, and
//! line/offset when the GeoError carries them. `field` is left empty (only the caller knows the JSON path).
ApiError from_geo_error(const GeoError& error);

//! An ApiError for a problem the API detected.
ApiError make_problem(Problem problem, std::string detail, std::optional<std::string> field = std::nullopt);

//! An ApiError for a status the HTTP layer chose itself (414 URI too long, 416, 503 ...): code "http_<status>".
ApiError make_transport_problem(int status, std::string detail);

//! The RFC 9457 body for `error` (UTF-8 JSON; invalid UTF-8 in details is replaced, never passed through).
std::string to_problem_json(const ApiError& error);

//! `text` as a JSON string literal, quotes included. Invalid UTF-8 becomes U+FFFD so the output is always valid
//! JSON (nlohmann's dump() would throw on it instead). For small hand-written bodies.
std::string json_quote(std::string_view text);

//! Either a value or an ApiError: geometry's Result<T>, for api-level failures that already have a status.
template <class T>
class [[nodiscard]] ApiResult {
public:
    ApiResult(T value) : data_(std::move(value)) {}
    ApiResult(ApiError error) : data_(std::move(error)) {}

    bool ok() const { return data_.index() == 0; }
    explicit operator bool() const { return ok(); }
    T& value() & {
        assert(ok());
        return std::get<0>(data_);
    }
    const T& value() const& {
        assert(ok());
        return std::get<0>(data_);
    }
    T&& value() && {
        assert(ok());
        return std::get<0>(std::move(data_));
    }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }
    ApiError& error() & {
        assert(!ok());
        return std::get<1>(data_);
    }
    const ApiError& error() const& {
        assert(!ok());
        return std::get<1>(data_);
    }

private:
    std::variant<T, ApiError> data_;
};

}  // namespace surfaced::api
