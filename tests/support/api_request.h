// What the in-process operation tests (tests/api/*_test.cpp) share: JSON mesh bodies, requests and contexts built
// without sockets, response headers, and problem+json checks. Header-only; `using namespace fixtures;` in a test's
// anonymous namespace brings them in.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/operation.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced::api::fixtures {

//! {"positions": [[x, y, z], ...], "faces": [[i, j, k, ...], ...]} of `mesh`.
inline std::string mesh_json(const PolygonMesh& mesh) {
    nlohmann::json positions = nlohmann::json::array(), faces = nlohmann::json::array();
    for (const Vec3& p : mesh.positions) positions.push_back({p.x, p.y, p.z});
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto face = mesh.face(f);
        faces.push_back(std::vector<Index>(face.begin(), face.end()));
    }
    return nlohmann::json{{"positions", positions}, {"faces", faces}}.dump();
}

//! {"mesh": <mesh>, <extra members>}
inline std::string json_request(const PolygonMesh& mesh, const std::string& extra = "") {
    return R"({"mesh":)" + mesh_json(mesh) + extra + "}";
}

//! A request as the HTTP layer would hand it to an operation. `body` is not copied: it must outlive the request.
inline ApiRequest make_request(std::string method, std::string path, std::string content_type = "",
                               std::string_view body = {}, std::multimap<std::string, std::string> query = {}) {
    ApiRequest request;
    request.method = std::move(method);
    request.path = std::move(path);
    request.content_type = std::move(content_type);
    request.body = body;
    request.query = std::move(query);
    return request;
}

inline ApiContext context_with(const Limits& limits = {}, const Cancel& cancel = {}) {
    ApiContext context;
    context.limits = limits;
    context.cancel = cancel;
    return context;
}

//! The value of response header `name`, "" when there is none.
inline std::string header(const ApiResponse& response, std::string_view name) {
    for (const auto& [key, value] : response.headers)
        if (key == name) return value;
    return "";
}

//! Checks status, code and that the body is the matching problem+json with a detail; returns the parsed body.
inline nlohmann::json expect_problem(const ApiResponse& response, int status, const std::string& code) {
    EXPECT_EQ(response.status, status) << response.body;
    EXPECT_EQ(response.content_type, "application/problem+json");
    EXPECT_TRUE(response.error.has_value());
    auto json = nlohmann::json::parse(response.body, nullptr, false);
    EXPECT_FALSE(json.is_discarded()) << response.body;
    if (json.is_discarded()) return {};
    EXPECT_EQ(json.value("status", 0), status) << response.body;
    EXPECT_EQ(json.value("code", ""), code) << response.body;
    EXPECT_FALSE(json.value("detail", "").empty());
    return json;
}

//! Checks status, code and the field path the error names (not checked when `field` is "").
inline void expect_problem(const ApiResponse& response, int status, const std::string& code, const std::string& field) {
    EXPECT_EQ(response.status, status) << response.body;
    EXPECT_EQ(response.content_type, "application/problem+json");
    ASSERT_TRUE(response.error.has_value()) << response.body;
    EXPECT_EQ(response.error->code, code) << response.body;
    if (!field.empty()) {
        EXPECT_EQ(response.error->field.value_or("<none>"), field) << response.body;
    }
}

}  // namespace surfaced::api::fixtures
