// The OpenAPI document: valid OpenAPI 3.1 (checked by an independent validator, npm @seriousme/openapi-schema-
// validator), in step with the route table in both directions, and its request examples accepted by the operations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "api/openapi.h"
#include "api/routes.h"

namespace surfaced::api {
namespace {

nlohmann::json document() { return nlohmann::json::parse(openapi_document()); }

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

TEST(OpenApi, IsValidOpenApi31) {
    // One file per process: the normal and sanitizer trees (or two developers) may run this test at once.
    const auto path =
        std::filesystem::temp_directory_path() / ("surfaced-openapi-test-" + std::to_string(::getpid()) + ".json");
    {
        std::ofstream out(path, std::ios::binary);
        out << openapi_document();
    }
    const std::string command =
        std::string("node '") + SURFACED_SOURCE_DIR + "/tests/tools/validate_openapi.mjs' '" + path.string() + "' 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[4096];
    while (std::size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
    const int status = pclose(pipe);
    std::filesystem::remove(path);
    EXPECT_EQ(status, 0) << output;
    EXPECT_NE(output.find("\"valid\":true"), std::string::npos) << output;
    EXPECT_EQ(document().value("openapi", ""), "3.1.0");
}

TEST(OpenApi, DocumentsExactlyTheRoutesTheServiceHas) {
    const auto doc = document();
    std::set<std::pair<std::string, std::string>> documented, routed;
    for (const auto& [path, item] : doc["paths"].items())
        for (const auto& [method, operation] : item.items()) documented.insert({method, path});
    for (const Route& route : routes()) routed.insert({lower(route.method), std::string(route.path)});
    for (const auto& r : routed) EXPECT_TRUE(documented.count(r)) << r.first << " " << r.second << " is not documented";
    for (const auto& d : documented)
        EXPECT_TRUE(routed.count(d)) << d.first << " " << d.second << " is documented but not served";
}

TEST(OpenApi, JsonRequestExamplesAreAccepted) {
    const auto doc = document();
    int examples = 0;
    for (const auto& [path, item] : doc["paths"].items())
        for (const auto& [method, operation] : item.items()) {
            if (!operation.contains("requestBody")) continue;
            const auto& content = operation["requestBody"]["content"];
            if (!content.contains("application/json")) continue;
            const auto& media = content["application/json"];
            std::vector<std::pair<std::string, std::string>>
                bodies;  // (name, body): `example` and every `examples` entry
            if (media.contains("example")) bodies.emplace_back("example", media["example"].dump());
            if (media.contains("examples"))
                for (const auto& [name, entry] : media["examples"].items())
                    if (entry.contains("value")) bodies.emplace_back(name, entry["value"].dump());
            for (const auto& [name, body] : bodies) {
                ApiRequest request;
                request.method.clear();
                for (char c : method) request.method += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
                request.path = path;
                request.content_type = "application/json";
                request.body = body;
                const ApiResponse response = dispatch(request, ApiContext{});
                EXPECT_EQ(response.status, 200) << method << " " << path << " (" << name << "): " << response.body;
                ++examples;
            }
        }
    EXPECT_GE(examples, 10);
}

TEST(OpenApi, ServedAtOpenApiJson) {
    ApiRequest request;
    request.method = "GET";
    request.path = "/openapi.json";
    const ApiResponse response = dispatch(request, ApiContext{});
    EXPECT_EQ(response.status, 200);
    EXPECT_EQ(response.content_type, "application/json");
    EXPECT_EQ(response.body, openapi_document());
}

}  // namespace
}  // namespace surfaced::api
