#include "api/errors.h"

#include <cstdio>

namespace surfaced::api {
namespace {

struct ProblemInfo {
    int status;
    const char* code;
    const char* title;
};

ProblemInfo info(Problem problem) {
    switch (problem) {
        case Problem::BadRequest: return {400, "bad_request", "Malformed HTTP request"};
        case Problem::EmptyBody: return {400, "empty_body", "Request body is empty"};
        case Problem::InvalidJson: return {400, "invalid_json", "Request body is not valid JSON"};
        case Problem::NumberOutOfRange: return {400, "number_out_of_range", "Number out of range"};
        case Problem::InvalidField: return {400, "invalid_field", "Invalid field or parameter"};
        case Problem::UnknownField: return {400, "unknown_field", "Unknown field"};
        case Problem::UnknownParameter: return {400, "unknown_parameter", "Unknown query parameter"};
        case Problem::MalformedMultipart: return {400, "malformed_multipart", "Malformed multipart/form-data body"};
        case Problem::NotFound: return {404, "not_found", "No such endpoint"};
        case Problem::MethodNotAllowed: return {405, "method_not_allowed", "Method not allowed"};
        case Problem::NotAcceptable: return {406, "not_acceptable", "No acceptable output media type"};
        case Problem::PayloadTooLarge: return {413, "payload_too_large", "Request body too large"};
        case Problem::UnsupportedMediaType: return {415, "unsupported_media_type", "Unsupported media type"};
        case Problem::CoordinateOutOfRange:
            return {422, "coordinate_out_of_range", "Coordinate beyond the output format's range"};
        case Problem::BudgetExceeded: return {422, "budget_exceeded", "Request exceeds a budget"};
        case Problem::Internal: return {500, "internal", "Internal error"};
    }
    return {500, "internal", "Internal error"};
}

const char* title_for(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument: return "Invalid argument";
        case ErrorCode::ParseError: return "Malformed mesh data";
        case ErrorCode::IndexOutOfRange: return "Index out of range";
        case ErrorCode::DegenerateFace: return "Degenerate face";
        case ErrorCode::NonFinite: return "Non-finite coordinate";
        case ErrorCode::NotTriangleMesh: return "Not a triangle mesh";
        case ErrorCode::NonManifold: return "Non-manifold mesh";
        case ErrorCode::BudgetExceeded: return "Request exceeds a budget";
        case ErrorCode::Unsupported: return "Unsupported input";
        case ErrorCode::Cancelled: return "Request cancelled";
        case ErrorCode::Internal: return "Internal error";
    }
    return "Internal error";
}

// Length of the valid UTF-8 sequence starting at s[i], or 0 when it is not valid (overlongs, surrogates and
// code points above U+10FFFF are invalid too, as RFC 3629 says).
std::size_t utf8_sequence_length(std::string_view s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = byte(i);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) return 1;
    if ((c & 0xE0) == 0xC0) {
        n = 2;
        cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
        n = 3;
        cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
        n = 4;
        cp = c & 0x07;
    } else
        return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (byte(i + k) & 0x3F);
    }
    static constexpr std::uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < kMin[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;
    return n;
}

}  // namespace

int http_status(ErrorCode code) {
    switch (code) {
        case ErrorCode::ParseError: return 400;
        case ErrorCode::InvalidArgument:
        case ErrorCode::IndexOutOfRange:
        case ErrorCode::DegenerateFace:
        case ErrorCode::NonFinite:
        case ErrorCode::NotTriangleMesh:
        case ErrorCode::NonManifold:
        case ErrorCode::BudgetExceeded:
        case ErrorCode::Unsupported: return 422;
        // The work was abandoned by its deadline or a shutdown: the request itself may succeed later or elsewhere.
        case ErrorCode::Cancelled: return 503;
        case ErrorCode::Internal: return 500;
    }
    return 500;
}

ApiError from_geo_error(const GeoError& error) {
    ApiError out;
    out.status = http_status(error.code);
    out.code = to_string(error.code);
    out.title = title_for(error.code);
    out.detail = error.message;
    if (error.line >= 0) out.line = error.line;
    if (error.offset >= 0) out.offset = error.offset;
    return out;
}

ApiError make_problem(Problem problem, std::string detail, std::optional<std::string> field) {
    const ProblemInfo i = info(problem);
    ApiError out;
    out.status = i.status;
    out.code = i.code;
    out.title = i.title;
    out.detail = std::move(detail);
    out.field = std::move(field);
    return out;
}

ApiError make_transport_problem(int status, std::string detail) {
    ApiError out;
    out.status = status;
    out.code = "http_" + std::to_string(status);
    out.title = "HTTP error " + std::to_string(status);
    out.detail = std::move(detail);
    return out;
}

std::string json_quote(std::string_view text) {
    std::string out;
    out.reserve(text.size() + 2);
    out += '"';
    for (std::size_t i = 0; i < text.size();) {
        const char c = text[i];
        const std::size_t n = utf8_sequence_length(text, i);
        if (n == 0) {
            out += "\\ufffd";
            ++i;
            continue;
        }
        if (n > 1) {
            out.append(text.substr(i, n));
            i += n;
            continue;
        }
        switch (c) {
            case '"': out += "\\\""; break;
            case '\\': out += "\\\\"; break;
            case '\n': out += "\\n"; break;
            case '\r': out += "\\r"; break;
            case '\t': out += "\\t"; break;
            default:
                if (static_cast<unsigned char>(c) < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
                    out += buf;
                } else {
                    out += c;
                }
        }
        ++i;
    }
    out += '"';
    return out;
}

std::string to_problem_json(const ApiError& error) {
    std::string out = "{\"type\":" + json_quote("/problems/" + error.code);
    out += ",\"title\":" + json_quote(error.title);
    out += ",\"status\":" + std::to_string(error.status);
    out += ",\"detail\":" + json_quote(error.detail);
    out += ",\"code\":" + json_quote(error.code);
    if (error.field) out += ",\"field\":" + json_quote(*error.field);
    if (error.line) out += ",\"line\":" + std::to_string(*error.line);
    if (error.offset) out += ",\"offset\":" + std::to_string(*error.offset);
    if (error.hint) out += ",\"hint\":" + json_quote(*error.hint);
    out += "}";
    return out;
}

}  // namespace surfaced::api
