// `surfaced query`: points and rays asked of a mesh file through POST /mesh/query; the answers as its JSON.
// `surfaced grid`: a mesh file or a scene as a narrow-band signed distance grid through POST /implicit/grid; the
// level_set scene node it answers as JSON. Both read a mesh file the same way (mesh_object).
// `surfaced limit`: the exact limit surface of a mesh file at (face, u, v) points through POST /limit/evaluate; the
// mesh goes as the multipart file part, so that OBJ subdivision tags and UVs reach the operation as they are.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/io/mesh_io.h"
#include "server/cli/commands.h"
#include "server/cli/requests.h"
#include "server/cli/table_options.h"

namespace surfaced::cli {
namespace {

constexpr std::string_view kQueryHelp =
    R"(Usage: surfaced query MESH_FILE --points FILE.json|- [--rays FILE.json|-] [--want LIST] [-o OUT.json|-]

Asks questions of the surface in MESH_FILE through the same operation as POST /mesh/query: for each point whether it
is inside (generalized winding number >= 1/2, robust on meshes with holes), its winding number, its signed distance
(negative inside) and the closest surface point with its face; for each ray the first hit (t, face, point, normal).
  MESH_FILE: .obj .off .ply .stl .glb .gltf, or .json (a mesh object, or a body with "mesh"); - reads standard input
  --points FILE: a JSON array of [x, y, z] (or an object with "points"); --rays FILE: a JSON array of
  [ox, oy, oz, dx, dy, dz] (or an object with "rays"). OUT (default -: standard output) is the JSON answer.

)";

constexpr std::string_view kGridHelp =
    R"(Usage: surfaced grid IN --voxel-size H [--band W] [--bounds B] [-o OUT.json|-]

Samples a narrow-band signed distance grid through the same operation as POST /implicit/grid: for a mesh, the exact
distance to the nearest triangle at every node within W voxels of the surface, signed by the generalized winding
number (negative inside; robust on meshes with holes), and +-W * H beyond; for a scene, its value clamped to +-W * H.
  IN: a mesh file (.obj .off .ply .stl .glb .gltf), or .json: a mesh object, a scene ({"op": ...}, needs --bounds),
  or a request body with "mesh" or "scene"; - reads standard input. OUT (default -: standard output) is the
  level_set scene node, usable as a scene (or part of one) by surfaced implicit.

)";

constexpr std::string_view kLimitHelp =
    R"(Usage: surfaced limit MESH_FILE --points FILE.json|- [options] [--derivatives 2] [-o OUT.json|-]

Evaluates the exact Catmull-Clark limit surface of MESH_FILE (the surface surfaced subdivide converges to with the
same options and the file's subdivision tags) through the same operation as POST /limit/evaluate: per point its
position, derivatives du and dv with respect to (u, v), unit normal, with --derivatives 2 also duu, duv, dvv, the
limit of the mesh's UVs when it has them, and whether the answer is exact (false only within 2^-24 of an
extraordinary vertex).
  MESH_FILE: .obj (with its t crease/corner/hole/interpolateboundary tags and vt UVs) .off .ply .stl .glb .gltf, or
  .json (a mesh object, or a request body with "mesh"); - reads standard input (format from --input-format, else
  from the bytes).
  --points FILE: a JSON array of {"face": f, "uv": [u, v]} (or an object with "points"). (face, u, v) is OpenSubdiv
  Bfr's parameterization: [0, 1]^2 on a quad; an N-gon is N tiles [x, x + 1/2] x [y, y + 1/2] (docs/subdivision.md).
  OUT (default -: standard output) is the JSON answer, {"points": [{"position": ..., ...}, ...]}.
Exit codes: 0 answered; 1 the operation failed (the mesh's geometry or format, a budget, a file that cannot be
read); 2 bad usage, including a point the operation refuses (a face out of range or a hole, (u, v) outside the
face's domain: printed with its field, points[k].face or points[k].uv) and a scheme it does not evaluate.

)";

constexpr std::string_view kWantNames[] = {"inside", "winding_number", "distance", "closest"};

