// Output formats over real HTTP: every mesh-producing endpoint answers every mesh format (glb, gltf, obj, ply, json,
// stl, off) with its media type; glTF outputs pass the Khronos validator; the other formats read back by our own
// readers give the JSON answer's vertex positions bit for bit (STL: as float32) and its faces; normals are written
// by default where the format holds them; text outputs never print -0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cctype>
#include <cstdlib>
#include <string>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "geometry/io/gltf.h"
#include "geometry/io/mesh_io.h"
#include "server/http_server.h"
#include "tests/support/gltf_validator.h"
#include "tests/support/http_test_server.h"

namespace surfaced::server {
namespace {

using nlohmann::json;

class FormatsHttp : public testing::SharedServerTest<FormatsHttp> {
protected:
    static httplib::Client client() { return server_->client(60); }
};

struct Format {
    const char* name;
    const char* media_type;
};
constexpr Format kFormats[] = {
    {"glb", "model/gltf-binary"}, {"gltf", "model/gltf+json"}, {"obj", "model/obj"}, {"ply", "application/ply"},
    {"json", "application/json"}, {"stl", "model/stl"},        {"off", "model/off"},
};

//! A unit cube of quads whose zero coordinates are all -0 (JSON "-0.0"), so a writer that printed the sign would
//! show it.
json negative_zero_cube() {
    const double z = -0.0;
    json positions = json::array();
    for (const auto& p : std::vector<std::vector<double>>{
             {z, z, z}, {1, z, z}, {1, 1, z}, {z, 1, z}, {z, z, 1}, {1, z, 1}, {1, 1, 1}, {z, 1, 1}})
        positions.push_back(p);
    return {{"positions", positions},
            {"faces", {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}}}};
}

//! One mesh-producing request: POST with a JSON body (output options under "output"), or GET with a query.
struct Endpoint {
    std::string name;
    std::string path;
    json body;  //!< null: GET `path` with "format=..." appended
};

std::vector<Endpoint> endpoints() {
    const json cube = negative_zero_cube();
    const json patch = {{"degree", {1, 1}}, {"points", {{0, 0, 0}, {1, 0, 0.25}, {0, 1, 0.5}, {1, 1, -0.5}}}};
    return {
        {"subdivide", "/subdivide", {{"mesh", cube}, {"levels", 1}}},
        {"simplify", "/simplify", {{"mesh", cube}, {"ratio", 0.5}}},
        {"remesh", "/remesh", {{"mesh", cube}, {"edge_length", 0.5}, {"iterations", 2}}},
        {"repair", "/repair", {{"mesh", cube}}},
        {"implicit_mesh",
         "/implicit/mesh",
         {{"scene", {{"op", "sphere"}, {"radius", 1}}},
          {"bounds", {{-1.5, -1.5, -1.5}, {1.5, 1.5, 1.5}}},
          {"resolution", 8}}},
        {"tessellate", "/tessellate", {{"patches", {patch}}, {"segments", 3}}},
        {"patches", "/patches/teapot?segments=2", nullptr},
    };
}

httplib::Result request(httplib::Client& client, const Endpoint& endpoint, const json& output) {
    if (endpoint.body.is_null()) {
        std::string path = endpoint.path;
        for (const auto& [name, value] : output.items())
            path += "&" + name + "=" + (value.is_string() ? value.get<std::string>() : value.dump());
        return client.Get(path);
    }
    json body = endpoint.body;
    body["output"] = output;
    return client.Post(endpoint.path, body.dump(), "application/json");
}

//! The JSON answer's mesh as a PolygonMesh (positions exactly as printed, faces as given).
PolygonMesh mesh_of(const json& answer) {
    PolygonMesh mesh;
    for (const auto& p : answer["mesh"]["positions"])
        mesh.positions.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
    for (const auto& f : answer["mesh"]["faces"]) mesh.add_face(f.get<std::vector<Index>>());
    return mesh;
}

//! Every number in `text` that reads as zero is printed without a sign. (A hand-written scan: GCC 12 warns inside
//! libstdc++'s std::regex under the sanitizer build, whose warnings are errors.)
void expect_no_negative_zero(const std::string& text, const std::string& what) {
    int signed_zeros = 0;
    for (std::size_t i = 0; i + 1 < text.size(); ++i) {
        if (text[i] != '-' || !std::isdigit(static_cast<unsigned char>(text[i + 1]))) continue;
        if (std::strtod(text.c_str() + i, nullptr) == 0) ++signed_zeros;
    }
    EXPECT_EQ(signed_zeros, 0) << what;
}

void expect_same_positions(const PolygonMesh& want, const PolygonMesh& got, const std::string& what) {
    ASSERT_EQ(got.positions.size(), want.positions.size()) << what;
    for (std::size_t i = 0; i < want.positions.size(); ++i)
        ASSERT_TRUE(got.positions[i] == want.positions[i]) << what << ": vertex " << i;
    EXPECT_EQ(got.face_offsets, want.face_offsets) << what;
    EXPECT_EQ(got.face_indices, want.face_indices) << what;
}

//! STL: each triangle of the fan-triangulated reference, with its corners rounded to float32.
void expect_same_triangles(const PolygonMesh& want, const PolygonMesh& got, const std::string& what) {
    const auto f32 = [](const Vec3& p) {
        return Vec3{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
    };
    std::size_t t = 0;
    for (std::size_t f = 0; f < want.face_count(); ++f) {
        const auto face = want.face(f);
        for (std::size_t k = 1; k + 1 < face.size(); ++k, ++t) {
            ASSERT_LT(t, got.face_count()) << what;
            const auto tri = got.face(t);
            ASSERT_EQ(tri.size(), 3u) << what;
            EXPECT_TRUE(got.positions[tri[0]] == f32(want.positions[face[0]])) << what << ": triangle " << t;
            EXPECT_TRUE(got.positions[tri[1]] == f32(want.positions[face[k]])) << what << ": triangle " << t;
            EXPECT_TRUE(got.positions[tri[2]] == f32(want.positions[face[k + 1]])) << what << ": triangle " << t;
        }
    }
    EXPECT_EQ(t, got.face_count()) << what;
}

TEST_F(FormatsHttp, EveryEndpointAnswersEveryFormat) {
    auto http = client();
    for (const Endpoint& endpoint : endpoints()) {
        SCOPED_TRACE(endpoint.name);
        // the reference: the JSON mesh without normals
        auto reference = request(http, endpoint, {{"format", "json"}, {"normals", false}});
        ASSERT_TRUE(reference) << httplib::to_string(reference.error());
        ASSERT_EQ(reference->status, 200) << reference->body;
        const json answer = json::parse(reference->body);
        EXPECT_FALSE(answer["mesh"].contains("normals"));
        const PolygonMesh want = mesh_of(answer);
        ASSERT_GT(want.face_count(), 0u);

        for (const Format& format : kFormats) {
            const std::string what = endpoint.name + " format " + format.name;
            auto res = request(http, endpoint, {{"format", format.name}});
            ASSERT_TRUE(res) << what << ": " << httplib::to_string(res.error());
            ASSERT_EQ(res->status, 200) << what << ": " << res->body.substr(0, 300);
            EXPECT_EQ(res->get_header_value("Content-Type"), format.media_type) << what;
            const std::string& body = res->body;
            const std::string_view name = format.name;
            if (name == "glb" || name == "gltf") {
                // glTF text is validated as the same bytes a client receives
                const auto report = testing::run_gltf_validator(body);
                ASSERT_TRUE(report.ran) << report.report;
                EXPECT_EQ(report.errors, 0) << what << ": " << report.report;
                auto mesh = name == "glb" ? read_glb(body) : read_gltf(body);
                ASSERT_TRUE(mesh.ok()) << what << ": " << mesh.error().message;
                // the primitive has a NORMAL attribute (the JSON chunk of a GLB is text too)
                EXPECT_NE(body.find("\"NORMAL\""), std::string::npos) << what << ": normals are written by default";
                if (name == "gltf") expect_no_negative_zero(body, what);
                continue;
            }
            if (name == "json") {
                const json doc = json::parse(body);
                const PolygonMesh got = mesh_of(doc);
                expect_same_positions(want, got, what);
                ASSERT_TRUE(doc["mesh"].contains("normals")) << what << ": normals are written by default";
                ASSERT_EQ(doc["mesh"]["normals"].size(), want.positions.size()) << what;
                for (const auto& n : doc["mesh"]["normals"]) {
                    const Vec3 v{n[0].get<double>(), n[1].get<double>(), n[2].get<double>()};
                    EXPECT_TRUE(std::abs(norm(v) - 1) < 1e-9 || norm(v) == 0) << what;  // unit, or none
                }
                expect_no_negative_zero(body, what);
                continue;
            }
            const MeshFormat mesh_format = name == "obj"   ? MeshFormat::Obj
                                           : name == "ply" ? MeshFormat::Ply
                                           : name == "stl" ? MeshFormat::Stl
                                                           : MeshFormat::Off;
            auto got = read_mesh(body, mesh_format);
            ASSERT_TRUE(got.ok()) << what << ": " << got.error().message;
            if (name == "stl") {
                expect_same_triangles(want, *got, what);
                continue;
            }
            expect_same_positions(want, *got, what);
            if (name == "ply") {
                EXPECT_TRUE(got->has_normals()) << what << ": normals are written by default";
            } else {
                expect_no_negative_zero(body, what);  // OBJ and OFF are text (PLY is binary)
            }
            if (name == "obj") {
                EXPECT_NE(body.find("\nvn "), std::string::npos) << what << ": normals are written by default";
            }
        }
    }
}

// subdivide levels=0 answers the input mesh itself: its -0 coordinates reach every text writer.
TEST_F(FormatsHttp, NegativeZeroIsPrintedAsZero) {
    auto http = client();
    const Endpoint unchanged{"subdivide levels 0", "/subdivide", {{"mesh", negative_zero_cube()}, {"levels", 0}}};
    for (const char* format : {"obj", "off", "json", "gltf"}) {
        auto res = request(http, unchanged, {{"format", format}});
        ASSERT_TRUE(res) << httplib::to_string(res.error());
        ASSERT_EQ(res->status, 200) << res->body;
        expect_no_negative_zero(res->body, format);
    }
    // the JSON mesh and its stats: "0", never "-0" or "0.0"
    auto res = request(http, unchanged, {{"format", "json"}, {"normals", false}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->body.find("-0"), std::string::npos) << res->body;
    EXPECT_EQ(res->body.find(".0,"), std::string::npos) << res->body;
    EXPECT_NE(res->body.find("[0,0,0]"), std::string::npos) << res->body;
}

// A JSON answer with normals is a valid JSON request: POSTed back it gives the same mesh.
TEST_F(FormatsHttp, JsonOutputWithNormalsPostsBack) {
    auto http = client();
    const Endpoint first{"subdivide", "/subdivide", {{"mesh", negative_zero_cube()}, {"levels", 1}}};
    auto res = request(http, first, {{"format", "json"}});
    ASSERT_TRUE(res && res->status == 200);
    const json answer = json::parse(res->body);
    ASSERT_TRUE(answer["mesh"].contains("normals"));
    const Endpoint again{"subdivide", "/subdivide", {{"mesh", answer["mesh"]}, {"levels", 0}}};
    auto back = request(http, again, {{"format", "json"}});
    ASSERT_TRUE(back);
    ASSERT_EQ(back->status, 200) << back->body;
    const json echoed = json::parse(back->body);
    EXPECT_EQ(echoed["mesh"]["positions"], answer["mesh"]["positions"]);
    EXPECT_EQ(echoed["mesh"]["faces"], answer["mesh"]["faces"]);

    // operations that change the vertices carry the input's normals along (or compute them): one per output vertex
    for (const char* path : {"/repair", "/simplify", "/remesh"}) {
        json body = {{"mesh", answer["mesh"]}, {"output", {{"format", "json"}}}};
        if (std::string_view(path) == "/simplify") body["ratio"] = 0.5;
        auto changed = http.Post(path, body.dump(), "application/json");
        ASSERT_TRUE(changed);
        ASSERT_EQ(changed->status, 200) << path << ": " << changed->body.substr(0, 300);
        const json out = json::parse(changed->body);
        EXPECT_EQ(out["mesh"]["normals"].size(), out["mesh"]["positions"].size()) << path;
    }

    json bad = answer["mesh"];
    bad["normals"].erase(bad["normals"].begin());
    testing::expect_http_problem(http.Post("/subdivide", json{{"mesh", bad}}.dump(), "application/json"), 400,
                                 "invalid_field", "mesh.normals");
}

// normals=true with a format that holds none names the option; the default does not apply there.
TEST_F(FormatsHttp, ExplicitNormalsWithStlOrOffIs400) {
    auto http = client();
    for (const Endpoint& endpoint : endpoints()) {
        SCOPED_TRACE(endpoint.name);
        const std::string field = endpoint.body.is_null() ? "normals" : "output.normals";
        for (const char* format : {"stl", "off"})
            testing::expect_http_problem(request(http, endpoint, {{"format", format}, {"normals", true}}), 400,
                                         "invalid_field", field);
    }
}

// Point clouds keep their own formats; gltf is the GLB's scene as glTF JSON, as for meshes.
TEST_F(FormatsHttp, PointcloudAnswersGltf) {
    auto http = client();
    const json body = {{"points", {{0, 0, 0}, {1, -0.0, 0.5}, {0.25, 1, -0.0}}},
                       {"normals", {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}},
                       {"output", {{"format", "gltf"}, {"compression", "none"}}}};
    auto res = http.Post("/pointcloud", body.dump(), "application/json");
    ASSERT_TRUE(res) << httplib::to_string(res.error());
    ASSERT_EQ(res->status, 200) << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "model/gltf+json");
    const auto report = testing::run_gltf_validator(res->body);
    ASSERT_TRUE(report.ran) << report.report;
    EXPECT_EQ(report.errors, 0) << report.report;
    const json doc = json::parse(res->body);
    const json& attributes = doc["meshes"][0]["primitives"][0]["attributes"];
    EXPECT_TRUE(attributes.contains("NORMAL"));
    const json& position = doc["accessors"][attributes["POSITION"].get<int>()];
    EXPECT_EQ(position["count"], 3);
    EXPECT_EQ(position["max"], json::array({1, 1, 0.5}));  // printed "1", not "1.0"
    expect_no_negative_zero(res->body, "pointcloud gltf");
}

// STL stores float32 as glTF does: a coordinate beyond its range is 422 naming the vertex; OFF keeps the double.
TEST_F(FormatsHttp, CoordinateBeyondFloat32Is422ForStlOnly) {
    auto http = client();
    const json mesh = {{"positions", {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1e39, 0}}}, {"faces", {{0, 1, 2, 3}}}};
    const Endpoint unchanged{"subdivide levels 0", "/subdivide", {{"mesh", mesh}, {"levels", 0}}};
    const json problem = testing::expect_http_problem(request(http, unchanged, {{"format", "stl"}}), 422,
                                                      "coordinate_out_of_range", "mesh.positions[3]");
    EXPECT_NE(problem.value("detail", "").find("\"stl\""), std::string::npos) << problem.dump();
    auto off = request(http, unchanged, {{"format", "off"}});
    ASSERT_TRUE(off);
    ASSERT_EQ(off->status, 200) << off->body;
    auto read = read_off(off->body);
    ASSERT_TRUE(read.ok()) << read.error().message;
    EXPECT_EQ(read->positions[3].y, 1e39);
}

// The OpenAPI document served lists every format's media type among each endpoint's 200 answers (the format enums
// themselves are held to the option tables by tests/api/options_drift_test.cpp).
TEST_F(FormatsHttp, OpenApiListsEveryFormat) {
    auto http = client();
    auto res = http.Get("/openapi.json");
    ASSERT_TRUE(res && res->status == 200);
    const json doc = json::parse(res->body);
    for (const Endpoint& endpoint : endpoints()) {
        const bool get = endpoint.body.is_null();
        const std::string path = get ? "/patches/{name}" : endpoint.path;
        const json& operation = doc["paths"][path][get ? "get" : "post"];
        const json& content = operation["responses"]["200"]["content"];
        for (const Format& format : kFormats)
            EXPECT_TRUE(content.contains(format.media_type)) << path << " " << format.media_type;
    }
}

}  // namespace
}  // namespace surfaced::server
