// Acceptance of the repair corpus (tests/data/repair-corpus) by the operations that repair their input: every file is
// uploaded as it is, with the media type of its extension and the default repair ("auto"), to POST /simplify
// (ratio 0.5) and POST /remesh (default edge length), called directly. Every mesh must be processed (200, with
// X-Repairs); the files that are no mesh at all must give no surface back. The table it prints is the one in
// docs/repair.md ("Acceptance").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/routes.h"
#include "tests/support/api_request.h"
#include "tests/support/mesh_asserts.h"

namespace surfaced::api {
namespace {

using namespace fixtures;
namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(SURFACED_TEST_DATA_DIR) / "repair-corpus";

std::string media_type_of_file(const std::string& name) {
    const std::string ext = fs::path(name).extension().string();
    if (ext == ".obj") return "model/obj";
    if (ext == ".off") return "model/off";
    if (ext == ".ply") return "application/ply";
    if (ext == ".stl") return "model/stl";
    if (ext == ".gltf") return "model/gltf+json";
    if (ext == ".glb") return "model/gltf-binary";
    return "application/octet-stream";
}

//! What an operation answered: "200, 24 faces" or "<status> <code>".
std::string outcome(const ApiResponse& response) {
    if (response.status == 200) return "200, " + header(response, "X-Output-Faces") + " faces";
    const auto problem = nlohmann::json::parse(response.body, nullptr, false);
    return std::to_string(response.status) + " " + (problem.is_discarded() ? "?" : problem.value("code", "?"));
}

//! The non-zero counts of an X-Repairs header ("duplicate=8, components=1"), "none" when every count is 0 (the
//! operation ran on the mesh as sent).
std::string nonzero_repairs(const std::string& x_repairs) {
    std::string out;
    std::size_t at = 0;
    while (at < x_repairs.size()) {
        std::size_t end = x_repairs.find("; ", at);
        if (end == std::string::npos) end = x_repairs.size();
        const std::string item = x_repairs.substr(at, end - at);
        if (item.substr(item.find('=') + 1) != "0") out += (out.empty() ? "" : ", ") + item;
        at = end + 2;
    }
    return out.empty() ? "none" : out;
}

//! Files that are not meshes at all.
const std::set<std::string> kNotMeshes = {"not_a_mesh_point_cloud.ply", "not_a_mesh_only_degenerate.obj"};

TEST(RepairCorpusAcceptance, SimplifyAndRemeshProcessEveryMeshAndReturnNoSurfaceForTheRest) {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kCorpus)) {
        const std::string name = entry.path().filename().string();
        if (name != "generate.py" && name != "expected.json") names.push_back(name);
    }
    std::sort(names.begin(), names.end());
    ASSERT_GE(names.size(), 12u);

    std::size_t meshes = 0, simplified = 0, remeshed = 0;
    std::string table = "| file | /simplify | /remesh | X-Repairs of /simplify, non-zero counts |\n|---|---|---|---|\n";
    for (const std::string& name : names) {
        SCOPED_TRACE(name);
        const std::string body = testing::read_file((kCorpus / name).string());
        const std::string type = media_type_of_file(name);
        const ApiResponse s = dispatch(
            make_request("POST", "/simplify", type, body, {{"ratio", "0.5"}, {"format", "obj"}}), context_with());
        const ApiResponse r =
            dispatch(make_request("POST", "/remesh", type, body, {{"format", "obj"}}), context_with());
        table += "| `" + name + "` | " + outcome(s) + " | " + outcome(r) + " | " +
                 (s.status == 200 ? nonzero_repairs(header(s, "X-Repairs")) : "") + " |\n";
        if (kNotMeshes.count(name)) {
            // no surface comes back: a 4xx, or (measured: /simplify on a file whose every face is degenerate) an
            // empty mesh
            for (const ApiResponse* response : {&s, &r}) {
                EXPECT_TRUE((response->status >= 400 && response->status < 500) ||
                            (response->status == 200 && header(*response, "X-Output-Faces") == "0"))
                    << response->status << " " << response->body.substr(0, 200);
            }
            continue;
        }
        ++meshes;
        simplified += s.status == 200;
        remeshed += r.status == 200;
        EXPECT_EQ(s.status, 200) << s.body;
        EXPECT_EQ(r.status, 200) << r.body;
        EXPECT_FALSE(header(s, "X-Repairs").empty());
        EXPECT_FALSE(header(r, "X-Repairs").empty());
    }
    std::printf("%s\nmeshes: %zu of %zu files; /simplify 200 on %zu, /remesh 200 on %zu\n", table.c_str(), meshes,
                names.size(), simplified, remeshed);
    EXPECT_EQ(meshes + kNotMeshes.size(), names.size());
}

}  // namespace
}  // namespace surfaced::api
