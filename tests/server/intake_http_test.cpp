// How the server answers requests whose body is unusual, over a real loopback socket: form media types (which
// cpp-httplib would otherwise decode itself), a missing or empty body, a body longer than the limit, a method the
// route does not take, numbers and coordinates out of range. Each is answered at once with a problem+json naming
// what is wrong; waits are bounds for a stuck test, not timing assertions.
#include <gtest/gtest.h>

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <utility>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

using Json = nlohmann::json;
using testing::body_of;
using testing::connect_to;
using testing::expect_http_problem;
using testing::raw_header;
using testing::read_one_response;
using testing::send_all_text;
using testing::status_of;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

//! An OBJ over `bytes` long: the cube, padded with comment lines.
std::string obj_of_size(std::size_t bytes) {
    std::string out = kCubeObj;
    while (out.size() <= bytes) out += "# padding padding padding padding padding padding padding padding\n";
    return out;
}

class IntakeHttp : public testing::SharedServerTest<IntakeHttp> {
public:
    static int port() { return server_->port(); }
    static ServerConfig suite_config() {
        ServerConfig config = SharedServerTest::suite_config();
        config.limits.max_body_bytes = 1 << 20;
        // Far beyond the tests' read bounds (10 s): an answer that waits for a body that never comes fails them.
        config.body_timeout_seconds = 120;
        config.read_timeout_seconds = 120;
        return config;
    }

protected:
    static httplib::Client client() { return SharedServerTest::client(20); }
};

//! Sends `head` (request line and headers, without the blank line) and `body` on a new connection; the response.
std::string exchange(const std::string& head, const std::string& body = {}) {
    const int fd = connect_to(IntakeHttp::port());
    EXPECT_GE(fd, 0);
    if (fd < 0) return {};
    EXPECT_TRUE(send_all_text(fd, head + "\r\n\r\n" + body));
    std::string answer = read_one_response(fd);
    close(fd);
    return answer;
}

//! A POST of `body` with Content-Length and no Content-Type: its status and problem.
std::pair<int, Json> post_without_type(const std::string& path, const std::string& body) {
    const std::string answer =
        exchange("POST " + path + " HTTP/1.1\r\nHost: test\r\nContent-Length: " + std::to_string(body.size()), body);
    return {status_of(answer), Json::parse(body_of(answer), nullptr, false)};
}

//! The JSON body of a raw response (discarded when it is not JSON).
Json problem_of(const std::string& answer) { return Json::parse(body_of(answer), nullptr, false); }

//! The problem's detail, after checking it is a 415 naming each of `types`.
void expect_415_naming(const httplib::Result& res, std::initializer_list<const char*> types) {
    const Json problem = expect_http_problem(res, 415, "unsupported_media_type");
    const std::string detail = problem.value("detail", "");
    for (const char* type : types) EXPECT_NE(detail.find(type), std::string::npos) << type << " in " << detail;
}

