#include "server/cli.h"

#include <pthread.h>
#include <signal.h>

#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstdlib>
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
#include "api/operations/implicit_mesh.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/pointcloud_io.h"
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
  surfaced healthcheck [options]              exit 0 when a running service answers GET /livez with 200
  surfaced subdivide IN -o OUT [options]      subdivide a mesh file
  surfaced tessellate IN -o OUT [options]     tessellate Bezier patches (.bez/.bbp, sample:teapot)
  surfaced simplify IN -o OUT [options]       simplify a mesh file (QEM edge collapse)
  surfaced remesh IN -o OUT [options]         isotropic remeshing to one edge length, quality report
  surfaced implicit SCENE.json -o OUT [opts]  mesh an implicit scene (dual marching cubes, closed)
  surfaced pointcloud IN -o OUT [options]     convert a point cloud, estimate oriented normals
  surfaced <command> --help                   options of a command
  surfaced --help | --version

Exit codes: 0 success, 1 the operation failed, 2 bad usage.
)";

constexpr std::string_view kServeHelp = R"(Usage: surfaced serve [options]

Runs the HTTP service until SIGINT or SIGTERM. On either it drains: /readyz answers 503, the listening socket
closes (after --drain-delay-ms), accepted requests are answered and in-flight work finishes (cancelled with 503
after --drain-timeout), then it exits 0.

Options:
  --host H               address to listen on (default 127.0.0.1; 0.0.0.0 for all interfaces)
  --port P               TCP port, 0 for any free port (default 8080)
  --threads N            worker threads = connections served at once (default: one per CPU, at least 2)
  --queue N              accepted connections that may wait for a worker; beyond, 503 + Retry-After
                         (default: 8 x threads, at least 64)
  --deadline-ms MS       per-request compute deadline; work past it is cancelled with 503 (default 0: none)
  --keep-alive-max N     requests per connection (default 100)
  --keep-alive-timeout S idle seconds before a keep-alive connection is closed (default 5)
  --header-timeout S     seconds a request line and headers may take to arrive (default 10)
  --drain-timeout S      on SIGTERM, cancel work still running after S seconds (default 30)
  --drain-delay-ms MS    on SIGTERM, keep accepting this long with /readyz at 503 (default 0)
  --access-log WHERE     JSON access log lines to stderr (default), stdout, or off
  --auth-token-file F    require "Authorization: Bearer <token>" (the file's first line; or the environment
                         variable SURFACED_AUTH_TOKEN) on every route but /livez, /readyz, /healthz,
                         /openapi.json, static files and CORS preflights
  --cors-origin ORIGIN   allow browser calls from ORIGIN (repeatable; * for any)
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
    config.access_log = server::ServerConfig::AccessLog::Stderr;
    bool web_root_given = false;
    std::optional<std::string> auth_token_file;
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
        } else if (arg == "--queue") {
            config.queue_capacity = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1 << 20));
        } else if (arg == "--deadline-ms") {
            config.limits.compute_deadline_ms = static_cast<std::uint64_t>(
                parse_number(arg, args.value(arg, inline_value), 0, 86'400'000LL));
        } else if (arg == "--keep-alive-max") {
            config.keep_alive_max_requests = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1 << 20));
        } else if (arg == "--keep-alive-timeout") {
            config.keep_alive_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 3600));
        } else if (arg == "--header-timeout") {
            config.header_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 3600));
        } else if (arg == "--drain-timeout") {
            config.drain_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 3600));
        } else if (arg == "--drain-delay-ms") {
            config.drain_delay_ms = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 600'000));
        } else if (arg == "--access-log") {
            const std::string where = args.value(arg, inline_value);
            if (where == "off") config.access_log = server::ServerConfig::AccessLog::Off;
            else if (where == "stdout") config.access_log = server::ServerConfig::AccessLog::Stdout;
            else if (where == "stderr") config.access_log = server::ServerConfig::AccessLog::Stderr;
            else throw UsageError{"--access-log: unknown value \"" + where + "\" (allowed: off, stdout, stderr)"};
        } else if (arg == "--auth-token-file") {
            auth_token_file = args.value(arg, inline_value);
        } else if (arg == "--cors-origin") {
            const std::string origin = args.value(arg, inline_value);
            if (origin.empty() || origin.find_first_of("\r\n ,") != std::string::npos)
                throw UsageError{"--cors-origin: \"" + origin + "\" is not an origin (scheme://host[:port], or *)"};
            config.cors_origins.push_back(origin);
        } else {
            throw UsageError{"serve: unknown argument \"" + arg + "\""};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    std::error_code ec;
    if (web_root_given && !std::filesystem::is_directory(config.web_root, ec))
        throw UsageError{"--web-root " + config.web_root + " is not a directory"};
    if (auth_token_file) {
        std::string text, error;
        if (!read_file(*auth_token_file, text, error)) throw UsageError{"--auth-token-file: " + error};
        config.auth_token = text.substr(0, text.find_first_of("\r\n"));
        if (config.auth_token.empty()) throw UsageError{"--auth-token-file " + *auth_token_file + ": the first line is empty"};
    } else if (const char* token = std::getenv("SURFACED_AUTH_TOKEN"); token && *token) {
        config.auth_token = token;
    }
    while (!config.auth_token.empty() && (config.auth_token.back() == ' ' || config.auth_token.back() == '\t'))
        config.auth_token.pop_back();

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
              << (http.serves_web_root() ? config.web_root : std::string("none"))
              << (config.auth_token.empty() ? "" : ", bearer-token auth") << ")" << std::endl;

    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "surfaced: " << (signal_number == SIGINT ? "SIGINT" : "SIGTERM") << ", draining" << std::endl;
    http.stop();
    std::cout << "surfaced: stopped" << std::endl;
    return kExitOk;
}

