// The OpenAPI 3.1 description of every endpoint (api/openapi.json, compiled in). Tests keep it in step with the
// route table and validate it against the OpenAPI schema.
#pragma once

#include <string_view>

#include "api/operation.h"

namespace surfaced::api {

std::string_view openapi_document();

//! GET /openapi.json
ApiResponse openapi(const ApiRequest& request, const ApiContext& context) noexcept;

}  // namespace surfaced::api
