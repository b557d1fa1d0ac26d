// The multipart/form-data parser (api/multipart.h), the Accept negotiation (api/accept.h), and the form and Accept
// rules of the upload operations called in-process (the same requests over HTTP: tests/server/multipart_http_test).
#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/accept.h"
#include "api/multipart.h"
#include "api/operations/implicit_mesh.h"
#include "api/operations/pointcloud.h"
#include "api/operations/subdivide.h"
#include "api/operations/tessellate.h"
#include "tests/support/api_request.h"

namespace surfaced::api {
namespace {

using namespace fixtures;

constexpr std::string_view kBoundary = "XyZ-42";

//! A form with the parts given as (headers, content): each part's header lines as written, CRLF framed.
std::string form_of(const std::vector<std::pair<std::string, std::string>>& parts,
                    std::string_view boundary = kBoundary) {
    std::string out;
    for (const auto& [headers, content] : parts)
        out += "--" + std::string(boundary) + "\r\n" + headers + "\r\n\r\n" + content + "\r\n";
    return out + "--" + std::string(boundary) + "--\r\n";
}

std::string field(const std::string& name) { return "Content-Disposition: form-data; name=\"" + name + "\""; }

std::string file_header(const std::string& name, const std::string& filename, const std::string& type = "") {
    std::string out = "Content-Disposition: form-data; name=\"" + name + "\"; filename=\"" + filename + "\"";
    if (!type.empty()) out += "\r\nContent-Type: " + type;
    return out;
}

//! The problem of a failed parse, after checking it is 400 malformed_multipart; "" when it parsed.
std::string malformed_detail(std::string_view body, std::string_view boundary = kBoundary,
                             const MultipartLimits& limits = {}) {
    auto parts = parse_multipart(body, boundary, limits);
    if (parts) {
        ADD_FAILURE() << "parsed: " << body;
        return {};
    }
    EXPECT_EQ(parts.error().status, 400);
    EXPECT_EQ(parts.error().code, "malformed_multipart");
    return parts.error().detail;
}

TEST(Multipart, BoundaryFromTheContentType) {
    EXPECT_EQ(multipart_boundary("multipart/form-data; boundary=abc").value(), "abc");
    EXPECT_EQ(multipart_boundary("multipart/form-data;boundary=\"a b:c\"").value(), "a b:c");
    EXPECT_EQ(multipart_boundary("multipart/form-data; charset=utf-8; BOUNDARY=q1").value(), "q1");
    for (const char* bad : {"multipart/form-data", "multipart/form-data; boundary=", "multipart/form-data; boundary",
                            "multipart/form-data; boundary=\"unclosed", "multipart/form-data; boundary=a{b}",
                            "multipart/form-data; boundary=\"ends in a space \""}) {
        SCOPED_TRACE(bad);
        auto boundary = multipart_boundary(bad);
        ASSERT_FALSE(boundary.ok());
        EXPECT_EQ(boundary.error().code, "malformed_multipart");
        EXPECT_NE(boundary.error().detail.find("boundary"), std::string::npos) << boundary.error().detail;
    }
    EXPECT_FALSE(multipart_boundary("multipart/form-data; boundary=" + std::string(71, 'a')).ok());
    EXPECT_TRUE(multipart_boundary("multipart/form-data; boundary=" + std::string(70, 'a')).ok());
}

TEST(Multipart, PartsAreViewsOfTheirContent) {
    const std::string content = "v 0 0 0\r\nv 1 0 0\r\n\r\n--XyZ-4 is not the boundary\r\n";
    const std::string body = "preamble to ignore\r\n" +
                             form_of({{field("levels"), "2"},
                                      {file_header("file", "cube.obj", "model/obj"), content},
                                      {"content-disposition: FORM-DATA; filename=\"a\\\"b.ply\"; name=empty", ""}}) +
                             "epilogue to ignore";
    auto parts = parse_multipart(body, kBoundary);
    ASSERT_TRUE(parts.ok()) << parts.error().detail;
    const std::vector<MultipartPart>& p = parts.value();
    ASSERT_EQ(p.size(), 3u);
    EXPECT_EQ(p[0].name, "levels");
    EXPECT_FALSE(p[0].filename);
    EXPECT_EQ(p[0].body, "2");
    EXPECT_EQ(p[1].name, "file");
    EXPECT_EQ(p[1].filename.value_or("?"), "cube.obj");
    EXPECT_EQ(p[1].content_type, "model/obj");
    EXPECT_EQ(p[1].body, content);  // CRLFs and a near-boundary line inside the content are content
    EXPECT_GE(p[1].body.data(), body.data());
    EXPECT_LE(p[1].body.data() + content.size(), body.data() + body.size());
    EXPECT_EQ(p[2].name, "empty");
    EXPECT_EQ(p[2].filename.value_or("?"), "a\"b.ply");
    EXPECT_TRUE(p[2].body.empty());
}

TEST(Multipart, MalformedBodiesNameWhatIsWrong) {
    const std::string good = form_of({{field("levels"), "2"}});
    EXPECT_TRUE(parse_multipart(good, kBoundary).ok());
    // the boundary in Content-Type does not match the body's
    EXPECT_NE(malformed_detail(good, "other").find("no delimiter line \"--other\""), std::string::npos);
    // cut short: no close delimiter, or a part without its end
    EXPECT_NE(malformed_detail(good.substr(0, good.size() - 4)).find("close delimiter"), std::string::npos);
    EXPECT_NE(malformed_detail("--XyZ-42\r\n" + field("levels") + "\r\n\r\n2").find("part 1 (\"levels\") is not ended"),
              std::string::npos);
    // a delimiter followed by something else than CRLF or "--"
    EXPECT_NE(malformed_detail("--XyZ-42junk\r\n").find("instead of CRLF"), std::string::npos);
    // headers: no blank line, no Content-Disposition, not form-data, no name, a line without a colon, an encoding
    EXPECT_NE(malformed_detail("--XyZ-42\r\n" + field("a") + "\r\n").find("blank line"), std::string::npos);
    EXPECT_NE(malformed_detail(form_of({{"Content-Type: text/plain", "2"}})).find("no Content-Disposition"),
              std::string::npos);
    EXPECT_NE(malformed_detail(form_of({{"Content-Disposition: attachment; name=\"a\"", "2"}})).find("not form-data"),
              std::string::npos);
    EXPECT_NE(
        malformed_detail(form_of({{"Content-Disposition: form-data; filename=\"x.obj\"", "2"}})).find("has no name"),
        std::string::npos);
    EXPECT_NE(malformed_detail(form_of({{field("a") + "\r\nnot a header", "2"}})).find("\"not a header\""),
              std::string::npos);
    EXPECT_NE(
        malformed_detail(form_of({{field("a") + "\r\nContent-Transfer-Encoding: base64", "Mg=="}})).find("base64"),
        std::string::npos);
    EXPECT_NE(malformed_detail("").find("no delimiter"), std::string::npos);
}

TEST(Multipart, LimitsOnPartsAndHeaderSize) {
    MultipartLimits limits;
    limits.max_parts = 3;
    limits.max_header_bytes = 100;
    std::vector<std::pair<std::string, std::string>> three(3, {field("a"), "1"});
    EXPECT_TRUE(parse_multipart(form_of(three), kBoundary, limits).ok());
    three.push_back({field("b"), "1"});
    EXPECT_NE(malformed_detail(form_of(three), kBoundary, limits).find("more than 3 parts"), std::string::npos);
    const std::string long_header = field("a") + "\r\nX-Pad: " + std::string(200, 'p');
    EXPECT_NE(malformed_detail(form_of({{long_header, "1"}}), kBoundary, limits).find("over 100 bytes"),
              std::string::npos);
}

TEST(Accept, QualitiesSpecificityAndTies) {
    constexpr std::string_view offered[] = {"model/gltf-binary", "model/gltf+json", "model/obj", "application/ply",
                                            "application/json"};
    const auto pick = [&](std::string_view accept) { return negotiate_media_type(accept, offered, 0); };
    EXPECT_EQ(pick("model/obj"), 2u);
    EXPECT_EQ(pick("MODEL/OBJ; charset=x"), 2u);
    EXPECT_EQ(pick("*/*"), 0u);
    EXPECT_EQ(pick(""), 0u);
    EXPECT_EQ(pick("model/*"), 0u);        // a tie goes to the default
    EXPECT_EQ(pick("application/*"), 3u);  // a tie without the default: the earlier offered type
    EXPECT_EQ(pick("application/json;q=0.9, application/ply;q=0.5, */*;q=0.1"), 4u);
    EXPECT_EQ(pick("model/*;q=0.2, model/obj;q=0.8, */*;q=0.5"), 2u);
    EXPECT_EQ(pick("model/obj;q=0, model/*"), 0u);  // the exact range (q=0) excludes obj, model/* keeps the rest
    EXPECT_EQ(pick("*/*;q=0.1, model/gltf-binary;q=0"), 1u);
    EXPECT_EQ(pick("text/html"), std::nullopt);
    EXPECT_EQ(pick("text/html, application/xhtml+xml;q=0.9"), std::nullopt);
    EXPECT_EQ(pick("model/obj;q=0"), std::nullopt);
    EXPECT_EQ(pick("text/html,application/xhtml+xml,application/xml;q=0.9,*/*;q=0.8"), 0u);  // a browser's
    EXPECT_EQ(pick("garbage, model/obj;q=2"), 0u);  // nothing well-formed: as if absent
}

// ---- the operations --------------------------------------------------------------------------------------------

constexpr const char* kCubeObj =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const std::string kFormType = "multipart/form-data; boundary=" + std::string(kBoundary);

ApiResponse subdivide_form(const std::string& body, std::multimap<std::string, std::string> query = {},
                           std::string accept = "") {
    ApiRequest request = make_request("POST", "/subdivide", kFormType, body, std::move(query));
    if (!accept.empty()) request.headers.emplace("accept", accept);
    return operations::subdivide(request, context_with());
}

nlohmann::json problem_of(const ApiResponse& response) { return nlohmann::json::parse(response.body); }

TEST(FormUpload, FieldsAreQueryParameters) {
    const std::string form = form_of({{field("levels"), "2"},
                                      {field("format"), "obj"},
                                      {file_header("mesh", "cube.obj", "application/octet-stream"), kCubeObj}});
    const ApiResponse by_form = subdivide_form(form);
    ASSERT_EQ(by_form.status, 200) << by_form.body;
    EXPECT_EQ(by_form.content_type, "model/obj");
    EXPECT_EQ(header(by_form, "X-Output-Faces"), "96");  // 6 quads, two levels: 6 * 16
    ApiRequest raw = make_request("POST", "/subdivide", "model/obj", kCubeObj, {{"levels", "2"}, {"format", "obj"}});
    const ApiResponse by_query = operations::subdivide(raw, context_with());
    ASSERT_EQ(by_query.status, 200);
    EXPECT_EQ(by_form.body, by_query.body);
}

TEST(FormUpload, FileTypeFromPartTypeThenExtensionThenContent) {
    // a browser's guess for .obj that no endpoint reads gives way to the extension
    for (const auto& [name, type] :
         std::vector<std::pair<std::string, std::string>>{{"cube.obj", "application/x-tgif"},
                                                          {"cube.OBJ", ""},
                                                          {"cube", "application/octet-stream"},
                                                          {"cube.bin", ""},
                                                          {"cube", "model/obj"}}) {
        SCOPED_TRACE(name + " " + type);
        const ApiResponse response =
            subdivide_form(form_of({{file_header("file", name, type), kCubeObj}}), {{"format", "json"}});
        EXPECT_EQ(response.status, 200) << response.body;
    }
    // declared PLY wins over the name: the OBJ text is then read as PLY and refused at its first line
    const ApiResponse as_ply =
        subdivide_form(form_of({{file_header("file", "cube.obj", "application/ply"), kCubeObj}}));
    EXPECT_EQ(as_ply.status, 400) << as_ply.body;
    EXPECT_EQ(problem_of(as_ply).value("code", ""), "parse_error");
    const ApiResponse png = subdivide_form(form_of({{file_header("file", "x.png", "image/png"), kCubeObj}}));
    EXPECT_EQ(png.status, 415);
    EXPECT_NE(problem_of(png).value("detail", "").find("image/png"), std::string::npos);
}

TEST(FormUpload, FieldErrorsAreTheQueryParameterErrorsNamingTheField) {
    const std::string file = kCubeObj;
    const auto expect = [](const ApiResponse& response, const char* code, const char* field_name,
                           const char* in_detail) {
        ASSERT_EQ(response.status, 400) << response.body;
        const auto problem = problem_of(response);
        EXPECT_EQ(problem.value("code", ""), code);
        EXPECT_EQ(problem.value("field", ""), field_name);
        EXPECT_NE(problem.value("detail", "").find(in_detail), std::string::npos) << problem.dump();
    };
    const auto with = [&](std::vector<std::pair<std::string, std::string>> parts) {
        parts.push_back({file_header("file", "cube.obj"), file});
        return form_of(parts);
    };
    expect(subdivide_form(with({{field("levels"), "-1"}})), "invalid_field", "levels", "in [0, 8], got -1");
    expect(subdivide_form(with({{field("levles"), "2"}})), "unknown_parameter", "levles", "did you mean \"levels\"");
    // worded as the form fields they are; a query parameter of the same request stays one
    expect(subdivide_form(with({{field("levles"), "2"}})), "unknown_parameter", "levles",
           "unknown form field \"levles\"");
    expect(subdivide_form(with({{field("levels"), "two"}})), "invalid_field", "levels",
           "form field levels must be an integer");
    expect(subdivide_form(with({{field("scheme"), "loops"}})), "invalid_field", "scheme", "form field scheme: unknown");
    expect(subdivide_form(with({}), {{"levels", "two"}}), "invalid_field", "levels",
           "query parameter levels must be an integer");
    EXPECT_EQ(problem_of(subdivide_form(with({{field("levles"), "2"}}))).value("title", ""), "Unknown form field");
    expect(subdivide_form(with({{field("levels"), "1"}}), {{"levels", "1"}}), "invalid_field", "levels",
           "both as a query parameter and as a form field");
    expect(subdivide_form(with({{field("levels"), "1"}, {field("levels"), "2"}})), "invalid_field", "levels",
           "more than once");
}

TEST(FormUpload, ExactlyOneNonEmptyFilePart) {
    const ApiResponse none = subdivide_form(form_of({{field("levels"), "1"}}));
    ASSERT_EQ(none.status, 400);
    EXPECT_EQ(problem_of(none).value("code", ""), "malformed_multipart");
    EXPECT_NE(problem_of(none).value("detail", "").find("no file part"), std::string::npos);
    const ApiResponse two =
        subdivide_form(form_of({{file_header("a", "a.obj"), kCubeObj}, {file_header("b", "b.obj"), kCubeObj}}));
    ASSERT_EQ(two.status, 400);
    EXPECT_NE(problem_of(two).value("detail", "").find("two file parts, \"a\" and \"b\""), std::string::npos);
    // a part named "file" is the file even without a filename (curl -F 'file=<cube.obj')
    const ApiResponse named = subdivide_form(form_of({{field("file"), kCubeObj}}));
    EXPECT_EQ(named.status, 200) << named.body;
    const ApiResponse empty = subdivide_form(form_of({{file_header("file", ""), ""}}));
    ASSERT_EQ(empty.status, 400);
    EXPECT_EQ(problem_of(empty).value("code", ""), "empty_body");
    EXPECT_NE(problem_of(empty).value("detail", "").find("file part \"file\""), std::string::npos);
}

TEST(FormUpload, TessellateAndPointcloudTakeForms) {
    // a bilinear patch as OBJ; application/octet-stream (curl's type for .obj) gives way to the extension
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\ncstype bezier\ndeg 1 1\nsurf 0 1 0 1 1 2 3 4\nend\n";
    const std::string patches =
        form_of({{field("segments"), "4"}, {file_header("file", "p.obj", "application/octet-stream"), obj}});
    const ApiResponse tessellated = operations::tessellate(
        make_request("POST", "/tessellate", kFormType, patches, {{"format", "obj"}}), context_with());
    ASSERT_EQ(tessellated.status, 200) << tessellated.body;
    EXPECT_EQ(header(tessellated, "X-Output-Faces"), "32");  // 4 x 4 quads, two triangles each
    const std::string points = form_of({{file_header("file", "p.xyz"), "0 0 0\n1 0 0\n0 1 0\n"}});
    ApiRequest request = make_request("POST", "/pointcloud", kFormType, points);
    request.headers.emplace("accept", "application/json");
    const ApiResponse cloud = operations::pointcloud(request, context_with());
    ASSERT_EQ(cloud.status, 200) << cloud.body;
    EXPECT_EQ(cloud.content_type, "application/json");
    EXPECT_EQ(nlohmann::json::parse(cloud.body)["points"].size(), 3u);
}

TEST(AcceptHeader, PicksTheFormatUnlessOneIsNamed) {
    const std::string form = form_of({{file_header("file", "cube.obj"), kCubeObj}});
    EXPECT_EQ(subdivide_form(form, {}, "model/obj").content_type, "model/obj");
    EXPECT_EQ(subdivide_form(form, {}, "application/ply;q=0.5, application/json").content_type, "application/json");
    EXPECT_EQ(subdivide_form(form, {}, "*/*").content_type, "model/gltf-binary");
    EXPECT_EQ(subdivide_form(form, {{"format", "ply"}}, "model/obj").content_type, "application/ply");
    const ApiResponse refused = subdivide_form(form, {}, "text/html");
    ASSERT_EQ(refused.status, 406);
    EXPECT_EQ(refused.content_type, "application/problem+json");
    const std::string detail = problem_of(refused).value("detail", "");
    for (const char* type :
         {"model/gltf-binary", "model/gltf+json", "model/obj", "application/ply", "application/json"})
        EXPECT_NE(detail.find(type), std::string::npos) << type << " in " << detail;
    // two Accept headers are one list
    ApiRequest twice = make_request("POST", "/subdivide", kFormType, form);
    twice.headers.emplace("accept", "text/html");
    twice.headers.emplace("accept", "model/obj;q=0.5");
    EXPECT_EQ(operations::subdivide(twice, context_with()).content_type, "model/obj");
    // a JSON body: output.format wins, else Accept
    ApiRequest json = make_request("POST", "/subdivide", "application/json",
                                   R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]]}})");
    json.headers.emplace("accept", "model/obj");
    EXPECT_EQ(operations::subdivide(json, context_with()).content_type, "model/obj");
    const std::string named = R"({"mesh":{"positions":[[0,0,0],[1,0,0],[0,1,0]],"faces":[[0,1,2]]},)"
                              R"("output":{"format":"json"}})";
    json.body = named;
    EXPECT_EQ(operations::subdivide(json, context_with()).content_type, "application/json");
}

