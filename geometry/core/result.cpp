#include "geometry/core/result.h"

namespace surfaced {

const char* to_string(ErrorCode code) {
    switch (code) {
        case ErrorCode::InvalidArgument: return "invalid_argument";
        case ErrorCode::ParseError: return "parse_error";
        case ErrorCode::IndexOutOfRange: return "index_out_of_range";
        case ErrorCode::DegenerateFace: return "degenerate_face";
        case ErrorCode::NonFinite: return "non_finite";
        case ErrorCode::NotTriangleMesh: return "not_triangle_mesh";
        case ErrorCode::NonManifold: return "non_manifold";
        case ErrorCode::BudgetExceeded: return "budget_exceeded";
        case ErrorCode::Unsupported: return "unsupported";
        case ErrorCode::Cancelled: return "cancelled";
        case ErrorCode::Internal: return "internal";
    }
    return "unknown";
}

}  // namespace surfaced