//! --want: a comma-separated list of kWantNames.
std::string checked_want(std::string_view option, const std::string& text) {
    const std::vector<std::string_view> allowed(std::begin(kWantNames), std::end(kWantNames));
    std::istringstream in(text);
    std::size_t count = 0;
    for (std::string item; std::getline(in, item, ',');) {
        if (std::find(allowed.begin(), allowed.end(), item) == allowed.end())
            throw unknown_value(option, item, allowed);
        ++count;
    }
    if (count == 0 || text.ends_with(",")) throw unknown_value(option, text, allowed);
    return text;
}

//! Reads a JSON file; nullopt (and why, printed) when it cannot be read or is not JSON.
std::optional<nlohmann::json> read_json_file(const std::string& path) {
    const auto bytes = read_input(path);
    if (!bytes) return std::nullopt;
    nlohmann::json doc = nlohmann::json::parse(*bytes, nullptr, false);
    if (doc.is_discarded()) {
        std::cerr << "surfaced: " << (path == "-" ? "standard input" : path) << ": not valid JSON\n";
        return std::nullopt;
    }
    return doc;
}

//! `member` of a file that is either the array itself or an object holding it.
nlohmann::json member_or_self(nlohmann::json doc, const char* member) {
    if (doc.is_object() && doc.contains(member)) return std::move(doc[member]);
    return doc;
}

//! The mesh of MESH_FILE as the JSON mesh object; nullopt (and why, printed) when it cannot be read.
std::optional<nlohmann::json> mesh_object(const Parsed& parsed) {
    const bool json_file = parsed.has("--input-format") ? parsed.value("--input-format") == "json"
                                                        : lower_extension(parsed.input) == ".json";
    const auto bytes = read_input(parsed.input);
    if (!bytes) return std::nullopt;
    const bool looks_json = parsed.from_stdin() && !parsed.has("--input-format") &&
                            bytes->find_first_not_of(" \t\r\n") != std::string::npos &&
                            (*bytes)[bytes->find_first_not_of(" \t\r\n")] == '{';
    if (json_file || looks_json) {
        nlohmann::json doc = nlohmann::json::parse(*bytes, nullptr, false);
        if (doc.is_discarded()) {
            std::cerr << "surfaced: " << parsed.input_label() << ": not valid JSON\n";
            return std::nullopt;
        }
        return member_or_self(std::move(doc), "mesh");
    }
    const auto named = mesh_input_format(parsed);
    const MeshFormat format = named ? *named : sniff_mesh_format(*bytes);
    auto mesh = read_mesh(*bytes, format);
    if (!mesh) {
        std::cerr << "surfaced: " << parsed.input_label() << ": " << mesh.error().message << "\n";
        return std::nullopt;
    }
    nlohmann::json positions = nlohmann::json::array(), faces = nlohmann::json::array();
    for (const Vec3& p : mesh->positions) positions.push_back({p.x, p.y, p.z});
    for (std::size_t f = 0; f < mesh->face_count(); ++f) {
        const auto face = mesh->face(f);
        faces.push_back(std::vector<Index>(face.begin(), face.end()));
    }
    return nlohmann::json{{"positions", std::move(positions)}, {"faces", std::move(faces)}};
}

//! The arguments with "-o -" added when no output was named (the answer then goes to standard output).
std::vector<std::string> with_default_output(Args& args) {
    std::vector<std::string> out;
    bool output = false;
    while (!args.done()) {
        out.push_back(args.next());
        const std::string& arg = out.back();
        if (arg == "-o" || arg == "--output" || arg.starts_with("--output=") || arg == "-h" || arg == "--help")
            output = true;
    }
    if (!output) {
        out.emplace_back("-o");
        out.emplace_back("-");
    }
    return out;
}

//! A multipart/form-data body with the parts `file` (`bytes`, of `media_type`) and `request` (JSON), and its
//! boundary: one that does not occur in either part.
std::pair<std::string, std::string> form_body(std::string_view bytes, std::string_view media_type,
                                              const std::string& request) {
    std::string boundary = "surfaced-limit-form";
    while (bytes.find(boundary) != std::string_view::npos || request.find(boundary) != std::string::npos)
        boundary += "-x";
    std::string body = "--" + boundary +
                       "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"mesh\"\r\nContent-Type: " +
                       std::string(media_type) + "\r\n\r\n";
    body += bytes;
    body += "\r\n--" + boundary +
            "\r\nContent-Disposition: form-data; name=\"request\"\r\nContent-Type: application/json\r\n\r\n" + request +
            "\r\n--" + boundary + "--\r\n";
    return {std::move(body), std::move(boundary)};
}

}  // namespace

