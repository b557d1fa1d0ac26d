// Uploads as multipart/form-data (HTML forms, curl -F) and the output format chosen by the Accept header, over a real
// loopback socket: cpp-httplib's client writes the forms, the server hands the raw body to the API's parser.
#include <gtest/gtest.h>

#include <unistd.h>

#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

using Json = nlohmann::json;
using testing::expect_http_problem;

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

constexpr std::size_t kBodyLimit = 1 << 20;

class MultipartHttp : public testing::SharedServerTest<MultipartHttp> {
public:
    static ServerConfig suite_config() {
        ServerConfig config = SharedServerTest::suite_config();
        config.limits.max_body_bytes = kBodyLimit;
        return config;
    }

protected:
    static httplib::Client client() { return server_->client(20); }
};

//! The cube as the file part, as curl -F file=@cube.obj sends it (curl does not know .obj: octet-stream).
httplib::MultipartFormDataItems cube_form(httplib::MultipartFormDataItems fields = {}) {
    fields.push_back({"file", kCubeObj, "cube.obj", "application/octet-stream"});
    return fields;
}

TEST_F(MultipartHttp, FormGivesTheSameMeshAsTheQueryForm) {
    for (const char* path : {"/subdivide", "/remesh", "/repair", "/simplify"}) {
        SCOPED_TRACE(path);
        httplib::MultipartFormDataItems fields{{"format", "obj", "", ""}};
        std::string query = "?format=obj";
        if (std::string(path) == "/subdivide") {
            fields.push_back({"levels", "2", "", ""});
            query += "&levels=2";
        } else if (std::string(path) == "/simplify") {
            fields.push_back({"ratio", "0.5", "", ""});
            query += "&ratio=0.5";
        } else if (std::string(path) == "/remesh") {
            fields.push_back({"edge_length", "0.5", "", ""});
            query += "&edge_length=0.5";
        }
        auto by_form = client().Post(path, cube_form(fields));
        auto by_query = client().Post(std::string(path) + query, kCubeObj, "model/obj");
        ASSERT_TRUE(by_form && by_query);
        ASSERT_EQ(by_form->status, 200) << by_form->body;
        ASSERT_EQ(by_query->status, 200) << by_query->body;
        EXPECT_EQ(by_form->get_header_value("Content-Type"), "model/obj");
        EXPECT_EQ(by_form->body, by_query->body);
        EXPECT_EQ(by_form->get_header_value("X-Output-Faces"), by_query->get_header_value("X-Output-Faces"));
    }
    auto subdivided = client().Post("/subdivide", cube_form({{"levels", "2", "", ""}, {"format", "obj", "", ""}}));
    ASSERT_TRUE(subdivided);
    EXPECT_EQ(subdivided->get_header_value("X-Output-Faces"), "96");  // 6 quads x 4^2
}

TEST_F(MultipartHttp, FieldsAreCheckedAsQueryParameters) {
    expect_http_problem(client().Post("/subdivide", cube_form({{"levels", "99", "", ""}})), 422, "budget_exceeded",
                        "levels");
    const Json range = expect_http_problem(client().Post("/subdivide", cube_form({{"levels", "-1", "", ""}})), 400,
                                           "invalid_field", "levels");
    EXPECT_NE(range.value("detail", "").find("got -1"), std::string::npos) << range.dump();
    const Json typo = expect_http_problem(client().Post("/simplify", cube_form({{"rati", "0.5", "", ""}})), 400,
                                          "unknown_parameter", "rati");
    EXPECT_NE(typo.value("detail", "").find("did you mean \"ratio\""), std::string::npos) << typo.dump();
    const Json both = expect_http_problem(client().Post("/subdivide?levels=1", cube_form({{"levels", "2", "", ""}})),
                                          400, "invalid_field", "levels");
    EXPECT_NE(both.value("detail", "").find("both as a query parameter and as a form field"), std::string::npos);
}

