#include "server/cli.h"

#include <pthread.h>
#include <signal.h>

#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "api/dto.h"
#include "api/routes.h"
#include "geometry/io/mesh_io.h"
#include "server/http_server.h"

#ifndef SURFACED_VERSION
#define SURFACED_VERSION "unknown"
#endif
#ifndef SURFACED_DEFAULT_WEB_ROOT
#define SURFACED_DEFAULT_WEB_ROOT ""
#endif

namespace surfaced::cli {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitFailed = 1;
constexpr int kExitUsage = 2;

constexpr std::string_view kMainHelp = R"(surfaced - geometry service: subdivision, Bezier patch tessellation and simplification over HTTP/JSON and on the command line

Usage:
  surfaced serve [options]                    run the HTTP service
  surfaced subdivide IN -o OUT [options]      subdivide a mesh file
  surfaced tessellate IN -o OUT [options]     tessellate Bezier patches (.bez/.bbp, sample:teapot)
  surfaced simplify IN -o OUT [options]       simplify a mesh file (QEM edge collapse)
  surfaced <command> --help                   options of a command
  surfaced --help | --version

Exit codes: 0 success, 1 the operation failed, 2 bad usage.
)";

constexpr std::string_view kServeHelp = R"(Usage: surfaced serve [options]

Runs the HTTP service until SIGINT or SIGTERM.

Options:
  --host H               address to listen on (default 127.0.0.1; 0.0.0.0 for all interfaces)
  --port P               TCP port, 0 for any free port (default 8080)
  --threads N            worker threads = connections served at once (default: one per CPU, at least 2)
  --web-root DIR         static files served at / (default: the source tree's clients/web)
  --max-body-mb N        largest request body in MiB; larger ones get 413 (default 64)
  --max-levels N         largest subdivision levels accepted (default 8)
  --max-output-faces N   largest predicted output face count accepted (default 4000000)
  -h, --help             this text

Endpoints:
)";

constexpr std::string_view kSubdivideHelp = R"(Usage: surfaced subdivide IN -o OUT [options]

Subdivides the mesh in IN and writes it to OUT, through the same operation as POST /subdivide.
Formats come from the file extensions:
  IN:  .obj .off .ply .stl .glb
  OUT: .obj .ply .glb .gltf (glTF, Draco-compressed unless --no-draco; .gltf is one JSON file with the
       data embedded) .json ({"mesh": ..., "stats": ...})

Options:
  -o, --output OUT          output file (required)
  --scheme S                catmull-clark (default) or loop (triangle meshes only)
  --levels N                refinement levels (default 1)
  --boundary B              edge-only, edge-and-corner or none (default: the file's
                            `t interpolateboundary` tag, else edge-only)
  --crease-method M         uniform (default) or chaikin: how semi-sharp creases decay
  --triangle-rule R         catmark (default) or smooth: Catmull-Clark weights next to triangles
  --loop-weights W          loop (default, as OpenSubdiv) or warren (3/(8n); not OpenSubdiv's surface)
  --uv-interpolation M      texture coordinates: none, corners-only, corners-plus1 (default),
                            corners-plus2, boundaries or all (OpenSubdiv's FVAR_LINEAR_*)
  --limit-surface           project the result onto the limit surface (normals from limit tangents)
  --max-faces N             use the largest level (up to --levels, if given) with at most N faces
  --no-draco                write uncompressed glTF (.glb, .gltf)
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb only)
  --normals                 also write vertex normals (.glb .obj .ply)
  --max-output-faces N      refuse if the result would have more faces (default 4000000)
  -h, --help                this text
)";

struct UsageError {
    std::string message;
};

//! Splits argv into options and positionals; accepts "--name value" and "--name=value".
class Args {
public:
    Args(int argc, char** argv, int first) {
        for (int i = first; i < argc; ++i) args_.emplace_back(argv[i]);
    }
    bool done() const { return pos_ >= args_.size(); }
    std::string next() { return args_[pos_++]; }
    //! The value of option `name` (inline after '=' or the next argument).
    std::string value(std::string_view name, std::optional<std::string>& inline_value) {
        if (inline_value) return *std::exchange(inline_value, std::nullopt);
        if (done()) throw UsageError{std::string(name) + " needs a value"};
        return next();
    }

private:
    std::vector<std::string> args_;
    std::size_t pos_ = 0;
};

