// Typed errors for input problems. Programmer mistakes are asserts; anything a user can cause is a GeoError.
// No exception crosses from geometry/ into api/: every public entry point returns Result<T>.
#pragma once

#include <cassert>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace surfaced {

enum class ErrorCode {
    InvalidArgument,  //!< an option is out of its documented range
    ParseError,       //!< a file or payload is syntactically malformed
    IndexOutOfRange,  //!< a face or tag refers to a vertex/face that does not exist
    DegenerateFace,   //!< a face with fewer than 3 vertices or a repeated vertex
    NonFinite,        //!< NaN or Inf coordinates
    NotTriangleMesh,  //!< a triangle-only algorithm got another polygon
    NonManifold,      //!< topology the algorithm cannot handle
    BudgetExceeded,   //!< the work or output would exceed a configured limit
    Unsupported,      //!< a valid input using a feature we do not support
    Cancelled,        //!< the caller's Cancel fired (deadline passed or abort requested); see core/cancel.h
    Internal,         //!< a bug: should never reach a user
};

//! Short stable name of an error code ("parse_error", ...), used in the API's error envelope.
const char* to_string(ErrorCode code);

//! What GeoError::element indexes, so that callers can name it (the API turns it into a field path).
enum class ElementKind { None, Vertex, Face, Crease, Corner, Hole };

struct GeoError {
    ErrorCode code = ErrorCode::InvalidArgument;
    std::string message;        //!< human-readable, already names the location ("line 12: ...")
    std::int64_t line = -1;     //!< 1-based line in a text input, or -1
    std::int64_t offset = -1;   //!< byte offset in a binary input, or -1
    std::int64_t element = -1;  //!< index of the element the error is about, or -1
    ElementKind element_kind = ElementKind::None;
};

//! Either a value or a GeoError (a small std::expected).
template <class T>
class [[nodiscard]] Result {
public:
    using value_type = T;
    Result(T value) : data_(std::move(value)) {}
    Result(GeoError error) : data_(std::move(error)) {}

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
    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

    const GeoError& error() const {
        assert(!ok());
        return std::get<1>(data_);
    }

private:
    std::variant<T, GeoError> data_;
};

struct Ok {};
using Status = Result<Ok>;

inline GeoError make_error(ErrorCode code, std::string message, std::int64_t line = -1, std::int64_t offset = -1) {
    return GeoError{code, std::move(message), line, offset, -1, ElementKind::None};
}

//! Older form with an element index of unspecified kind; prefer element_error.
inline GeoError make_error(ErrorCode code, std::string message, std::int64_t line, std::int64_t offset,
                           std::int64_t element) {
    return GeoError{code, std::move(message), line, offset, element, ElementKind::None};
}

//! An error about one element of a mesh (vertex 3, face 12, crease 2, ...).
inline GeoError element_error(ErrorCode code, std::string message, ElementKind kind, std::int64_t index) {
    return GeoError{code, std::move(message), -1, -1, index, kind};
}

}  // namespace surfaced
