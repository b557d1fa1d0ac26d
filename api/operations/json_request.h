// What the operations whose request is a JSON document of queries share (POST /curves, /surfaces, /mesh/query,
// /implicit/query, /limit/evaluate): budget and geometry errors that name the request's field, the optional switch
// queries, and the JSON answer. Internal to api/operations (includes nlohmann through api/json_util.h).
#pragma once

#include <string>

#include "api/errors.h"
#include "api/json_util.h"
#include "api/operation.h"
#include "geometry/core/result.h"

namespace surfaced::api::operations {

//! 422 budget_exceeded about the request's `field`.
ApiError budget(std::string detail, const std::string& field);

//! A geometry error about the request's `field`.
ApiError error_at(const GeoError& error, const std::string& field);

//! The switch query `name` of the request's root: false when absent, else its boolean (400 when not one).
ApiResult<bool> read_switch(const json::Json& root, const char* name);

//! A 200 answer of `out` as JSON (numbers written as every output writes them: geometry/io/json_text.h).
ApiResponse json_response(const json::Json& out);

}  // namespace surfaced::api::operations