long long parse_number(std::string_view name, const std::string& text, long long min, long long max) {
    long long value = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || result.ec != std::errc() || result.ptr != text.data() + text.size())
        throw UsageError{std::string(name) + " needs an integer, got \"" + text + "\""};
    if (value < min || value > max)
        throw UsageError{std::string(name) + " must be between " + std::to_string(min) + " and " + std::to_string(max) +
                         ", got " + text};
    return value;
}

template <class E, std::size_t N>
std::string checked_enum(std::string_view name, const std::string& text, const api::EnumName<E> (&table)[N]) {
    if (!api::enum_from_name(table, text))
        throw UsageError{std::string(name) + ": unknown value \"" + text + "\" (allowed: " + api::enum_names(table) + ")"};
    return text;
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool read_file(const std::string& path, std::string& out, std::string& error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open " + path + ": " + std::strerror(errno);
        return false;
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) {
        error = "cannot read " + path;
        return false;
    }
    out = std::move(buffer).str();
    return true;
}

bool write_file(const std::string& path, std::string_view bytes, std::string& error) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) {
        error = "cannot create " + path + ": " + std::strerror(errno);
        return false;
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
        error = "cannot write " + path;
        return false;
    }
    return true;
}

std::string header(const api::ApiResponse& response, std::string_view name) {
    for (const auto& [key, value] : response.headers)
        if (key == name) return value;
    return "?";
}

// ---- serve ---------------------------------------------------------------------------------------------------

