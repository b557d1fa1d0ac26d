// The GeoError -> status table and the RFC 9457 envelope.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "api/errors.h"
#include "api/operation.h"

namespace surfaced::api {
namespace {

TEST(Errors, GeoErrorStatusTable) {
    EXPECT_EQ(http_status(ErrorCode::ParseError), 400);
    for (ErrorCode code :
         {ErrorCode::IndexOutOfRange, ErrorCode::DegenerateFace, ErrorCode::NonFinite, ErrorCode::NotTriangleMesh,
          ErrorCode::NonManifold, ErrorCode::InvalidArgument, ErrorCode::BudgetExceeded, ErrorCode::Unsupported})
        EXPECT_EQ(http_status(code), 422) << to_string(code);
    EXPECT_EQ(http_status(ErrorCode::Internal), 500);
}

TEST(Errors, ApiProblemStatuses) {
    EXPECT_EQ(make_problem(Problem::InvalidJson, "x").status, 400);
    EXPECT_EQ(make_problem(Problem::UnknownParameter, "x").status, 400);
    EXPECT_EQ(make_problem(Problem::NotFound, "x").status, 404);
    EXPECT_EQ(make_problem(Problem::MethodNotAllowed, "x").status, 405);
    EXPECT_EQ(make_problem(Problem::PayloadTooLarge, "x").status, 413);
    EXPECT_EQ(make_problem(Problem::UnsupportedMediaType, "x").status, 415);
    EXPECT_EQ(make_problem(Problem::BudgetExceeded, "x").status, 422);
    EXPECT_EQ(make_problem(Problem::Internal, "x").status, 500);
}

TEST(Errors, GeoErrorKeepsLineAndOffset) {
    const ApiError e = from_geo_error(make_error(ErrorCode::ParseError, "line 12: expected a number", 12, -1));
    EXPECT_EQ(e.status, 400);
    EXPECT_EQ(e.code, "parse_error");
    EXPECT_EQ(e.line, 12);
    EXPECT_FALSE(e.offset.has_value());
    EXPECT_EQ(e.detail, "line 12: expected a number");
}

TEST(Errors, ProblemJsonShape) {
    ApiError e = make_problem(Problem::InvalidField, "mesh.faces[12][3] must be \"an integer\"\n", "mesh.faces[12][3]");
    e.line = 3;
    const ApiResponse response = error_response(e);
    EXPECT_EQ(response.status, 400);
    EXPECT_EQ(response.content_type, "application/problem+json");
    ASSERT_TRUE(response.error.has_value());

    const auto json = nlohmann::json::parse(response.body);
    EXPECT_EQ(json["type"], "/problems/invalid_field");
    EXPECT_EQ(json["status"], 400);
    EXPECT_EQ(json["code"], "invalid_field");
    EXPECT_EQ(json["title"], e.title);
    EXPECT_EQ(json["detail"], e.detail);
    EXPECT_EQ(json["field"], "mesh.faces[12][3]");
    EXPECT_EQ(json["line"], 3);
    EXPECT_FALSE(json.contains("offset"));
    EXPECT_FALSE(json.contains("hint"));
    e.hint = "scheme \"catmull-clark\" takes any polygons";
    EXPECT_EQ(nlohmann::json::parse(error_response(e).body)["hint"], *e.hint);  // quoted as JSON
}

TEST(Errors, JsonQuoteNeverEmitsInvalidJson) {
    const std::string bad = std::string("a\x01") + "\xff\xfe" + "\xc3\xa9" + "\xed\xa0\x80" + "\"";
    const std::string quoted = json_quote(bad);
    const auto json = nlohmann::json::parse(quoted);  // throws on invalid UTF-8 or escapes
    EXPECT_EQ(json.get<std::string>(), "a\x01\xef\xbf\xbd\xef\xbf\xbd\xc3\xa9\xef\xbf\xbd\xef\xbf\xbd\xef\xbf\xbd\"");
}

}  // namespace
}  // namespace surfaced::api