int limit(Args& sent) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("limit_evaluate");
    std::vector<Option> options = table_options(operation, api::options::kJson);
    options.push_back(Option{.name = "--input-format",
                             .check = one_of_names({"obj", "off", "ply", "stl", "glb", "gltf", "json"}),
                             .synopsis = "--input-format NAME",
                             .description =
                                 "MESH_FILE's format instead of its extension: obj off ply stl glb gltf json "
                                 "(MESH_FILE -: from the bytes)"});
    options.push_back(Option{.name = "--points",
                             .check = [](std::string_view, const std::string& text) { return text; },
                             .synopsis = "--points FILE.json",
                             .description = "the points, a JSON array of {\"face\": f, \"uv\": [u, v]} (- : standard "
                                            "input)"});
    std::vector<std::string> words = with_default_output(sent);
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    Args args(static_cast<int>(argv.size()), argv.data(), 0);
    std::string help = std::string(kLimitHelp) + options_help(operation, options);
    constexpr std::string_view kRequired = "output file (required); - for standard output";
    if (const auto at = help.find(kRequired); at != std::string::npos)
        help.replace(at, kRequired.size(), "the JSON answer; - (the default) for standard output");
    const auto parsed = parse_file_command(args, "limit", help, options, "MESH_FILE");
    if (!parsed) return kExitOk;
    if (parsed->has("--format")) throw UsageError{"limit: the answer is JSON; --format does not apply"};
    if (!parsed->has("--points")) throw UsageError{"limit: give --points FILE"};
    if (parsed->from_stdin() && parsed->value("--points") == "-")
        throw UsageError{"limit: only one of MESH_FILE and --points can be standard input"};

    // the request: the options and points, with the mesh in it (a JSON file) or as the file part (any other)
    nlohmann::json body = nlohmann::json::object();
    const auto points = read_json_file(parsed->value("--points"));
    if (!points) return kExitFailed;
    for (const auto& [name, text] : parsed->params) {
        const api::options::OptionSpec& spec = table_option(operation, name);
        if (spec.type == api::options::OptionType::Integer)
            body[name] = std::stoll(text);
        else if (spec.type == api::options::OptionType::Number)
            body[name] = std::stod(text);
        else if (spec.type == api::options::OptionType::Bool)
            body[name] = text == "true";
        else
            body[name] = text;
    }
    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    const bool json_file = parsed->has("--input-format") ? parsed->value("--input-format") == "json"
                           : parsed->from_stdin()        ? bytes->find_first_not_of(" \t\r\n") != std::string::npos &&
                                                        (*bytes)[bytes->find_first_not_of(" \t\r\n")] == '{'
                                                  : lower_extension(parsed->input) == ".json";
    api::ApiRequest request;
    std::string form;
    std::string json_text;
    if (json_file) {
        nlohmann::json doc = nlohmann::json::parse(*bytes, nullptr, false);
        if (doc.is_discarded()) {
            std::cerr << "surfaced: " << parsed->input_label() << ": not valid JSON\n";
            return kExitFailed;
        }
        // a request body keeps its own members (tags, options); the command line's win
        if (doc.is_object() && doc.contains("mesh")) {
            for (auto it = body.begin(); it != body.end(); ++it) doc[it.key()] = it.value();
            body = std::move(doc);
        } else {
            body["mesh"] = std::move(doc);
        }
        body["points"] = member_or_self(*points, "points");
        json_text = body.dump();
        request = upload_request("/limit/evaluate", "application/json", json_text, {});
    } else {
        body["points"] = member_or_self(*points, "points");
        const auto named = mesh_input_format(*parsed);
        // from standard input without --input-format the operation sniffs the bytes
        const std::string media_type =
            named ? std::string(api::enum_name(api::kMeshMediaTypes, *named)) : "application/octet-stream";
        auto [text, boundary] = form_body(*bytes, media_type, body.dump());
        form = std::move(text);
        request = upload_request("/limit/evaluate", "multipart/form-data; boundary=" + boundary, form, {});
    }
    return finish(
        api::dispatch(request, context), *parsed,
        [&](const api::ApiResponse&) {
            const std::size_t count = body["points"].is_array() ? body["points"].size() : 0;
            parsed->report() << "wrote " << parsed->output_label() << ": " << count << " limit points\n";
        },
        ProblemStyle{.field = true, .line = false, .offset = false});
}