TEST_F(MultipartHttp, FilePartsAndFramingErrorsAreNamed) {
    httplib::MultipartFormDataItems two = cube_form();
    two.push_back({"second", kCubeObj, "again.obj", "model/obj"});
    const Json twice = expect_http_problem(client().Post("/subdivide", two), 400, "malformed_multipart");
    EXPECT_NE(twice.value("detail", "").find("two file parts, \"file\" and \"second\""), std::string::npos);
    const Json none =
        expect_http_problem(client().Post("/subdivide", httplib::MultipartFormDataItems{{"levels", "1", "", ""}}), 400,
                            "malformed_multipart");
    EXPECT_NE(none.value("detail", "").find("no file part"), std::string::npos);

    // a body framed with another boundary than the Content-Type's, and a Content-Type without one
    const std::string body =
        std::string("--real\r\nContent-Disposition: form-data; name=\"file\"; filename=\"c.obj\"") + "\r\n\r\n" +
        kCubeObj + "\r\n--real--\r\n";
    const Json wrong = expect_http_problem(client().Post("/subdivide", body, "multipart/form-data; boundary=claimed"),
                                           400, "malformed_multipart");
    EXPECT_NE(wrong.value("detail", "").find("\"--claimed\""), std::string::npos) << wrong.dump();
    const Json missing =
        expect_http_problem(client().Post("/subdivide", body, "multipart/form-data"), 400, "malformed_multipart");
    EXPECT_NE(missing.value("detail", "").find("no boundary"), std::string::npos) << missing.dump();
    const Json cut = expect_http_problem(
        client().Post("/subdivide", body.substr(0, body.size() - 12), "multipart/form-data; boundary=real"), 400,
        "malformed_multipart");
    EXPECT_NE(cut.value("detail", "").find("not ended by a delimiter"), std::string::npos) << cut.dump();
}

