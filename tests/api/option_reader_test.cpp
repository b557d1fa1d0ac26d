// The table-driven option readers (api/options/option_reader.h): the same mistake gets the same status, field and
// message from a query string and from a JSON body.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "api/options/option_reader.h"
#include "api/options/option_spec.h"

namespace surfaced::api::options {
namespace {

const OperationOptions& subdivide() { return *operation_options("subdivide"); }

ApiError query_error(std::multimap<std::string, std::string> query) {
    auto values = read_query(subdivide(), query);
    EXPECT_FALSE(values.ok());
    return values.ok() ? ApiError{} : values.error();
}

ApiError json_error(const char* body) {
    auto values = read_json(subdivide(), nlohmann::json::parse(body));
    EXPECT_FALSE(values.ok());
    return values.ok() ? ApiError{} : values.error();
}

TEST(OptionReader, MeshOperationsShareTheOutputOptions) {
    for (const char* operation : {"subdivide", "simplify", "remesh", "repair", "tessellate", "patches"}) {
        const OperationOptions* op = operation_options(operation);
        ASSERT_NE(op, nullptr) << operation;
        for (const char* name : {"format", "compression", "quantize_position", "normals"})
            EXPECT_NE(find_option(*op, name), nullptr) << operation << " " << name;
    }
    // every operation that encodes a result offers formats; /implicit/query, /mesh/query, /implicit/grid and
    // /surfaces and /limit/evaluate answer in JSON only
    for (const auto& op : operations())
        EXPECT_EQ(find_option(op, "format") != nullptr,
                  op.operation != "implicit_query" && op.operation != "mesh_query" && op.operation != "implicit_grid" &&
                      op.operation != "surfaces" && op.operation != "limit_evaluate")
            << op.operation;
    EXPECT_EQ(operation_options("no-such-operation"), nullptr);
}

TEST(OptionReader, ReadsEachTypeFromEitherTransport) {
    auto query = read_query(
        subdivide(),
        {{"levels", "2"}, {"scheme", "loop"}, {"limit_surface", "1"}, {"quantize_position", "20"}, {"format", "obj"}});
    ASSERT_TRUE(query.ok()) << query.error().detail;
    auto body = read_json(
        subdivide(),
        nlohmann::json::parse(
            R"({"levels":2,"scheme":"loop","limit_surface":true,"output":{"quantize_position":20,"format":"obj"}})"));
    ASSERT_TRUE(body.ok()) << body.error().detail;
    for (const OptionValues* values : {&query.value(), &body.value()}) {
        std::int64_t levels = 0;
        values->get("levels", levels);
        EXPECT_EQ(levels, 2);
        bool limit = false;
        values->get("limit_surface", limit);
        EXPECT_TRUE(limit);
        OutputOptions out;
        values->get_output(out);
        EXPECT_EQ(out.format, OutputFormat::Obj);
        EXPECT_EQ(out.quantize_position, 20);
        EXPECT_FALSE(values->has("target_faces"));
    }
}

TEST(OptionReader, OutOfRangeIs400NamingTheOptionWithRangeAndValue) {
    const ApiError query = query_error({{"quantize_position", "25"}});
    EXPECT_EQ(query.status, 400);
    EXPECT_EQ(query.code, "invalid_field");
    EXPECT_EQ(query.field, "quantize_position");
    EXPECT_EQ(query.detail, "quantize_position must be in [1, 24] (bits), got 25");
    const ApiError body = json_error(R"({"output":{"quantize_position":25}})");
    EXPECT_EQ(body.status, 400);
    EXPECT_EQ(body.code, "invalid_field");
    EXPECT_EQ(body.field, "output.quantize_position");
    EXPECT_EQ(body.detail, "output.quantize_position must be in [1, 24] (bits), got 25");
    EXPECT_EQ(query_error({{"target_faces", "0"}}).detail, "target_faces must be >= 1, got 0");
    EXPECT_EQ(json_error(R"({"levels":-1})").field, "levels");
}

TEST(OptionReader, LimitsAreLeftToTheOperation) {
    // levels' maximum is the server's configured Limits::max_levels (422 budget_exceeded), not a fixed range
    EXPECT_TRUE(read_query(subdivide(), {{"levels", "9"}}).ok());
}

TEST(OptionReader, NumbersInMessagesReadBackExactly) {
    OptionSpec tolerance{.name = "tolerance", .type = OptionType::Number, .min = Bound{1e-6, false}};
    EXPECT_EQ(range_text(tolerance), ">= 1e-06");
    tolerance.min = Bound{0, true};
    tolerance.max = Bound{0.5, false};
    EXPECT_EQ(range_text(tolerance), "in (0, 0.5]");
}

TEST(OptionReader, UnknownNamesSuggestTheNearestOne) {
    const ApiError one = query_error({{"levles", "2"}});
    EXPECT_EQ(one.status, 400);
    EXPECT_EQ(one.code, "unknown_parameter");
    EXPECT_EQ(one.field, "levles");
    EXPECT_NE(one.detail.find("did you mean \"levels\"?"), std::string::npos) << one.detail;
    EXPECT_NE(one.detail.find("allowed: scheme, levels"), std::string::npos) << one.detail;
    const ApiError far = query_error({{"colour", "red"}});
    EXPECT_EQ(far.detail.find("did you mean"), std::string::npos) << far.detail;
    const ApiError value = query_error({{"scheme", "lop"}});
    EXPECT_EQ(value.field, "scheme");
    EXPECT_NE(value.detail.find("did you mean \"loop\"?"), std::string::npos) << value.detail;
    const ApiError nested = json_error(R"({"output":{"fromat":"obj"}})");
    EXPECT_EQ(nested.code, "unknown_field");
    EXPECT_EQ(nested.field, "output.fromat");
    EXPECT_NE(nested.detail.find("did you mean \"format\"?"), std::string::npos) << nested.detail;
}

TEST(OptionReader, AGivenTwiceIs400) {
    const ApiError twice = query_error({{"levels", "1"}, {"levels", "2"}});
    EXPECT_EQ(twice.code, "invalid_field");
    EXPECT_EQ(twice.field, "levels");
}

TEST(OptionReader, DeprecatedAliasesAreReadUnderTheOptionsName) {
    static constexpr std::string_view kOldNames[] = {"subdivision_levels"};
    static constexpr OptionSpec kOptions[] = {
        {.name = "levels", .type = OptionType::Integer, .min = Bound{0, false}, .aliases = kOldNames}};
    static constexpr std::string_view kInputs[] = {"mesh"};
    const OperationOptions op{.operation = "test", .options = kOptions, .json_inputs = kInputs};
    auto query = read_query(op, {{"subdivision_levels", "3"}});
    ASSERT_TRUE(query.ok()) << query.error().detail;
    std::int64_t levels = 0;
    query->get("levels", levels);
    EXPECT_EQ(levels, 3);
    auto body = read_json(op, nlohmann::json::parse(R"({"subdivision_levels":4})"));
    ASSERT_TRUE(body.ok()) << body.error().detail;
    body->get("levels", levels);
    EXPECT_EQ(levels, 4);
    EXPECT_FALSE(read_query(op, {{"subdivision_levels", "3"}, {"levels", "3"}}).ok());
    EXPECT_FALSE(read_json(op, nlohmann::json::parse(R"({"subdivision_levels":4,"levels":4})")).ok());
    const auto members = json_members(op);
    EXPECT_NE(std::find(members.begin(), members.end(), "subdivision_levels"), members.end());
}

TEST(OptionReader, RemeshTakesLockBorderAndItsDeprecatedNameKeepBoundary) {
    const OperationOptions& remesh = *operation_options("remesh");
    const OptionSpec* lock = find_option(remesh, "lock_border");
    ASSERT_NE(lock, nullptr);
    EXPECT_EQ(find_option(remesh, "keep_boundary"), lock);
    EXPECT_EQ(lock->default_json, "true");  // moving an open mesh's border shrinks it
    EXPECT_EQ(find_option(*operation_options("simplify"), "lock_border")->default_json, "false");  // as meshoptimizer
    for (const char* name : {"lock_border", "keep_boundary"}) {
        SCOPED_TRACE(name);
        bool value = true;
        auto query = read_query(remesh, {{name, "false"}});
        ASSERT_TRUE(query.ok()) << query.error().detail;
        query->get("lock_border", value);
        EXPECT_FALSE(value);
        value = true;
        auto body = read_json(remesh, nlohmann::json::parse(std::string("{\"") + name + "\":false}"));
        ASSERT_TRUE(body.ok()) << body.error().detail;
        body->get("lock_border", value);
        EXPECT_FALSE(value);
    }
    // both names: 400 naming the deprecated one, saying which option it is
    auto both_query = read_query(remesh, {{"lock_border", "true"}, {"keep_boundary", "false"}});
    ASSERT_FALSE(both_query.ok());
    EXPECT_EQ(both_query.error().status, 400);
    EXPECT_EQ(both_query.error().code, "invalid_field");
    EXPECT_NE(both_query.error().detail.find("keep_boundary is its deprecated name"), std::string::npos)
        << both_query.error().detail;
    auto both_json = read_json(remesh, nlohmann::json::parse(R"({"lock_border":true,"keep_boundary":true})"));
    ASSERT_FALSE(both_json.ok());
    EXPECT_EQ(both_json.error().status, 400);
    EXPECT_EQ(both_json.error().field, "keep_boundary");
    EXPECT_NE(both_json.error().detail.find("keep_boundary is its deprecated name"), std::string::npos)
        << both_json.error().detail;
    // the old name of /remesh is not one of /simplify's
    EXPECT_EQ(find_option(*operation_options("simplify"), "keep_boundary"), nullptr);
}

}  // namespace
}  // namespace surfaced::api::options
