#include "api/operations/json_request.h"

#include <utility>

namespace surfaced::api::operations {

ApiError budget(std::string detail, const std::string& field) {
    return make_problem(Problem::BudgetExceeded, std::move(detail), field);
}

ApiError error_at(const GeoError& error, const std::string& field) {
    ApiError out = from_geo_error(error);
    out.field = field;
    return out;
}

ApiResult<bool> read_switch(const json::Json& root, const char* name) {
    const auto it = root.find(name);
    if (it == root.end()) return false;
    return json::read_bool(*it, name);
}

ApiResponse json_response(const json::Json& out) {
    ApiResponse response;
    response.content_type = "application/json";
    response.body = json_text(out);
    return response;
}

}  // namespace surfaced::api::operations