// ---- healthcheck ---------------------------------------------------------------------------------------------

constexpr std::string_view kHealthcheckHelp = R"(Usage: surfaced healthcheck [options]

Asks a running service GET /livez (for a container HEALTHCHECK); exit 0 on 200, 1 otherwise (no answer in time,
refused, another status). Prints the reason on stderr when it fails.

Options:
  --host H        address of the service (default 127.0.0.1; 0.0.0.0 means this machine)
  --port P        its port (default 8080, or the environment variable SURFACED_PORT)
  --timeout S     seconds to wait for the connection and for the answer (default 2)
  --path P        the path to ask (default /livez; /readyz for readiness)
  -h, --help      this text
)";

int healthcheck(Args& args) {
    std::string host = "127.0.0.1";
    int port = 8080;
    if (const char* env = std::getenv("SURFACED_PORT"); env && *env) port = static_cast<int>(parse_number("SURFACED_PORT", env, 1, 65535));
    double timeout = 2.0;
    std::string path = "/livez";
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (arg == "-h" || arg == "--help") {
            std::cout << kHealthcheckHelp;
            return kExitOk;
        } else if (arg == "--host") {
            host = args.value(arg, inline_value);
        } else if (arg == "--port") {
            port = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 65535));
        } else if (arg == "--timeout") {
            const std::string text = args.value(arg, inline_value);
            char* end = nullptr;
            timeout = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !(timeout > 0 && timeout <= 3600))
                throw UsageError{"--timeout needs seconds in (0, 3600], got \"" + text + "\""};
        } else if (arg == "--path") {
            path = args.value(arg, inline_value);
            if (!path.starts_with("/") || path.find_first_of("\r\n ") != std::string::npos)
                throw UsageError{"--path must start with / and contain no spaces"};
        } else {
            throw UsageError{"healthcheck: unknown argument \"" + arg + "\""};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    std::string detail;
    if (server::probe_http(host, port, path, timeout, &detail)) return kExitOk;
    std::cerr << "surfaced healthcheck: " << detail << "\n";
    return kExitFailed;
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

// ---- remesh --------------------------------------------------------------------------------------------------

constexpr std::string_view kRemeshHelp = R"(Usage: surfaced remesh IN -o OUT [--edge-length L] [--iterations K] [options]

Remeshes the mesh in IN isotropically (split, collapse, flip, relax, project; Botsch-Kobbelt) towards edges of
length L and writes it to OUT, through the same operation as POST /remesh. Polygons are triangulated first. Sharp
edges and the boundary are kept. Prints the triangle quality before and after and the Hausdorff distance.
  IN:  .obj .off .ply .stl .glb        OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required)
  --edge-length L           target edge length in model units (default: the input's mean edge length)
  --iterations K            rounds of split/collapse/flip/relax, 0..100 (default 10)
  --feature-angle DEG       dihedral angle above which an edge is sharp, 0..180 (default 60; 180: none)
  --free-boundary           relax boundary vertices like interior ones (default: keep the boundary)
  --smoothing S             tangential (default), laplacian or none
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

int remesh(Args& args) {
    std::string input, output;
    std::optional<std::string> edge_length, iterations, feature_angle, smoothing, quantize;
    bool free_boundary = false, no_draco = false, normals = false;
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
            std::cout << kRemeshHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--edge-length") {
            edge_length = checked_real(arg, args.value(arg, inline_value));
        } else if (arg == "--iterations") {
            iterations = std::to_string(parse_number(arg, args.value(arg, inline_value), 0, 100));
        } else if (arg == "--feature-angle") {
            feature_angle = checked_real(arg, args.value(arg, inline_value));
        } else if (arg == "--smoothing") {
            smoothing = args.value(arg, inline_value);
        } else if (arg == "--free-boundary") {
            free_boundary = true;
        } else if (arg == "--quantize-position") {
            quantize = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 24));
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--normals") {
            normals = true;
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"remesh: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"remesh: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"remesh: missing input file"};
    if (output.empty()) throw UsageError{"remesh: missing -o OUT"};
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
    // The request POST /remesh would receive for this upload: one code path for the CLI and the service.
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/remesh";
    request.content_type = std::string(api::enum_name(api::kMeshMediaTypes, *in_format));
    request.body = bytes;
    if (edge_length) request.query.emplace("edge_length", *edge_length);
    if (iterations) request.query.emplace("iterations", *iterations);
    if (feature_angle) request.query.emplace("feature_angle", *feature_angle);
    if (smoothing) request.query.emplace("smoothing", *smoothing);
    if (free_boundary) request.query.emplace("keep_boundary", "false");
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
              << "), edge length " << header(response, "X-Edge-Length") << " (mean "
              << header(response, "X-Mean-Edge-Length-After") << "), min angle "
              << header(response, "X-Min-Angle-Before") << " -> " << header(response, "X-Min-Angle-After")
              << " deg, below 30 deg " << header(response, "X-Below-30-Before") << " -> "
              << header(response, "X-Below-30-After") << ", radius ratio " << header(response, "X-Radius-Ratio-Before")
              << " -> " << header(response, "X-Radius-Ratio-After") << ", Hausdorff " << header(response, "X-Hausdorff")
              << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
    return kExitOk;
}