int query(Args& sent) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("mesh_query");
    std::vector<Option> options = table_options(operation, api::options::kJson);
    options.push_back(Option{.name = "--input-format",
                             .check = one_of_names({"obj", "off", "ply", "stl", "glb", "gltf", "json"}),
                             .synopsis = "--input-format NAME",
                             .description =
                                 "MESH_FILE's format instead of its extension: obj off ply stl glb gltf json "
                                 "(MESH_FILE -: from the bytes)"});
    options.push_back(Option{.name = "--points",
                             .check = [](std::string_view, const std::string& text) { return text; },
                             .synopsis = "--points FILE.json",
                             .description = "the query points, a JSON array of [x, y, z] (- : standard input)"});
    options.push_back(Option{.name = "--rays",
                             .check = [](std::string_view, const std::string& text) { return text; },
                             .synopsis = "--rays FILE.json",
                             .description = "the rays, a JSON array of [ox, oy, oz, dx, dy, dz] (- : standard input)"});
    options.push_back(Option{.name = "--want",
                             .check = checked_want,
                             .synopsis = "--want LIST",
                             .description = "point answers, comma-separated: inside, winding_number, distance, "
                                            "closest (default: all)"});
    std::vector<std::string> words = with_default_output(sent);
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    Args args(static_cast<int>(argv.size()), argv.data(), 0);
    // OUT is optional here (with_default_output): the shared help's "(required)" does not apply.
    std::string help = std::string(kQueryHelp) + options_help(operation, options);
    constexpr std::string_view kRequired = "output file (required); - for standard output";
    if (const auto at = help.find(kRequired); at != std::string::npos)
        help.replace(at, kRequired.size(), "the JSON answer; - (the default) for standard output");
    const auto parsed = parse_file_command(args, "query", help, options, "MESH_FILE");
    if (!parsed) return kExitOk;
    if (parsed->has("--format")) throw UsageError{"query: the answer is JSON; --format does not apply"};
    if (!parsed->has("--points") && !parsed->has("--rays"))
        throw UsageError{"query: give --points FILE or --rays FILE"};
    const int from_stdin = (parsed->from_stdin() ? 1 : 0) +
                           (parsed->has("--points") && parsed->value("--points") == "-") +
                           (parsed->has("--rays") && parsed->value("--rays") == "-");
    if (from_stdin > 1) throw UsageError{"query: only one of MESH_FILE, --points and --rays can be standard input"};

    nlohmann::json body;
    const auto mesh = mesh_object(*parsed);
    if (!mesh) return kExitFailed;
    body["mesh"] = *mesh;
    if (parsed->has("--points")) {
        const auto points = read_json_file(parsed->value("--points"));
        if (!points) return kExitFailed;
        body["points"] = member_or_self(*points, "points");
    }
    if (parsed->has("--rays")) {
        const auto rays = read_json_file(parsed->value("--rays"));
        if (!rays) return kExitFailed;
        body["rays"] = member_or_self(*rays, "rays");
    }
    if (parsed->has("--want")) {
        nlohmann::json want = nlohmann::json::array();
        std::istringstream in(parsed->value("--want"));
        for (std::string item; std::getline(in, item, ',');) want.push_back(item);
        body["want"] = std::move(want);
    }
    for (const auto& [name, text] : parsed->params) {
        const api::options::OptionSpec& spec = table_option(operation, name);
        nlohmann::json& container = spec.json_object.empty() ? body : body[std::string(spec.json_object)];
        if (spec.type == api::options::OptionType::Bool)
            container[name] = text == "true";
        else
            container[name] = std::stod(text);
    }
    return finish(
        api::dispatch(upload_request("/mesh/query", "application/json", body.dump(), {}), context), *parsed,
        [&](const api::ApiResponse&) {
            const std::size_t points = body.contains("points") && body["points"].is_array() ? body["points"].size() : 0;
            const std::size_t rays = body.contains("rays") && body["rays"].is_array() ? body["rays"].size() : 0;
            parsed->report() << "wrote " << parsed->output_label() << ": " << points << " points, " << rays
                             << " rays answered\n";
        },
        ProblemStyle{.field = true, .line = false, .offset = false});
}