int serve(Args& args) {
    server::ServerConfig config;
    config.web_root = SURFACED_DEFAULT_WEB_ROOT;
    bool web_root_given = false;
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (arg == "-h" || arg == "--help") {
            std::cout << kServeHelp;
            for (const api::Route& route : api::routes())
                std::cout << "  " << route.method << " " << route.path << "  " << route.description << "\n";
            return kExitOk;
        } else if (arg == "--host") {
            config.host = args.value(arg, inline_value);
        } else if (arg == "--port") {
            config.port = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 65535));
        } else if (arg == "--threads") {
            config.threads = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1024));
        } else if (arg == "--web-root") {
            config.web_root = args.value(arg, inline_value);
            web_root_given = true;
        } else if (arg == "--max-body-mb") {
            config.limits.max_body_bytes = static_cast<std::size_t>(
                parse_number(arg, args.value(arg, inline_value), 1, 1 << 20)) << 20;
        } else if (arg == "--max-levels") {
            config.limits.max_levels = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 16));
        } else if (arg == "--max-output-faces") {
            config.limits.max_output_faces = static_cast<std::uint64_t>(
                parse_number(arg, args.value(arg, inline_value), 1, 4'000'000'000LL));
        } else {
            throw UsageError{"serve: unknown argument \"" + arg + "\""};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    std::error_code ec;
    if (web_root_given && !std::filesystem::is_directory(config.web_root, ec))
        throw UsageError{"--web-root " + config.web_root + " is not a directory"};

    // Block the stop signals before any thread exists, so every thread inherits the mask and the main thread
    // receives them synchronously with sigwait (no async-signal-safety concerns in a handler).
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    server::HttpServer http(config);
    std::string error;
    if (!http.start(&error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    std::cout << "surfaced " << SURFACED_VERSION << " listening on http://" << config.host << ":" << http.port()
              << "/ (" << http.threads() << " threads, web client: "
              << (http.serves_web_root() ? config.web_root : std::string("none")) << ")" << std::endl;

    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "surfaced: " << (signal_number == SIGINT ? "SIGINT" : "SIGTERM") << ", stopping" << std::endl;
    http.stop();
    return kExitOk;
}

// ---- subdivide -----------------------------------------------------------------------------------------------

int subdivide(Args& args) {
    std::string input, output;
    std::optional<std::string> scheme, levels, boundary, quantize, crease_method, triangle_rule, max_faces, uv_mode,
        loop_weights;
    bool no_draco = false, normals = false, limit_surface = false;
    api::ApiContext context;
    // Files are the user's own: the body limit protects the server's memory, not the CLI's.
    context.limits.max_body_bytes = static_cast<std::size_t>(-1);
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (arg == "-h" || arg == "--help") {
            std::cout << kSubdivideHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--scheme") {
            scheme = checked_enum(arg, args.value(arg, inline_value), api::kSchemeNames);
        } else if (arg == "--levels") {
            levels = std::to_string(parse_number(arg, args.value(arg, inline_value), 0, 1'000'000));
        } else if (arg == "--boundary") {
            boundary = checked_enum(arg, args.value(arg, inline_value), api::kBoundaryNames);
        } else if (arg == "--crease-method") {
            crease_method = checked_enum(arg, args.value(arg, inline_value), api::kCreaseMethodNames);
        } else if (arg == "--triangle-rule") {
            triangle_rule = checked_enum(arg, args.value(arg, inline_value), api::kTriangleRuleNames);
        } else if (arg == "--loop-weights") {
            loop_weights = checked_enum(arg, args.value(arg, inline_value), api::kLoopWeightNames);
        } else if (arg == "--uv-interpolation") {
            uv_mode = checked_enum(arg, args.value(arg, inline_value), api::kUvInterpolationNames);
        } else if (arg == "--max-faces") {
            max_faces = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 4'000'000'000LL));
        } else if (arg == "--limit-surface") {
            limit_surface = true;
        } else if (arg == "--quantize-position") {
            quantize = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 24));
        } else if (arg == "--max-output-faces") {
            context.limits.max_output_faces = static_cast<std::uint64_t>(
                parse_number(arg, args.value(arg, inline_value), 1, 4'000'000'000LL));
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--normals") {
            normals = true;
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"subdivide: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"subdivide: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"subdivide: missing input file"};
    if (output.empty()) throw UsageError{"subdivide: missing -o OUT"};

    const std::string in_ext = lower_extension(input);
    const std::string out_ext = lower_extension(output);
    if (in_ext == ".gltf") throw UsageError{".gltf input is not supported yet; use .glb"};
    const auto in_format = format_from_extension(input);
    if (!in_format)
        throw UsageError{"cannot tell the format of " + input + " from its extension (use .obj .off .ply .stl .glb)"};
    std::optional<api::OutputFormat> out_format;
    if (out_ext == ".obj") out_format = api::OutputFormat::Obj;
    else if (out_ext == ".ply") out_format = api::OutputFormat::Ply;
    else if (out_ext == ".glb") out_format = api::OutputFormat::Glb;
    else if (out_ext == ".gltf") out_format = api::OutputFormat::Gltf;
    else if (out_ext == ".json") out_format = api::OutputFormat::Json;
    else throw UsageError{"cannot tell the output format of " + output + " from its extension (use .obj .ply .glb .gltf .json)"};
    const bool gltf = *out_format == api::OutputFormat::Glb || *out_format == api::OutputFormat::Gltf;
    if (quantize && !gltf) throw UsageError{"--quantize-position applies only to .glb and .gltf output"};
    if (quantize && no_draco) throw UsageError{"--quantize-position applies only with Draco (drop --no-draco)"};
    if (normals && *out_format == api::OutputFormat::Json)
        throw UsageError{"--normals is not available for .json output"};

    std::string bytes, error;
    if (!read_file(input, bytes, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }

    // The request POST /subdivide would receive for this upload: one code path for the CLI and the service.
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/subdivide";
    request.content_type = std::string(api::enum_name(api::kMeshMediaTypes, *in_format));
    request.body = bytes;
    if (scheme) request.query.emplace("scheme", *scheme);
    if (levels) request.query.emplace("levels", *levels);
    if (boundary) request.query.emplace("boundary", *boundary);
    if (crease_method) request.query.emplace("crease_method", *crease_method);
    if (triangle_rule) request.query.emplace("triangle_rule", *triangle_rule);
    if (max_faces) request.query.emplace("max_faces", *max_faces);
    if (uv_mode) request.query.emplace("uv_interpolation", *uv_mode);
    if (loop_weights) request.query.emplace("loop_weights", *loop_weights);
    if (limit_surface) request.query.emplace("limit_surface", "true");
    request.query.emplace("format", std::string(api::enum_name(api::kOutputFormatNames, *out_format)));
    if (no_draco && gltf) request.query.emplace("compression", "none");
    if (quantize) request.query.emplace("quantize_position", *quantize);
    if (normals) request.query.emplace("normals", "true");

    const api::ApiResponse response = api::dispatch(request, context);
    if (response.status >= 400) {
        std::cerr << "surfaced: " << input << ": ";
        if (response.error) {
            std::cerr << response.error->detail;
            if (response.error->line) std::cerr << " (line " << *response.error->line << ")";
            else if (response.error->offset) std::cerr << " (byte offset " << *response.error->offset << ")";
            std::cerr << " [" << response.error->code << "]";
        } else {
            std::cerr << "failed with status " << response.status;
        }
        std::cerr << "\n";
        return kExitFailed;
    }
    if (!write_file(output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    std::cout << "wrote " << output << ": " << header(response, "X-Output-Vertices") << " vertices, "
              << header(response, "X-Output-Faces") << " faces (from " << header(response, "X-Input-Vertices")
              << " vertices, " << header(response, "X-Input-Faces") << " faces) in "
              << header(response, "X-Elapsed-Ms") << " ms\n";
    return kExitOk;
}

// ---- tessellate ----------------------------------------------------------------------------------------------

constexpr std::string_view kTessellateHelp = R"(Usage: surfaced tessellate IN -o OUT (--tolerance T | --segments N) [options]

Tessellates the Bezier patches in IN (a geomview .bez/.bbp file, or sample:teapot for a built-in sample) into a
crack-free triangle mesh with normals and UVs, through the same operation as POST /tessellate (GET /patches/NAME).

Options:
  -o, --output OUT          output file: .glb (Draco-compressed unless --no-draco), .obj or .ply (required)
  --tolerance T             guaranteed maximum distance between triangles and surface (model units)
  --segments N              segments along each direction of every patch (default 8)
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..30 (default 14; .glb only)
  --no-normals              leave out vertex normals
  --max-output-faces N      refuse if the result could have more triangles (default 4000000)
  -h, --help                this text
)";

int tessellate(Args& args) {
    std::string input, output;
    std::optional<std::string> tolerance, segments, quantize;
    bool no_draco = false, no_normals = false;
    api::ApiContext context;
    context.limits.max_body_bytes = static_cast<std::size_t>(-1);  // the user's own file
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (arg == "-h" || arg == "--help") {
            std::cout << kTessellateHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--tolerance") {
            tolerance = args.value(arg, inline_value);
            double value = 0;
            const auto r = std::from_chars(tolerance->data(), tolerance->data() + tolerance->size(), value);
            if (tolerance->empty() || r.ec != std::errc() || r.ptr != tolerance->data() + tolerance->size() ||
                !(value > 0))
                throw UsageError{"--tolerance needs a number > 0, got \"" + *tolerance + "\""};
        } else if (arg == "--segments") {
            segments = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 1'000'000));
        } else if (arg == "--quantize-position") {
            quantize = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 30));
        } else if (arg == "--max-output-faces") {
            context.limits.max_output_faces = static_cast<std::uint64_t>(
                parse_number(arg, args.value(arg, inline_value), 1, 4'000'000'000LL));
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--no-normals") {
            no_normals = true;
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"tessellate: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"tessellate: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"tessellate: missing input file"};
    if (output.empty()) throw UsageError{"tessellate: missing -o OUT"};
    if (tolerance && segments) throw UsageError{"tessellate: give --tolerance or --segments, not both"};
    const std::string out_ext = lower_extension(output);
    std::string format;
    if (out_ext == ".glb") format = "glb";
    else if (out_ext == ".obj") format = "obj";
    else if (out_ext == ".ply") format = "ply";
    else throw UsageError{"cannot tell the output format of " + output + " from its extension (use .glb .obj .ply)"};
    if (quantize && (format != "glb" || no_draco))
        throw UsageError{"--quantize-position applies only to .glb output with Draco"};

    // The request POST /tessellate (or GET /patches/NAME) would receive: one code path for CLI and service.
    api::ApiRequest request;
    std::string bytes, error;
    if (input.starts_with("sample:")) {
        request.method = "GET";
        request.path = "/patches/" + input.substr(7);
    } else {
        if (!read_file(input, bytes, error)) {
            std::cerr << "surfaced: " << error << "\n";
            return kExitFailed;
        }
        request.method = "POST";
        request.path = "/tessellate";
        request.content_type = "application/x-geomview-bez";
        request.body = bytes;
    }
    if (tolerance) request.query.emplace("tolerance", *tolerance);
    if (segments) request.query.emplace("segments", *segments);
    request.query.emplace("format", format);
    if (no_draco && format == "glb") request.query.emplace("compression", "none");
    if (quantize) request.query.emplace("quantize_position", *quantize);
    if (no_normals) request.query.emplace("normals", "false");

    const api::ApiResponse response = api::dispatch(request, context);
    if (response.status >= 400) {
        std::cerr << "surfaced: " << input << ": ";
        if (response.error) {
            std::cerr << response.error->detail;
            if (response.error->line) std::cerr << " (line " << *response.error->line << ")";
            std::cerr << " [" << response.error->code << "]";
        } else {
            std::cerr << "failed with status " << response.status;
        }
        std::cerr << "\n";
        return kExitFailed;
    }
    if (!write_file(output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    std::cout << "wrote " << output << ": " << header(response, "X-Output-Vertices") << " vertices, "
              << header(response, "X-Output-Faces") << " triangles from " << header(response, "X-Patches")
              << " patches, max deviation <= " << header(response, "X-Error-Bound") << ", in "
              << header(response, "X-Elapsed-Ms") << " ms\n";
    return kExitOk;
}

// ---- simplify ------------------------------------------------------------------------------------------------

constexpr std::string_view kSimplifyHelp = R"(Usage: surfaced simplify IN -o OUT (--target-faces N | --ratio R | --max-error E) [options]

Simplifies the mesh in IN by quadric-error edge collapse and writes it to OUT, through the same operation as
POST /simplify. Polygons are triangulated first. Stops at whichever of the given criteria is reached first.
  IN:  .obj .off .ply .stl .glb        OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required)
  --target-faces N          stop at N triangles or fewer
  --ratio R                 stop at R times the input's triangles, 0 < R <= 1
  --max-error E             keep the Hausdorff distance to the input <= E (model units)
  --lock-border             boundary vertices stay exactly where they are
  --report-error            measure and print the Hausdorff and RMS distance to the input
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

//! A number option as text, checked to parse (the operation checks its range).
std::string checked_real(std::string_view name, const std::string& text) {
    double value = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value))
        throw UsageError{std::string(name) + " needs a number, got \"" + text + "\""};
    return text;
}

int simplify(Args& args) {
    std::string input, output;
    std::optional<std::string> target_faces, ratio, max_error, quantize;
    bool lock_border = false, report_error = false, no_draco = false, normals = false;
    api::ApiContext context;
    context.limits.max_body_bytes = static_cast<std::size_t>(-1);  // the user's own file
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (arg == "-h" || arg == "--help") {
            std::cout << kSimplifyHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--target-faces") {
            target_faces = std::to_string(parse_number(arg, args.value(arg, inline_value), 0, 4'000'000'000LL));
        } else if (arg == "--ratio") {
            ratio = checked_real(arg, args.value(arg, inline_value));
        } else if (arg == "--max-error") {
            max_error = checked_real(arg, args.value(arg, inline_value));
        } else if (arg == "--lock-border") {
            lock_border = true;
        } else if (arg == "--report-error") {
            report_error = true;
        } else if (arg == "--quantize-position") {
            quantize = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 24));
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--normals") {
            normals = true;
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"simplify: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"simplify: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"simplify: missing input file"};
    if (output.empty()) throw UsageError{"simplify: missing -o OUT"};
    if (!target_faces && !ratio && !max_error)
        throw UsageError{"simplify: give --target-faces, --ratio or --max-error"};
    if (lower_extension(input) == ".gltf") throw UsageError{".gltf input is not supported yet; use .glb"};
    const auto in_format = format_from_extension(input);
    if (!in_format)
        throw UsageError{"cannot tell the format of " + input + " from its extension (use .obj .off .ply .stl .glb)"};
    const std::string out_ext = lower_extension(output);
    std::optional<api::OutputFormat> out_format;
    if (out_ext == ".obj") out_format = api::OutputFormat::Obj;
    else if (out_ext == ".ply") out_format = api::OutputFormat::Ply;
    else if (out_ext == ".glb") out_format = api::OutputFormat::Glb;
    else if (out_ext == ".gltf") out_format = api::OutputFormat::Gltf;
    else if (out_ext == ".json") out_format = api::OutputFormat::Json;
    else throw UsageError{"cannot tell the output format of " + output + " from its extension (use .obj .ply .glb .gltf .json)"};
    const bool gltf = *out_format == api::OutputFormat::Glb || *out_format == api::OutputFormat::Gltf;
    if (quantize && (!gltf || no_draco)) throw UsageError{"--quantize-position applies only to .glb/.gltf output with Draco"};
    if (normals && *out_format == api::OutputFormat::Json) throw UsageError{"--normals is not available for .json output"};

    std::string bytes, error;
    if (!read_file(input, bytes, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    // The request POST /simplify would receive for this upload: one code path for the CLI and the service.
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/simplify";
    request.content_type = std::string(api::enum_name(api::kMeshMediaTypes, *in_format));
    request.body = bytes;
    if (target_faces) request.query.emplace("target_faces", *target_faces);
    if (ratio) request.query.emplace("ratio", *ratio);
    if (max_error) request.query.emplace("max_error", *max_error);
    if (lock_border) request.query.emplace("lock_border", "true");
    if (report_error) request.query.emplace("report_error", "true");
    request.query.emplace("format", std::string(api::enum_name(api::kOutputFormatNames, *out_format)));
    if (no_draco && gltf) request.query.emplace("compression", "none");
    if (quantize) request.query.emplace("quantize_position", *quantize);
    if (normals) request.query.emplace("normals", "true");

    const api::ApiResponse response = api::dispatch(request, context);
    if (response.status >= 400) {
        std::cerr << "surfaced: " << input << ": ";
        if (response.error) {
            std::cerr << response.error->detail;
            if (response.error->line) std::cerr << " (line " << *response.error->line << ")";
            else if (response.error->offset) std::cerr << " (byte offset " << *response.error->offset << ")";
            std::cerr << " [" << response.error->code << "]";
        } else {
            std::cerr << "failed with status " << response.status;
        }
        std::cerr << "\n";
        return kExitFailed;
    }
    if (!write_file(output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    std::cout << "wrote " << output << ": " << header(response, "X-Output-Faces") << " triangles, "
              << header(response, "X-Output-Vertices") << " vertices (from " << header(response, "X-Input-Faces")
              << " faces" << (header(response, "X-Triangulated") == "true" ? ", triangulated first" : "")
              << "), error " << header(response, "X-Achieved-Error") << " (" << header(response, "X-Relative-Error")
              << " of the bounding-box diagonal)";
    if (report_error)
        std::cout << ", Hausdorff " << header(response, "X-Hausdorff") << ", RMS " << header(response, "X-RMS");
    std::cout << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
    return kExitOk;
}

}  // namespace

int run(int argc, char** argv) {
    try {
        if (argc < 2) {
            std::cerr << kMainHelp;
            return kExitUsage;
        }
        const std::string command = argv[1];
        Args args(argc, argv, 2);
        if (command == "-h" || command == "--help" || command == "help") {
            std::cout << kMainHelp;
            return kExitOk;
        }
        if (command == "--version" || command == "-V") {
            std::cout << "surfaced " << SURFACED_VERSION << "\n";
            return kExitOk;
        }
        if (command == "serve") return serve(args);
        if (command == "subdivide") return subdivide(args);
        if (command == "tessellate") return tessellate(args);
        if (command == "simplify") return simplify(args);
        throw UsageError{"unknown command \"" + command + "\" (commands: serve, subdivide, tessellate, simplify; see surfaced --help)"};
    } catch (const UsageError& e) {
        std::cerr << "surfaced: " << e.message << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "surfaced: internal error: " << e.what() << "\n";
        return kExitFailed;
    }
}

}  // namespace surfaced::cli