// ---- implicit ------------------------------------------------------------------------------------------------

constexpr std::string_view kImplicitHelp = R"(Usage: surfaced implicit SCENE.json -o OUT [--resolution N | --cell-size H] [options]

Meshes the zero level set of an implicit scene inside its bounds, through the same operation as POST /implicit/mesh
(dual marching cubes with QEF vertices: closed, manifold, consistently oriented, sharp edges kept). Where the
surface meets the bounds it is closed by flat caps. SCENE.json is a request body:
  {"scene": {"op": "difference", "args": [...]}, "bounds": [[x0,y0,z0],[x1,y1,z1]], "resolution": 64}
  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT            output file (required)
  --resolution N              cells along the longest side of the bounds (default: the file's, else 64)
  --cell-size H               cell size instead of a resolution
  --mode M                    uniform (default) or adaptive (skips empty space: cost follows the surface)
  --simplify-tolerance T      adaptive only: QEM-simplify flat regions to this Hausdorff distance
  --max-grid-cells N          refuse larger grids (default 16777216)
  --no-draco                  write uncompressed glTF (.glb, .gltf)
  --quantize-position BITS    Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                   also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                  this text
)";

int implicit(Args& args) {
    std::string input, output;
    api::operations::ImplicitMeshOverrides overrides;
    bool no_draco = false, normals = false;
    std::optional<std::int64_t> quantize;
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
            std::cout << kImplicitHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--resolution") {
            overrides.resolution = parse_number(arg, args.value(arg, inline_value), 2, 65536);
        } else if (arg == "--cell-size") {
            overrides.cell_size = std::stod(checked_real(arg, args.value(arg, inline_value)));
        } else if (arg == "--mode") {
            overrides.mode = args.value(arg, inline_value);
            if (*overrides.mode != "uniform" && *overrides.mode != "adaptive")
                throw UsageError{"--mode: unknown value \"" + *overrides.mode + "\" (allowed: uniform, adaptive)"};
        } else if (arg == "--simplify-tolerance") {
            overrides.simplify_tolerance = std::stod(checked_real(arg, args.value(arg, inline_value)));
        } else if (arg == "--max-grid-cells") {
            context.limits.max_grid_cells = static_cast<std::uint64_t>(
                parse_number(arg, args.value(arg, inline_value), 1, 1'000'000'000'000LL));
        } else if (arg == "--quantize-position") {
            quantize = parse_number(arg, args.value(arg, inline_value), 1, 24);
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--normals") {
            normals = true;
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"implicit: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"implicit: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"implicit: missing SCENE.json"};
    if (output.empty()) throw UsageError{"implicit: missing -o OUT"};
    if (overrides.resolution && overrides.cell_size) throw UsageError{"give --resolution or --cell-size, not both"};
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
    overrides.output.format = *out_format;
    if (no_draco && gltf) overrides.output.draco = false;
    if (quantize) overrides.output.quantize_position = *quantize;
    if (normals) overrides.output.normals = true;

    std::string bytes, error;
    if (!read_file(input, bytes, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    const api::ApiResponse response = api::operations::implicit_mesh_from_file(bytes, overrides, context);
    if (response.status >= 400) {
        std::cerr << "surfaced: " << input << ": ";
        if (response.error) {
            const std::string& field = response.error->field ? *response.error->field : std::string();
            if (!field.empty() && !response.error->detail.starts_with(field)) std::cerr << field << ": ";
            std::cerr << response.error->detail;
            if (response.error->offset) std::cerr << " (byte offset " << *response.error->offset << ")";
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
              << header(response, "X-Output-Vertices") << " vertices, grid " << header(response, "X-Grid") << " ("
              << header(response, "X-Surface-Cells") << " surface cells, " << header(response, "X-Field-Evaluations")
              << " field evaluations), in " << header(response, "X-Elapsed-Ms") << " ms\n";
    return kExitOk;
}

// ---- pointcloud ----------------------------------------------------------------------------------------------

constexpr std::string_view kPointcloudHelp = R"(Usage: surfaced pointcloud IN -o OUT [--estimate-normals [--k N]] [options]

Reads the points in IN and writes them to OUT, through the same operation as POST /pointcloud; with
--estimate-normals the normals are replaced by PCA of the k nearest neighbours, consistently oriented (outward on
closed shapes).
  IN:  .ply .obj .xyz (.txt .pts as XYZ)        OUT: .glb (Draco POINTS) .ply .json

Options:
  -o, --output OUT          output file (required)
  --estimate-normals        estimate and orient normals
  --k N                     neighbours for --estimate-normals, 3..256 (default 16)
  --no-normals              leave normals out of the output
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb only)
  -h, --help                this text
)";

int pointcloud(Args& args) {
    std::string input, output;
    std::optional<std::string> k, quantize;
    bool estimate = false, no_normals = false, no_draco = false;
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
            std::cout << kPointcloudHelp;
            return kExitOk;
        } else if (arg == "-o" || arg == "--output") {
            output = args.value(arg, inline_value);
        } else if (arg == "--estimate-normals") {
            estimate = true;
        } else if (arg == "--k") {
            k = std::to_string(parse_number(arg, args.value(arg, inline_value), 3, 256));
        } else if (arg == "--no-normals") {
            no_normals = true;
        } else if (arg == "--no-draco") {
            no_draco = true;
        } else if (arg == "--quantize-position") {
            quantize = std::to_string(parse_number(arg, args.value(arg, inline_value), 1, 24));
        } else if (arg.starts_with("-") && arg != "-") {
            throw UsageError{"pointcloud: unknown option \"" + arg + "\""};
        } else if (input.empty()) {
            input = arg;
        } else {
            throw UsageError{"pointcloud: unexpected argument \"" + arg + "\" (input is already " + input + ")"};
        }
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    if (input.empty()) throw UsageError{"pointcloud: missing input file"};
    if (output.empty()) throw UsageError{"pointcloud: missing -o OUT"};
    if (k && !estimate) throw UsageError{"--k applies only with --estimate-normals"};
    const auto in_format = point_format_from_extension(input);
    if (!in_format) throw UsageError{"cannot tell the point format of " + input + " from its extension (use .ply .obj .xyz)"};
    const std::string out_ext = lower_extension(output);
    std::string out_format;
    if (out_ext == ".glb") out_format = "glb";
    else if (out_ext == ".ply") out_format = "ply";
    else if (out_ext == ".json") out_format = "json";
    else throw UsageError{"cannot tell the output format of " + output + " from its extension (use .glb .ply .json)"};
    if ((no_draco || quantize) && out_format != "glb") throw UsageError{"--no-draco and --quantize-position apply only to .glb output"};
    if (quantize && no_draco) throw UsageError{"--quantize-position applies only with Draco"};

    std::string bytes, error;
    if (!read_file(input, bytes, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    api::ApiRequest request;
    request.method = "POST";
    request.path = "/pointcloud";
    request.content_type = *in_format == PointFormat::Ply   ? "application/ply"
                           : *in_format == PointFormat::Obj ? "model/obj"
                                                            : "text/x-xyz";
    request.body = bytes;
    if (estimate) request.query.emplace("estimate_normals", "true");
    if (k) request.query.emplace("k", *k);
    request.query.emplace("format", out_format);
    if (no_draco) request.query.emplace("compression", "none");
    if (quantize) request.query.emplace("quantize_position", *quantize);
    if (no_normals) request.query.emplace("normals", "false");

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
    std::cout << "wrote " << output << ": " << header(response, "X-Output-Points") << " points"
              << (header(response, "X-Normals") == "true" ? ", normals" : "")
              << (header(response, "X-Colors") == "true" ? ", colors" : "") << ", in "
              << header(response, "X-Elapsed-Ms") << " ms\n";
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
        if (command == "healthcheck") return healthcheck(args);
        if (command == "subdivide") return subdivide(args);
        if (command == "tessellate") return tessellate(args);
        if (command == "simplify") return simplify(args);
        if (command == "remesh") return remesh(args);
        if (command == "implicit") return implicit(args);
        if (command == "pointcloud") return pointcloud(args);
        throw UsageError{"unknown command \"" + command + "\" (commands: serve, healthcheck, subdivide, tessellate, simplify, remesh, implicit, pointcloud; see surfaced --help)"};
    } catch (const UsageError& e) {
        std::cerr << "surfaced: " << e.message << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "surfaced: internal error: " << e.what() << "\n";
        return kExitFailed;
    }
}

}  // namespace surfaced::cli