// curl -d / --data-binary sends application/x-www-form-urlencoded. cpp-httplib decodes such bodies into query
// parameters and refused one over 8 KiB with 413; the server reads it as bytes and answers 415 with the endpoint's
// accepted types, for any size below the body limit.
TEST_F(IntakeHttp, FormEncodedBodyIs415WithTheEndpointsTypesAtAnySize) {
    for (const std::size_t size : {std::size_t{20}, std::size_t{9000}, std::size_t{200'000}}) {
        SCOPED_TRACE(size);
        const std::string body = obj_of_size(size);
        expect_415_naming(
            client().Post("/subdivide", body, "application/x-www-form-urlencoded"),
            {"application/x-www-form-urlencoded", "application/json", "model/obj", "model/stl", "multipart/form-data"});
        expect_415_naming(client().Post("/pointcloud", body, "application/x-www-form-urlencoded"),
                          {"application/json", "application/ply", "text/x-xyz"});
        expect_415_naming(client().Post("/tessellate", body, "application/x-www-form-urlencoded; charset=utf-8"),
                          {"application/json", "application/x-geomview-bez"});
        expect_415_naming(client().Post("/curves", body, "Application/X-WWW-Form-Urlencoded"), {"application/json"});
    }
}

// multipart/form-data (curl -F) reaches the API as sent (cpp-httplib would decode it into files, leaving the body
// empty): the upload endpoints read it (tests/server/multipart_http_test.cpp), a JSON-only endpoint answers 415.
TEST_F(IntakeHttp, MultipartFormBodyIs415ForAJsonOnlyEndpoint) {
    httplib::MultipartFormDataItems items{{"file", kCubeObj, "cube.obj", "model/obj"}};
    expect_415_naming(client().Post("/curves", items), {"multipart/form-data", "application/json"});
}

// Without a Content-Type, the 415 lists what this endpoint accepts (not the mesh types for every endpoint).
TEST_F(IntakeHttp, BodyWithoutContentTypeIs415WithTheEndpointsTypes) {
    for (const std::size_t size : {std::size_t{20}, std::size_t{9000}}) {
        SCOPED_TRACE(size);
        const std::string body = obj_of_size(size);
        const auto [mesh_status, mesh] = post_without_type("/subdivide", body);
        EXPECT_EQ(mesh_status, 415) << mesh.dump();
        EXPECT_NE(mesh.value("detail", "").find("model/obj"), std::string::npos) << mesh.dump();
        const auto [points_status, points] = post_without_type("/pointcloud", body);
        EXPECT_EQ(points_status, 415) << points.dump();
        EXPECT_NE(points.value("detail", "").find("text/x-xyz"), std::string::npos) << points.dump();
        EXPECT_EQ(points.value("detail", "").find("model/stl"), std::string::npos) << points.dump();
        const auto [query_status, query] = post_without_type("/implicit/query", body);
        EXPECT_EQ(query_status, 415) << query.dump();
        EXPECT_NE(query.value("detail", "").find("application/json"), std::string::npos) << query.dump();
        EXPECT_EQ(query.value("detail", "").find("model/obj"), std::string::npos) << query.dump();
    }
}

// A POST with neither Content-Length nor Transfer-Encoding has an empty body (RFC 9112 section 6.3). cpp-httplib
// read such a body until the client closed, which ended in 408 after the body timeout; it is answered at once, 400
// empty_body, and the connection serves the next request.
TEST_F(IntakeHttp, PostWithoutBodyOrLengthIsAnsweredAtOnce) {
    for (const char* path : {"/subdivide", "/simplify", "/remesh", "/repair", "/tessellate", "/curves",
                             "/implicit/query", "/mesh/query", "/pointcloud", "/implicit/mesh"}) {
        SCOPED_TRACE(path);
        const int fd = connect_to(port());
        ASSERT_GE(fd, 0);
        ASSERT_TRUE(send_all_text(
            fd, std::string("POST ") + path + " HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\n\r\n"));
        const std::string answer = read_one_response(fd, 10'000);
        EXPECT_EQ(status_of(answer), 400) << answer;
        const Json problem = problem_of(answer);
        EXPECT_EQ(problem.value("code", ""), "empty_body") << answer;
        EXPECT_NE(problem.value("detail", "").find("empty"), std::string::npos) << answer;
        // the connection is still usable
        ASSERT_TRUE(send_all_text(fd, "GET /livez HTTP/1.1\r\nHost: test\r\n\r\n"));
        EXPECT_EQ(status_of(read_one_response(fd, 10'000)), 200);
        close(fd);
    }
}

// An explicit empty body is the same 400, whatever the Content-Type (or none).
TEST_F(IntakeHttp, EmptyBodyIs400EmptyBody) {
    expect_http_problem(client().Post("/subdivide", "", "model/obj"), 400, "empty_body");
    expect_http_problem(client().Post("/simplify?target_faces=4", "", "model/obj"), 400, "empty_body");
    expect_http_problem(client().Post("/curves", "", "application/json"), 400, "empty_body");
    const auto [status, problem] = post_without_type("/pointcloud", "");
    EXPECT_EQ(status, 400) << problem.dump();
    EXPECT_EQ(problem.value("code", ""), "empty_body") << problem.dump();
}

// A method the route does not take is refused from the head, before any body is read: 405 with Allow (404 for no
// route at all), and the connection closed since the body was not read.
TEST_F(IntakeHttp, WrongMethodIsRefusedBeforeTheBody) {
    const std::string teapot = exchange(
        "POST /patches/teapot HTTP/1.1\r\nHost: test\r\nContent-Type: application/json\r\nContent-Length: 50000");
    EXPECT_EQ(status_of(teapot), 405) << teapot;
    EXPECT_EQ(raw_header(teapot, "Allow"), "GET, HEAD");
    EXPECT_EQ(raw_header(teapot, "Connection"), "close");
    EXPECT_EQ(problem_of(teapot).value("code", ""), "method_not_allowed") << teapot;

    const std::string put = exchange("PUT /subdivide HTTP/1.1\r\nHost: test\r\nContent-Length: 50000");
    EXPECT_EQ(status_of(put), 405) << put;
    EXPECT_EQ(raw_header(put, "Allow"), "POST");

    const std::string nowhere = exchange("POST /nowhere HTTP/1.1\r\nHost: test\r\nContent-Length: 50000");
    EXPECT_EQ(status_of(nowhere), 404) << nowhere;
    EXPECT_EQ(problem_of(nowhere).value("code", ""), "not_found") << nowhere;

    // without a body the connection stays open, as for any answer
    const std::string empty = exchange("POST /patches/teapot HTTP/1.1\r\nHost: test\r\nContent-Length: 0");
    EXPECT_EQ(status_of(empty), 405) << empty;
    EXPECT_EQ(raw_header(empty, "Connection"), "");
}

// A Content-Length over the limit is 413 at once, without waiting for (or reading) the body, and the connection is
// closed: no Keep-Alive.
TEST_F(IntakeHttp, DeclaredBodyOverTheLimitIs413AtOnce) {
    const int fd = connect_to(port());
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(send_all_text(fd,
                              "POST /subdivide HTTP/1.1\r\nHost: test\r\nContent-Type: model/obj\r\n"
                              "Content-Length: 1048577\r\n\r\nv 0 0 0\n"));
    const std::string answer = read_one_response(fd, 10'000);
    EXPECT_EQ(status_of(answer), 413) << answer;
    EXPECT_EQ(raw_header(answer, "Connection"), "close");
    EXPECT_EQ(raw_header(answer, "Keep-Alive"), "");
    const Json problem = problem_of(answer);
    EXPECT_EQ(problem.value("code", ""), "payload_too_large") << answer;
    EXPECT_NE(problem.value("detail", "").find("1048577"), std::string::npos) << answer;
    EXPECT_EQ(testing::read_until_close(fd, 10'000), "");  // closed by the server
    close(fd);
}

// A 408 closes the connection and says so: Connection: close and no Keep-Alive, with or without other clients.
TEST(IntakeTimeout, BodyTimeoutClosesTheConnection) {
    ServerConfig config;
    config.threads = 2;
    config.web_root = "";
    config.body_timeout_seconds = 1;
    testing::LoopbackServer s(config);
    ASSERT_TRUE(s.started());
    const int fd = connect_to(s.port());
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(send_all_text(
        fd, "POST /subdivide HTTP/1.1\r\nHost: test\r\nContent-Type: model/obj\r\nContent-Length: 10\r\n\r\nv 0"));
    const std::string answer = read_one_response(fd);
    EXPECT_EQ(status_of(answer), 408) << answer;
    EXPECT_EQ(raw_header(answer, "Connection"), "close");
    EXPECT_EQ(raw_header(answer, "Keep-Alive"), "");
    EXPECT_EQ(problem_of(answer).value("code", ""), "body_timeout") << answer;
    EXPECT_EQ(testing::read_until_close(fd, 10'000), "");
    close(fd);
}

// A JSON number beyond a double is 400 number_out_of_range with its position; no problem detail carries a
// library's exception text.
TEST_F(IntakeHttp, JsonNumberOutOfRangeIs400WithItsPosition) {
    const std::string mesh = "{\"mesh\":{\"positions\":[[0,0,0],[1,0,0],\n[0,1e400,0]],\"faces\":[[0,1,2]]}}";
    const Json subdivide =
        expect_http_problem(client().Post("/subdivide", mesh, "application/json"), 400, "number_out_of_range");
    EXPECT_EQ(subdivide.value("offset", -1), static_cast<int>(mesh.find("1e400"))) << subdivide.dump();
    EXPECT_NE(subdivide.value("detail", "").find("line 2, column 4"), std::string::npos) << subdivide.dump();
    EXPECT_NE(subdivide.value("detail", "").find("1e400"), std::string::npos) << subdivide.dump();

    const std::string curve = R"({"points": [[0, 0, 0], [1, -1e400, 0]], "evaluate": [0.5]})";
    const Json curves =
        expect_http_problem(client().Post("/curves", curve, "application/json"), 400, "number_out_of_range");
    EXPECT_EQ(curves.value("offset", -1), static_cast<int>(curve.find("-1e400"))) << curves.dump();

    for (const char* path :
         {"/subdivide", "/curves", "/implicit/query", "/mesh/query", "/pointcloud", "/tessellate", "/repair"}) {
        for (const char* body : {R"({"a": 1e400})", R"({"a": x})", R"({"a": [1, 2)", "[1e999999999]"}) {
            SCOPED_TRACE(std::string(path) + " " + body);
            auto res = client().Post(path, body, "application/json");
            ASSERT_TRUE(res);
            EXPECT_EQ(res->status, 400) << res->body;
            const Json problem = Json::parse(res->body, nullptr, false);
            const std::string detail = problem.value("detail", "");
            EXPECT_EQ(detail.find("json.exception"), std::string::npos) << detail;
            EXPECT_EQ(detail.find("parse error"), std::string::npos) << detail;
            EXPECT_TRUE(problem.contains("offset")) << res->body;
        }
    }
}

// A coordinate beyond float32 cannot be written to glTF (an accessor's min/max would be null, Draco fails): 422
// coordinate_out_of_range naming the vertex, its field path when the mesh was JSON. Formats that keep doubles work.
TEST_F(IntakeHttp, CoordinateBeyondFloat32Is422ForGltfOutput) {
    const std::string mesh = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[1,1,0],[0,1e39,0]],"faces":[[0,1,2,3]]})";
    for (const char* output : {"", R"(,"output":{"compression":"none"})", R"(,"output":{"format":"gltf"})"}) {
        SCOPED_TRACE(output);
        const Json problem = expect_http_problem(client().Post("/subdivide", mesh + output + "}", "application/json"),
                                                 422, "coordinate_out_of_range", "mesh.positions[3]");
        EXPECT_NE(problem.value("detail", "").find("1e+39"), std::string::npos) << problem.dump();
    }
    auto obj = client().Post("/subdivide", mesh + R"(,"output":{"format":"obj"}})", "application/json");
    ASSERT_TRUE(obj);
    EXPECT_EQ(obj->status, 200) << obj->body;

    const Json upload = expect_http_problem(
        client().Post("/subdivide", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1e39 0\nf 1 2 3 4\n", "model/obj"), 422,
        "coordinate_out_of_range");
    EXPECT_NE(upload.value("detail", "").find("vertex 3"), std::string::npos) << upload.dump();

    const Json points = expect_http_problem(
        client().Post("/pointcloud", R"({"points":[[0,0,0],[1,0,0],[0,2e39,0]]})", "application/json"), 422,
        "coordinate_out_of_range", "points[2]");
    EXPECT_NE(points.value("detail", "").find("2e+39"), std::string::npos) << points.dump();
    const Json xyz = expect_http_problem(client().Post("/pointcloud", "0 0 0\n1 0 0\n0 2e39 0\n", "text/x-xyz"), 422,
                                         "coordinate_out_of_range");
    EXPECT_NE(xyz.value("detail", "").find("point 2"), std::string::npos) << xyz.dump();
}

// Coordinates within float32 whose extent is not (both signs near 3.4e38) cannot be quantized by Draco, which
// crashed on them: 422; without compression they are written, with finite accessor bounds.
TEST_F(IntakeHttp, ExtentBeyondFloat32Is422WithDraco) {
    const std::string mesh =
        R"({"mesh":{"positions":[[-3e38,0,0],[3e38,0,0],[3e38,3e38,0],[-3e38,3e38,0]],"faces":[[0,1,2,3]]})";
    const Json problem =
        expect_http_problem(client().Post("/subdivide", mesh + "}", "application/json"), 422, "invalid_argument");
    EXPECT_NE(problem.value("detail", "").find("compression none"), std::string::npos) << problem.dump();
    expect_http_problem(client().Post("/pointcloud", R"({"points":[[-3e38,0,0],[3e38,0,0]]})", "application/json"), 422,
                        "invalid_argument");

    auto plain =
        client().Post("/subdivide", mesh + R"(,"output":{"format":"gltf","compression":"none"}})", "application/json");
    ASSERT_TRUE(plain);
    ASSERT_EQ(plain->status, 200) << plain->body;
    const Json gltf = Json::parse(plain->body, nullptr, false);
    ASSERT_FALSE(gltf.is_discarded());
    for (const Json& bound : gltf["accessors"][0]["max"]) EXPECT_TRUE(bound.is_number()) << gltf["accessors"][0];
    EXPECT_EQ(client().Get("/livez")->status, 200);
}

}  // namespace
}  // namespace surfaced::server