TEST(AcceptHeader, TessellateAndImplicitMeshFollowIt) {
    const std::string patches = R"({"patches":[{"degree":[1,1],"points":[[0,0,0],[1,0,0],[0,1,0],[1,1,1]]}]})";
    ApiRequest tessellate = make_request("POST", "/tessellate", "application/json", patches);
    tessellate.headers.emplace("accept", "application/ply");
    EXPECT_EQ(operations::tessellate(tessellate, context_with()).content_type, "application/ply");
    tessellate.headers.clear();
    tessellate.headers.emplace("accept", "application/json");  // the JSON mesh
    EXPECT_EQ(operations::tessellate(tessellate, context_with()).content_type, "application/json");
    tessellate.headers.clear();
    tessellate.headers.emplace("accept", "text/html");  // not among /tessellate's formats
    EXPECT_EQ(operations::tessellate(tessellate, context_with()).status, 406);

    const std::string scene = R"({"scene":{"op":"sphere","radius":1},"bounds":[[-1.5,-1.5,-1.5],[1.5,1.5,1.5]],)"
                              R"("resolution":8})";
    ApiRequest implicit = make_request("POST", "/implicit/mesh", "application/json", scene);
    implicit.headers.emplace("accept", "model/obj;q=0.5, application/json;q=0.6");
    const ApiResponse meshed = operations::implicit_mesh(implicit, context_with());
    ASSERT_EQ(meshed.status, 200) << meshed.body;
    EXPECT_EQ(meshed.content_type, "application/json");
}

}  // namespace
}  // namespace surfaced::api