int grid(Args& sent) {
    api::ApiContext context = file_context();
    const api::options::OperationOptions& operation = *api::options::operation_options("implicit_grid");
    std::vector<Option> options = table_options(operation, api::options::kJson);
    options.push_back(Option{.name = "--input-format",
                             .check = one_of_names({"obj", "off", "ply", "stl", "glb", "gltf", "json"}),
                             .synopsis = "--input-format NAME",
                             .description = "IN's format instead of its extension: obj off ply stl glb gltf json "
                                            "(IN -: from the bytes)"});
    options.push_back(Option{.name = "--bounds",
                             .check =
                                 [](std::string_view option, const std::string& text) {
                                     std::istringstream in(text);
                                     std::size_t count = 0;
                                     for (std::string number; std::getline(in, number, ',');) {
                                         checked_real(option, number);
                                         ++count;
                                     }
                                     if (count != 6 || text.ends_with(","))
                                         throw UsageError{std::string(option) +
                                                          " needs six numbers xmin,ymin,zmin,xmax,ymax,zmax, got \"" +
                                                          text + "\""};
                                     return text;
                                 },
                             .synopsis = "--bounds X0,Y0,Z0,X1,Y1,Z1",
                             .description = "the grid's box (required for a scene; a mesh's default: its box grown "
                                            "by band + 1 voxels)"});
    std::vector<std::string> words = with_default_output(sent);
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    Args args(static_cast<int>(argv.size()), argv.data(), 0);
    std::string help = std::string(kGridHelp) + options_help(operation, options);
    constexpr std::string_view kRequired = "output file (required); - for standard output";
    if (const auto at = help.find(kRequired); at != std::string::npos)
        help.replace(at, kRequired.size(), "the level_set node; - (the default) for standard output");
    const auto parsed = parse_file_command(args, "grid", help, options, "IN");
    if (!parsed) return kExitOk;
    if (parsed->has("--format")) throw UsageError{"grid: the answer is JSON; --format does not apply"};
    if (!parsed->param("voxel_size")) throw UsageError{"grid: give --voxel-size H"};

    // the request body: a JSON file as it is (a body, a scene or a mesh), any other file as its mesh
    nlohmann::json body = nlohmann::json::object();
    const bool json_file = parsed->has("--input-format") ? parsed->value("--input-format") == "json"
                                                         : lower_extension(parsed->input) == ".json";
    if (json_file) {
        const auto doc = read_json_file(parsed->input);
        if (!doc) return kExitFailed;
        if (doc->is_object() && (doc->contains("mesh") || doc->contains("scene")))
            body = *doc;
        else if (doc->is_object() && doc->contains("op"))
            body["scene"] = *doc;
        else
            body["mesh"] = *doc;
    } else {
        const auto mesh = mesh_object(*parsed);
        if (!mesh) return kExitFailed;
        body["mesh"] = *mesh;
    }
    if (parsed->has("--bounds")) {
        std::vector<double> v;
        std::istringstream in(parsed->value("--bounds"));
        for (std::string number; std::getline(in, number, ',');) v.push_back(std::stod(number));
        body["bounds"] = nlohmann::json::array({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    }
    if (body.contains("scene") && !body.contains("bounds"))
        throw UsageError{"grid: " + parsed->input_label() + " is a scene: give --bounds xmin,ymin,zmin,xmax,ymax,zmax"};
    for (const auto& [name, text] : parsed->params) {
        const api::options::OptionSpec& spec = table_option(operation, name);
        if (spec.type == api::options::OptionType::Integer)
            body[name] = std::stoll(text);
        else
            body[name] = std::stod(text);
    }
    return finish(
        api::dispatch(upload_request("/implicit/grid", "application/json", body.dump(), {}), context), *parsed,
        [&](const api::ApiResponse& response) {
            parsed->report() << "wrote " << parsed->output_label() << ": grid " << header(response, "X-Grid") << ", "
                             << header(response, "X-Band-Nodes") << " nodes in the band, in "
                             << header(response, "X-Elapsed-Ms") << " ms\n";
        },
        ProblemStyle{.field = true, .line = false, .offset = false});
}

}  // namespace surfaced::cli