TEST_F(MultipartHttp, TheWholeFormIsWithinTheBodyLimit) {
    // a form declared one byte over the limit is refused from its head, before its body is read
    const int fd = testing::connect_to(server_->port());
    ASSERT_GE(fd, 0);
    ASSERT_TRUE(testing::send_all_text(fd,
                                       "POST /subdivide HTTP/1.1\r\nHost: test\r\n"
                                       "Content-Type: multipart/form-data; boundary=b\r\nContent-Length: " +
                                           std::to_string(kBodyLimit + 1) + "\r\n\r\n--b\r\n"));
    const std::string answer = testing::read_one_response(fd, 10'000);
    close(fd);
    EXPECT_EQ(testing::status_of(answer), 413) << answer;
    EXPECT_EQ(Json::parse(testing::body_of(answer), nullptr, false).value("code", ""), "payload_too_large") << answer;
    // a form just under the limit is read whole
    std::string fits = kCubeObj;
    while (fits.size() < kBodyLimit - 4096) fits += "# padding padding padding padding padding padding padding\n";
    auto read = client().Post("/subdivide", httplib::MultipartFormDataItems{{"file", fits, "fits.obj", ""}});
    ASSERT_TRUE(read);
    EXPECT_EQ(read->status, 200) << read->body.substr(0, 300);
    EXPECT_EQ(read->get_header_value("X-Input-Faces"), "6");
}

TEST_F(MultipartHttp, AcceptPicksTheFormatAnExplicitOneWins) {
    auto obj = client().Post("/subdivide", {{"Accept", "model/obj"}}, cube_form());
    ASSERT_TRUE(obj);
    EXPECT_EQ(obj->status, 200);
    EXPECT_EQ(obj->get_header_value("Content-Type"), "model/obj");
    EXPECT_NE(obj->body.find("\nv "), std::string::npos) << obj->body.substr(0, 100);
    EXPECT_NE(obj->body.find("\nf "), std::string::npos) << obj->body.substr(0, 100);

    auto raw = client().Post("/subdivide", {{"Accept", "application/ply;q=0.4, application/json;q=0.9"}}, kCubeObj,
                             "model/obj");
    ASSERT_TRUE(raw);
    EXPECT_EQ(raw->get_header_value("Content-Type"), "application/json");
    EXPECT_TRUE(Json::parse(raw->body).contains("mesh")) << raw->body.substr(0, 100);

    auto any = client().Post("/subdivide", {{"Accept", "*/*"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(any);
    EXPECT_EQ(any->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_EQ(any->body.substr(0, 4), "glTF");

    auto named = client().Post("/subdivide?format=ply", {{"Accept", "model/obj"}}, kCubeObj, "model/obj");
    ASSERT_TRUE(named);
    EXPECT_EQ(named->get_header_value("Content-Type"), "application/ply");
    auto named_field = client().Post("/subdivide", {{"Accept", "text/html"}}, cube_form({{"format", "ply", "", ""}}));
    ASSERT_TRUE(named_field);
    EXPECT_EQ(named_field->status, 200) << named_field->body;
    EXPECT_EQ(named_field->get_header_value("Content-Type"), "application/ply");

    const Json refused = expect_http_problem(
        client().Post("/subdivide", {{"Accept", "text/html"}}, kCubeObj, "model/obj"), 406, "not_acceptable");
    const std::string detail = refused.value("detail", "");
    for (const char* type :
         {"model/gltf-binary", "model/gltf+json", "model/obj", "application/ply", "application/json"})
        EXPECT_NE(detail.find(type), std::string::npos) << type << " in " << detail;
    // the point cloud endpoint offers its own formats
    const Json points = expect_http_problem(
        client().Post("/pointcloud", {{"Accept", "model/obj"}}, "0 0 0\n1 0 0\n0 1 0\n", "text/x-xyz"), 406,
        "not_acceptable");
    EXPECT_NE(
        points.value("detail", "").find("with: model/gltf-binary, model/gltf+json, application/ply, application/json"),
        std::string::npos)
        << points.dump();
    // a JSON-only answer is unaffected
    auto query = client().Post("/implicit/query", {{"Accept", "text/html"}},
                               R"({"scene":{"op":"sphere","radius":1},"points":[[0,0,0]]})", "application/json");
    ASSERT_TRUE(query);
    EXPECT_EQ(query->status, 200) << query->body;
    EXPECT_EQ(query->get_header_value("Content-Type"), "application/json");
    // /curves answers json, glb or gltf: Accept picks among them when the body names no output.format
    const std::string curve = R"({"points":[[0,0],[1,2],[3,2],[4,0]],"tessellate":{"tolerance":0.01})";
    auto glb = client().Post("/curves", {{"Accept", "model/gltf-binary"}}, curve + "}", "application/json");
    ASSERT_TRUE(glb);
    EXPECT_EQ(glb->status, 200) << glb->body;
    EXPECT_EQ(glb->get_header_value("Content-Type"), "model/gltf-binary");
    auto named_json = client().Post("/curves", {{"Accept", "model/gltf-binary"}},
                                    curve + R"(,"output":{"format":"json"}})", "application/json");
    ASSERT_TRUE(named_json);
    EXPECT_EQ(named_json->get_header_value("Content-Type"), "application/json");
    expect_http_problem(client().Post("/curves", {{"Accept", "text/html"}}, curve + "}", "application/json"), 406,
                        "not_acceptable");
}

TEST_F(MultipartHttp, PatchSampleFollowsAcceptAndSaysSo) {
    auto obj = client().Get("/patches/teapot?segments=2", {{"Accept", "model/obj"}});
    ASSERT_TRUE(obj);
    EXPECT_EQ(obj->status, 200);
    EXPECT_EQ(obj->get_header_value("Content-Type"), "model/obj");
    EXPECT_EQ(obj->get_header_value("Vary"), "Accept");
    auto glb = client().Get("/patches/teapot?segments=2");
    ASSERT_TRUE(glb);
    EXPECT_EQ(glb->get_header_value("Content-Type"), "model/gltf-binary");
    EXPECT_NE(glb->get_header_value("ETag"), obj->get_header_value("ETag"));
}

// POST /mesh/query over HTTP with the mesh as a file part and the rest of the body as the JSON part "request": the
// answer of the same question sent as one JSON body; a missing part is named.
TEST_F(MultipartHttp, MeshQueryTakesTheMeshAsAFilePart) {
    const std::string request = R"({"points": [[0, 0, 0], [2, 0, 0]], "want": ["inside", "distance"]})";
    auto form = client().Post("/mesh/query", cube_form({{"request", request, "query.json", "application/json"}}));
    ASSERT_TRUE(form) << httplib::to_string(form.error());
    ASSERT_EQ(form->status, 200) << form->body;
    const auto answer = nlohmann::json::parse(form->body);
    EXPECT_EQ(answer["points"]["inside"], nlohmann::json::parse("[true, false]"));
    EXPECT_EQ(answer["points"]["distance"], nlohmann::json::parse("[-0.5, 1.5]"));
    expect_http_problem(client().Post("/mesh/query", cube_form()), 400, "malformed_multipart");
}

}  // namespace
}  // namespace surfaced::server
