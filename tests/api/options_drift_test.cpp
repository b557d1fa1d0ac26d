// The option tables (api/options/catalog.cpp) against api/openapi.json: for every operation with a table, each
// option is documented as a query parameter and/or a JSON body member (as its transports say) with the same type,
// range, default and enum values, and the document lists no option the table does not have. Each deprecated alias of
// an option is documented too, as a parameter or member of its own marked `deprecated: true` (and only the aliases
// are). The table is what the readers enforce, so a failure here means the document no longer describes the server.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/openapi.h"
#include "api/options/option_reader.h"
#include "api/options/option_spec.h"

namespace surfaced::api {
namespace {

using nlohmann::json;
using options::OperationOptions;
using options::OptionSpec;
using options::OptionType;

const json& document() {
    static const json doc = json::parse(openapi_document());
    return doc;
}

//! `value` with a "$ref" (to this document) followed.
const json& resolve(const json& value) {
    if (value.is_object() && value.contains("$ref")) {
        const std::string ref = value["$ref"];
        EXPECT_EQ(ref.rfind("#/", 0), 0u) << ref;
        return resolve(document().at(json::json_pointer(ref.substr(1))));
    }
    return value;
}

std::string type_name(const OptionSpec& option) {
    switch (option.type) {
        case OptionType::Integer: return "integer";
        case OptionType::Number: return "number";
        case OptionType::Bool: return "boolean";
        case OptionType::Enum: return "string";
        case OptionType::List: return "array";
    }
    return "?";
}

//! The bounds of `schema` against the option's: minimum or exclusiveMinimum, maximum or exclusiveMaximum, and whether
//! the maximum is a server limit.
void expect_bounds(const json& schema, const OptionSpec& option, const std::string& where) {
    const auto expect_bound = [&](const std::optional<options::Bound>& bound, const char* inclusive,
                                  const char* exclusive) {
        const std::string wanted = bound ? (bound->exclusive ? exclusive : inclusive) : "";
        for (const char* key : {inclusive, exclusive}) {
            if (key == wanted) {
                ASSERT_TRUE(schema.contains(key))
                    << where << ": OpenAPI has no " << key << ", the option table has " << bound->value;
                EXPECT_EQ(schema[key].get<double>(), bound->value) << where << ": " << key;
            } else {
                EXPECT_FALSE(schema.contains(key))
                    << where << ": OpenAPI has " << key << " " << schema[key].dump() << ", the option table has none";
            }
        }
    };
    expect_bound(option.min, "minimum", "exclusiveMinimum");
    expect_bound(option.max, "maximum", "exclusiveMaximum");
    // a maximum that is the server's (configurable) limit is marked so: above it is 422 budget_exceeded, not 400
    EXPECT_EQ(schema.value("x-maximum-is-limit", false), option.max_is_limit)
        << where << ": x-maximum-is-limit against the table's max_is_limit";
}

//! One documented option (a query parameter's schema, or a JSON member's) against its row of the table.
void expect_same(const json& documented, const OptionSpec& option, const std::string& where) {
    const json& schema = resolve(documented);
    if (option.type == OptionType::List && where.find("query parameter") != std::string::npos) {
        // a list in a query string is one comma-separated string
        EXPECT_EQ(schema.value("type", ""), "string") << where;
    } else {
        EXPECT_EQ(schema.value("type", ""), type_name(option)) << where << ": type";
    }
    if (option.type == OptionType::List) {
        if (schema.contains("items")) expect_bounds(resolve(schema["items"]), option, where + " items");
    } else {
        expect_bounds(schema, option, where);
    }
    if (option.default_json.empty()) {
        EXPECT_FALSE(schema.contains("default"))
            << where << ": OpenAPI has default " << schema["default"].dump() << ", the option table has none";
    } else if (!schema.contains("default")) {
        ADD_FAILURE() << where << ": OpenAPI has no default, the option table has " << option.default_json;
    } else {
        const json wanted = json::parse(option.default_json);
        const json& have = schema["default"];
        if (wanted.is_number() && have.is_number())
            EXPECT_EQ(have.get<double>(), wanted.get<double>()) << where << ": default";
        else
            EXPECT_EQ(have, wanted) << where << ": default";
    }
    if (option.type == OptionType::Enum) {
        const std::vector<std::string> wanted(option.values.begin(), option.values.end());
        std::vector<std::string> have;
        if (schema.contains("enum"))
            for (const auto& v : schema["enum"]) have.push_back(v.get<std::string>());
        EXPECT_EQ(have, wanted) << where << ": enum values";
    }
}

std::string label(const OperationOptions& op) { return std::string(op.operation) + " (" + std::string(op.path) + ")"; }

TEST(OptionsDrift, EveryOperationWithATableIsInTheDocument) {
    ASSERT_FALSE(options::operations().empty());
    for (const auto& op : options::operations()) {
        ASSERT_TRUE(document()["paths"].contains(std::string(op.path))) << label(op);
        EXPECT_TRUE(document()["paths"][std::string(op.path)].contains(std::string(op.method))) << label(op);
    }
}

TEST(OptionsDrift, QueryParametersMatchTheTable) {
    for (const auto& op : options::operations()) {
        SCOPED_TRACE(label(op));
        const json& operation = document()["paths"][std::string(op.path)][std::string(op.method)];
        std::map<std::string, json> documented;
        std::set<std::string> deprecated;
        for (const auto& parameter : operation.value("parameters", json::array())) {
            const json& p = resolve(parameter);
            if (p.value("in", "") != "query") continue;
            documented[p["name"]] = p["schema"];
            if (p.value("deprecated", false)) deprecated.insert(p["name"]);
        }
        for (const OptionSpec* option : options::all_options(op)) {
            const std::string name(option->name);
            const std::string where = "query parameter " + name + " of " + label(op);
            if (!option->on_query()) {
                EXPECT_FALSE(documented.count(name))
                    << where << ": documented, but the option table accepts it only in a JSON body";
                continue;
            }
            if (!documented.count(name)) {
                ADD_FAILURE() << where << ": in the option table, missing from OpenAPI";
                continue;
            }
            expect_same(documented[name], *option, where);
            EXPECT_FALSE(deprecated.count(name)) << where << ": marked deprecated, the option table has no such mark";
            // each deprecated alias: a parameter of its own, deprecated, of the option's type, range and default
            for (std::string_view alias_view : option->aliases) {
                const std::string alias(alias_view);
                const std::string alias_where =
                    "query parameter " + alias + " (deprecated alias of " + name + ") of " + label(op);
                if (!documented.count(alias)) {
                    ADD_FAILURE() << alias_where << ": in the option table, missing from OpenAPI";
                    continue;
                }
                EXPECT_TRUE(deprecated.count(alias)) << alias_where << ": not marked deprecated: true";
                expect_same(documented[alias], *option, alias_where);
            }
        }
        for (const auto& [name, schema] : documented) {
            const OptionSpec* option = options::find_option(op, name);
            EXPECT_TRUE(option && option->on_query())
                << "query parameter " << name << " of " << label(op) << ": in OpenAPI, missing from the option table";
        }
    }
}

TEST(OptionsDrift, JsonBodyMembersMatchTheTable) {
    for (const auto& op : options::operations()) {
        SCOPED_TRACE(label(op));
        const json& operation = document()["paths"][std::string(op.path)][std::string(op.method)];
        const json* body = nullptr;
        if (operation.contains("requestBody"))
            if (const auto& content = resolve(operation["requestBody"])["content"];
                content.contains("application/json"))
                body = &resolve(content["application/json"]["schema"]);
        bool any_json = false;
        for (const OptionSpec* option : options::all_options(op)) any_json = any_json || option->on_json();
        if (!any_json) continue;
        ASSERT_NE(body, nullptr) << label(op) << ": the option table has JSON options, OpenAPI has no JSON body";
        const json& properties = (*body)["properties"];

        // every table option where its transport puts it
        std::set<std::string> objects;
        for (const OptionSpec* option : options::all_options(op)) {
            if (!option->on_json()) continue;
            const std::string name(option->name);
            const std::string path = option->json_object.empty() ? name : std::string(option->json_object) + "." + name;
            const std::string where = "JSON member " + path + " of " + label(op);
            const json* container = &properties;
            if (!option->json_object.empty()) {
                objects.insert(std::string(option->json_object));
                if (!properties.contains(std::string(option->json_object))) {
                    ADD_FAILURE() << where << ": in the option table, OpenAPI has no " << option->json_object;
                    continue;
                }
                container = &resolve(properties[std::string(option->json_object)])["properties"];
            }
            if (!container->contains(name)) {
                ADD_FAILURE() << where << ": in the option table, missing from OpenAPI";
                continue;
            }
            expect_same((*container)[name], *option, where);
            EXPECT_FALSE(resolve((*container)[name]).value("deprecated", false))
                << where << ": marked deprecated, the option table has no such mark";
            // each deprecated alias (the readers accept them for members of the body itself): a member of its own,
            // deprecated, of the option's type, range and default
            if (!option->json_object.empty()) continue;
            for (std::string_view alias_view : option->aliases) {
                const std::string alias(alias_view);
                const std::string alias_where =
                    "JSON member " + alias + " (deprecated alias of " + name + ") of " + label(op);
                if (!container->contains(alias)) {
                    ADD_FAILURE() << alias_where << ": in the option table, missing from OpenAPI";
                    continue;
                }
                const json& schema = (*container)[alias];
                EXPECT_TRUE(schema.value("deprecated", false)) << alias_where << ": not marked deprecated: true";
                expect_same(schema, *option, alias_where);
            }
        }

        // every documented member is an input, an option or an object of options, and so is every member of those
        const std::vector<std::string_view> members = options::json_members(op);
        for (const auto& [name, schema] : properties.items()) {
            const bool known = std::find(members.begin(), members.end(), name) != members.end();
            EXPECT_TRUE(known) << "JSON member " << name << " of " << label(op)
                               << ": in OpenAPI, missing from the option table";
        }
        for (const std::string& object : objects) {
            if (!properties.contains(object)) continue;
            for (const auto& [name, schema] : resolve(properties[object])["properties"].items()) {
                const OptionSpec* option = options::find_option(op, name);
                EXPECT_TRUE(option && option->on_json() && option->json_object == object)
                    << "JSON member " << object << "." << name << " of " << label(op)
                    << ": in OpenAPI, missing from the option table";
            }
        }
    }
}

// A multipart/form-data upload carries the query parameters as text fields: its schema documents the same options
// (and the file part), so a form field is described exactly as the query parameter it stands for.
TEST(OptionsDrift, MultipartFieldsMatchTheQueryParameters) {
    int forms = 0;
    for (const auto& op : options::operations()) {
        const json& operation = document()["paths"][std::string(op.path)][std::string(op.method)];
        if (!operation.contains("requestBody")) continue;
        const json& content = resolve(operation["requestBody"])["content"];
        if (!content.contains("multipart/form-data")) continue;
        SCOPED_TRACE(label(op));
        ++forms;
        const json& properties = resolve(content["multipart/form-data"]["schema"])["properties"];
        EXPECT_TRUE(properties.contains("file")) << label(op) << ": the form has no file part";
        std::set<std::string> query;
        for (const OptionSpec* option : options::all_options(op)) {
            if (!option->on_query()) continue;
            const std::string name(option->name);
            query.insert(name);
            // a deprecated alias is a field too, documented as deprecated
            for (const std::string_view alias : option->aliases) {
                query.insert(std::string(alias));
                EXPECT_TRUE(properties.contains(std::string(alias)) &&
                            resolve(properties[std::string(alias)]).value("deprecated", false))
                    << "form field " << alias << " of " << label(op) << ": a deprecated alias, not documented so";
            }
            if (!properties.contains(name)) {
                ADD_FAILURE() << "form field " << name << " of " << label(op) << ": a query parameter, not a field";
                continue;
            }
            // (a field's text is read as the query parameter's: "query parameter" in `where` says so to expect_same)
            expect_same(resolve(properties[name]), *option,
                        "form field " + name + " (read as its query parameter) of " + label(op));
        }
        // a JSON part (contentMediaType application/json) carries JSON body members, described by its contentSchema
        for (const auto& [name, schema] : properties.items())
            EXPECT_TRUE(name == "file" || query.count(name) ||
                        resolve(schema).value("contentMediaType", "") == "application/json")
                << "form field " << name << " of " << label(op) << ": in OpenAPI, not a query parameter";
    }
    EXPECT_GE(forms, 6);  // subdivide, simplify, remesh, repair, tessellate, pointcloud
}

}  // namespace
}  // namespace surfaced::api
