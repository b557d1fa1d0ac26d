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
#include <functional>
#include <initializer_list>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "api/dto.h"
#include "api/routes.h"
#include "api/operations/curves.h"
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

constexpr std::string_view kMainHelp =
    R"(surfaced - surface modeling over HTTP/JSON and on the command line: subdivision, simplification, remeshing,
repair, Bezier patches and curves, implicit surfaces, point clouds

Usage:
  surfaced serve [options]                    run the HTTP service
  surfaced healthcheck [options]              exit 0 when a running service answers GET /livez with 200
  surfaced subdivide IN -o OUT [options]      subdivide a mesh file
  surfaced tessellate IN -o OUT [options]     tessellate Bezier patches (.bez/.bbp, sample:teapot)
  surfaced simplify IN -o OUT [options]       simplify a mesh file (QEM edge collapse)
  surfaced remesh IN -o OUT [options]         isotropic remeshing to one edge length, quality report
  surfaced repair IN -o OUT [options]         repair a mesh (weld, orient, non-manifold cut apart), with a report
  surfaced implicit SCENE.json -o OUT [opts]  mesh an implicit scene (dual marching cubes, closed)
  surfaced pointcloud IN -o OUT [options]     convert a point cloud, estimate oriented normals
  surfaced curve IN -o OUT [options]          curve queries (Bezier, chains, SVG paths, B-splines); glTF lines
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
  --body-timeout S       seconds a request body may take after its head, plus 1 s per --body-min-rate bytes
                         received; slower bodies get 408 and the connection is closed (default 30)
  --body-min-rate B      bytes per second that earn a body more time (default 16384; 0: none)
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
  IN:  .obj .off .ply .stl .glb .gltf
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
        throw UsageError{std::string(name) + ": unknown value \"" + text + "\" (allowed: " + api::enum_names(table) +
                         ")"};
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

// ---- what the commands share ---------------------------------------------------------------------------------

//! The option loop of every command: splits "--name=value" and hands each argument to `handle(arg, inline_value)`,
//! which takes the value it needs (Args::value); a value left over is an error ("--normals=yes"). `handle` returns
//! false when the command is done (it printed its help); so does this.
template <class Handle>
bool for_each_argument(Args& args, Handle&& handle) {
    while (!args.done()) {
        std::string arg = args.next();
        std::optional<std::string> inline_value;
        if (const auto eq = arg.find('='); arg.starts_with("--") && eq != std::string::npos) {
            inline_value = arg.substr(eq + 1);
            arg.resize(eq);
        }
        if (!handle(arg, inline_value)) return false;
        if (inline_value) throw UsageError{arg + " takes no value"};
    }
    return true;
}

//! Checks an option's value and returns the text to pass on, or throws a UsageError naming the option.
using CheckValue = std::function<std::string(std::string_view option, const std::string& text)>;

//! A number option as text, checked to parse (the operation checks its range).
std::string checked_real(std::string_view name, const std::string& text) {
    double value = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(value))
        throw UsageError{std::string(name) + " needs a number, got \"" + text + "\""};
    return text;
}

CheckValue integer(long long min, long long max) {
    return [=](std::string_view option, const std::string& text) {
        return std::to_string(parse_number(option, text, min, max));
    };
}
CheckValue real() { return checked_real; }
CheckValue any_text() {
    return [](std::string_view, const std::string& text) { return text; };
}
template <class E, std::size_t N>
CheckValue one_of(const api::EnumName<E> (&table)[N]) {
    return [&table](std::string_view option, const std::string& text) { return checked_enum(option, text, table); };
}

//! An option of a file command: "--name VALUE" (checked by `check`), or a switch "--name" (no `check`).
struct Option {
    std::string_view name;
    //! The query parameter it becomes (a switch's value is `switch_value`); empty: the command reads it itself.
    std::string_view param;
    CheckValue check;
    std::string_view switch_value = "true";
};

//! A switch: "--name" (no value) gives query parameter `param`, if any, the value `value`.
Option flag(std::string_view name, std::string_view param = "", std::string_view value = "true") {
    return Option{name, param, nullptr, value};
}

//! The arguments of `COMMAND IN -o OUT [options]`: the options given, each with its last (checked) value.
struct Parsed {
    std::string input, output;
    std::map<std::string, std::string, std::less<>> given;  //!< by option name; "" for switches

    bool has(std::string_view name) const { return given.find(name) != given.end(); }
    //! The value of an option that `has` been given.
    const std::string& value(std::string_view name) const { return given.find(name)->second; }
};

//! Parses the arguments of a file command against its `options`, with the wording every command shares: -h/--help
//! prints `help` (nullopt: the command is done), -o/--output, unknown options, one IN (`input_name` when missing),
//! OUT required.
std::optional<Parsed> parse_file_command(Args& args, const std::string& command, std::string_view help,
                                         const std::vector<Option>& options,
                                         const std::string& input_name = "input file") {
    Parsed parsed;
    const bool complete = for_each_argument(args, [&](const std::string& arg,
                                                      std::optional<std::string>& inline_value) {
        if (arg == "-h" || arg == "--help") {
            std::cout << help;
            return false;
        }
        if (arg == "-o" || arg == "--output") {
            parsed.output = args.value(arg, inline_value);
            return true;
        }
        for (const Option& option : options)
            if (arg == option.name) {
                parsed.given[arg] = option.check ? option.check(arg, args.value(arg, inline_value)) : std::string();
                return true;
            }
        if (arg.starts_with("-") && arg != "-") throw UsageError{command + ": unknown option \"" + arg + "\""};
        if (!parsed.input.empty())
            throw UsageError{command + ": unexpected argument \"" + arg + "\" (input is already " + parsed.input + ")"};
        parsed.input = arg;
        return true;
    });
    if (!complete) return std::nullopt;
    if (parsed.input.empty()) throw UsageError{command + ": missing " + input_name};
    if (parsed.output.empty()) throw UsageError{command + ": missing -o OUT"};
    return parsed;
}

//! The mesh format of IN, from its extension.
MeshFormat mesh_input_format(const std::string& input) {
    const auto format = format_from_extension(input);
    if (!format)
        throw UsageError{"cannot tell the format of " + input +
                         " from its extension (use .obj .off .ply .stl .glb .gltf)"};
    return *format;
}

//! The output format of OUT, from its extension; `allowed` as the error lists them (".obj .ply .glb").
api::OutputFormat output_format(const std::string& output, std::initializer_list<api::OutputFormat> allowed,
                                std::string_view listed) {
    const std::string ext = lower_extension(output);
    for (const api::OutputFormat format : allowed)
        if (ext == "." + std::string(api::enum_name(api::kOutputFormatNames, format))) return format;
    throw UsageError{"cannot tell the output format of " + output + " from its extension (use " + std::string(listed) +
                     ")"};
}
api::OutputFormat mesh_output_format(const std::string& output) {
    using enum api::OutputFormat;
    return output_format(output, {Obj, Ply, Glb, Gltf, Json}, ".obj .ply .glb .gltf .json");
}

bool is_gltf(api::OutputFormat format) { return format == api::OutputFormat::Glb || format == api::OutputFormat::Gltf; }

//! --quantize-position and --normals against a mesh output format.
void check_mesh_output_options(const Parsed& parsed, api::OutputFormat format) {
    if (parsed.has("--quantize-position") && (!is_gltf(format) || parsed.has("--no-draco")))
        throw UsageError{"--quantize-position applies only to .glb/.gltf output with Draco"};
    if (parsed.has("--normals") && format == api::OutputFormat::Json)
        throw UsageError{"--normals is not available for .json output"};
}

//! The query parameters of the raw-file request form: the options that name one, the output format, and
//! compression "none" for --no-draco with glTF output.
std::multimap<std::string, std::string> file_query(const Parsed& parsed, const std::vector<Option>& options,
                                                   api::OutputFormat format) {
    std::multimap<std::string, std::string> query;
    for (const Option& option : options)
        if (!option.param.empty() && parsed.has(option.name))
            query.emplace(option.param, option.check ? parsed.value(option.name) : std::string(option.switch_value));
    query.emplace("format", std::string(api::enum_name(api::kOutputFormatNames, format)));
    if (parsed.has("--no-draco") && is_gltf(format)) query.emplace("compression", "none");
    return query;
}

//! The request POST `path` would receive for an upload of `body`: one code path for the CLI and the service.
api::ApiRequest upload_request(std::string path, std::string content_type, std::string_view body,
                               std::multimap<std::string, std::string> query) {
    api::ApiRequest request;
    request.method = "POST";
    request.path = std::move(path);
    request.content_type = std::move(content_type);
    request.body = body;
    request.query = std::move(query);
    return request;
}

//! The bytes of IN; nullopt (and why, printed) when it cannot be read.
std::optional<std::string> read_input(const std::string& path) {
    std::string bytes, error;
    if (read_file(path, bytes, error)) return bytes;
    std::cerr << "surfaced: " << error << "\n";
    return std::nullopt;
}

//! What a command's problem message locates: "surfaced: IN: [field: ]detail[ (line N)][ (byte offset N)] [code]".
struct ProblemStyle {
    bool field = false;  //!< the field path, when the detail does not start with it
    bool line = true;
    bool offset = true;  //!< (when there is no line)
};

//! The end of every file command: a problem is printed (exit 1); a result is written to OUT and `summary(response)`
//! printed (exit 0).
template <class Summary>
int finish(const api::ApiResponse& response, const Parsed& parsed, Summary&& summary, ProblemStyle style = {}) {
    if (response.status >= 400) {
        std::cerr << "surfaced: " << parsed.input << ": ";
        if (const auto& problem = response.error) {
            if (style.field && problem->field && !problem->field->empty() &&
                !problem->detail.starts_with(*problem->field))
                std::cerr << *problem->field << ": ";
            std::cerr << problem->detail;
            if (style.line && problem->line)
                std::cerr << " (line " << *problem->line << ")";
            else if (style.offset && problem->offset)
                std::cerr << " (byte offset " << *problem->offset << ")";
            std::cerr << " [" << problem->code << "]";
        } else {
            std::cerr << "failed with status " << response.status;
        }
        std::cerr << "\n";
        return kExitFailed;
    }
    std::string error;
    if (!write_file(parsed.output, response.body, error)) {
        std::cerr << "surfaced: " << error << "\n";
        return kExitFailed;
    }
    summary(response);
    return kExitOk;
}

//! The context of a command run in process. Files are the user's own: the body limit protects the server's memory,
//! not the CLI's.
api::ApiContext file_context() {
    api::ApiContext context;
    context.limits.max_body_bytes = static_cast<std::size_t>(-1);
    return context;
}

//! subdivide, simplify, remesh after their own checks: IN read and sent as the raw-file form of POST `path` with the
//! query of the options given; then `finish`.
template <class Summary>
int upload_mesh(std::string path, const Parsed& parsed, const std::vector<Option>& options, MeshFormat in_format,
                api::OutputFormat out_format, const api::ApiContext& context, Summary&& summary) {
    const auto bytes = read_input(parsed.input);
    if (!bytes) return kExitFailed;
    const api::ApiRequest request =
        upload_request(std::move(path), std::string(api::enum_name(api::kMeshMediaTypes, in_format)), *bytes,
                       file_query(parsed, options, out_format));
    return finish(api::dispatch(request, context), parsed, std::forward<Summary>(summary));
}

//! What repair did, on stderr ("repaired IN: welded=12; degenerate=3; ..."), when X-Repairs reports anything; the
//! output on stdout stays the operation's summary.
void print_repairs(const Parsed& parsed, const api::ApiResponse& response) {
    const std::string repairs = header(response, "X-Repairs");
    if (repairs == "?") return;
    bool any = false;
    for (std::size_t at = repairs.find('='); at != std::string::npos; at = repairs.find('=', at + 1)) {
        const std::size_t name = repairs.rfind(' ', at) == std::string::npos ? 0 : repairs.rfind(' ', at) + 1;
        if (repairs.compare(name, at - name, "components") != 0 && repairs[at + 1] != '0') any = true;
    }
    if (any) std::cerr << "repaired " << parsed.input << ": " << repairs << "\n";
}

//! "wrote OUT: T triangles, V vertices (from F faces[, triangulated first])" of simplify and remesh.
void print_triangulated_result(const Parsed& parsed, const api::ApiResponse& response) {
    std::cout << "wrote " << parsed.output << ": " << header(response, "X-Output-Faces") << " triangles, "
              << header(response, "X-Output-Vertices") << " vertices (from " << header(response, "X-Input-Faces")
              << " faces" << (header(response, "X-Triangulated") == "true" ? ", triangulated first" : "") << ")";
}

// ---- serve ---------------------------------------------------------------------------------------------------

//! The `serve` command line: the configuration it builds and what still has to be checked or read once all
//! options are known.
struct ServeOptions {
    server::ServerConfig config;
    bool web_root_given = false;
    std::optional<std::string> auth_token_file;
};

//! Applies one `serve` option (taking its value from `args`); false when it was --help (the help is printed).
bool apply_serve_option(Args& args, const std::string& arg, std::optional<std::string>& inline_value,
                        ServeOptions& options) {
    server::ServerConfig& config = options.config;
    if (arg == "-h" || arg == "--help") {
        std::cout << kServeHelp;
        for (const api::Route& route : api::routes())
            std::cout << "  " << route.method << " " << route.path << "  " << route.description << "\n";
        return false;
    } else if (arg == "--host") {
        config.host = args.value(arg, inline_value);
    } else if (arg == "--port") {
        config.port = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 65535));
    } else if (arg == "--threads") {
        config.threads = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1024));
    } else if (arg == "--web-root") {
        config.web_root = args.value(arg, inline_value);
        options.web_root_given = true;
    } else if (arg == "--max-body-mb") {
        config.limits.max_body_bytes =
            static_cast<std::size_t>(parse_number(arg, args.value(arg, inline_value), 1, 1 << 20)) << 20;
    } else if (arg == "--max-levels") {
        config.limits.max_levels = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 16));
    } else if (arg == "--max-output-faces") {
        config.limits.max_output_faces =
            static_cast<std::uint64_t>(parse_number(arg, args.value(arg, inline_value), 1, 4'000'000'000LL));
    } else if (arg == "--queue") {
        config.queue_capacity = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1 << 20));
    } else if (arg == "--deadline-ms") {
        config.limits.compute_deadline_ms =
            static_cast<std::uint64_t>(parse_number(arg, args.value(arg, inline_value), 0, 86'400'000LL));
    } else if (arg == "--keep-alive-max") {
        config.keep_alive_max_requests = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 1 << 20));
    } else if (arg == "--keep-alive-timeout") {
        config.keep_alive_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 3600));
    } else if (arg == "--header-timeout") {
        config.header_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 3600));
    } else if (arg == "--body-timeout") {
        config.body_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 1, 3600));
    } else if (arg == "--body-min-rate") {
        config.body_min_rate_bytes =
            static_cast<std::size_t>(parse_number(arg, args.value(arg, inline_value), 0, 1LL << 40));
    } else if (arg == "--drain-timeout") {
        config.drain_timeout_seconds = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 3600));
    } else if (arg == "--drain-delay-ms") {
        config.drain_delay_ms = static_cast<int>(parse_number(arg, args.value(arg, inline_value), 0, 600'000));
    } else if (arg == "--access-log") {
        const std::string where = args.value(arg, inline_value);
        if (where == "off")
            config.access_log = server::ServerConfig::AccessLog::Off;
        else if (where == "stdout")
            config.access_log = server::ServerConfig::AccessLog::Stdout;
        else if (where == "stderr")
            config.access_log = server::ServerConfig::AccessLog::Stderr;
        else
            throw UsageError{"--access-log: unknown value \"" + where + "\" (allowed: off, stdout, stderr)"};
    } else if (arg == "--auth-token-file") {
        options.auth_token_file = args.value(arg, inline_value);
    } else if (arg == "--cors-origin") {
        const std::string origin = args.value(arg, inline_value);
        if (origin.empty() || origin.find_first_of("\r\n ,") != std::string::npos)
            throw UsageError{"--cors-origin: \"" + origin + "\" is not an origin (scheme://host[:port], or *)"};
        config.cors_origins.push_back(origin);
    } else {
        throw UsageError{"serve: unknown argument \"" + arg + "\""};
    }
    return true;
}

//! The bearer token: the first line of `file` when given (which must not be empty), else the environment variable
//! SURFACED_AUTH_TOKEN, else none; trailing blanks dropped.
std::string read_auth_token(const std::optional<std::string>& file) {
    auto trimmed = [](std::string token) {
        while (!token.empty() && (token.back() == ' ' || token.back() == '\t')) token.pop_back();
        return token;
    };
    if (file) {
        std::string text, error;
        if (!read_file(*file, text, error)) throw UsageError{"--auth-token-file: " + error};
        // a first line of blanks is as empty as no line: the service must not start open when a token was meant
        const std::string token = trimmed(text.substr(0, text.find_first_of("\r\n")));
        if (token.empty()) throw UsageError{"--auth-token-file " + *file + ": the first line is empty"};
        return token;
    }
    if (const char* env = std::getenv("SURFACED_AUTH_TOKEN"); env && *env) {
        const std::string token = trimmed(env);
        if (token.empty()) throw UsageError{"SURFACED_AUTH_TOKEN holds only blanks"};
        return token;
    }
    return {};
}

//! The server configuration the `serve` arguments give; nullopt when --help was printed.
std::optional<server::ServerConfig> serve_config(Args& args) {
    ServeOptions options;
    options.config.web_root = SURFACED_DEFAULT_WEB_ROOT;
    options.config.access_log = server::ServerConfig::AccessLog::Stderr;
    const bool complete =
        for_each_argument(args, [&](const std::string& arg, std::optional<std::string>& inline_value) {
            return apply_serve_option(args, arg, inline_value, options);
        });
    if (!complete) return std::nullopt;
    server::ServerConfig& config = options.config;
    std::error_code ec;
    if (options.web_root_given && !std::filesystem::is_directory(config.web_root, ec))
        throw UsageError{"--web-root " + config.web_root + " is not a directory"};
    config.auth_token = read_auth_token(options.auth_token_file);
    return std::move(config);
}

//! Runs the service until SIGINT or SIGTERM, then stops it gracefully.
int serve_until_signalled(const server::ServerConfig& config) {
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
              << "/ (" << http.threads()
              << " threads, web client: " << (http.serves_web_root() ? config.web_root : std::string("none"))
              << (config.auth_token.empty() ? "" : ", bearer-token auth") << ")" << std::endl;

    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    std::cout << "surfaced: " << (signal_number == SIGINT ? "SIGINT" : "SIGTERM") << ", draining" << std::endl;
    http.stop();
    std::cout << "surfaced: stopped" << std::endl;
    return kExitOk;
}

int serve(Args& args) {
    const std::optional<server::ServerConfig> config = serve_config(args);
    if (!config) return kExitOk;
    return serve_until_signalled(*config);
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
    if (const char* env = std::getenv("SURFACED_PORT"); env && *env)
        port = static_cast<int>(parse_number("SURFACED_PORT", env, 1, 65535));
    double timeout = 2.0;
    std::string path = "/livez";
    const bool complete =
        for_each_argument(args, [&](const std::string& arg, std::optional<std::string>& inline_value) {
            if (arg == "-h" || arg == "--help") {
                std::cout << kHealthcheckHelp;
                return false;
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
            return true;
        });
    if (!complete) return kExitOk;
    std::string detail;
    if (server::probe_http(host, port, path, timeout, &detail)) return kExitOk;
    std::cerr << "surfaced healthcheck: " << detail << "\n";
    return kExitFailed;
}

// ---- subdivide -----------------------------------------------------------------------------------------------

int subdivide(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--scheme", "scheme", one_of(api::kSchemeNames)},
        {"--levels", "levels", integer(0, 1'000'000)},
        {"--boundary", "boundary", one_of(api::kBoundaryNames)},
        {"--crease-method", "crease_method", one_of(api::kCreaseMethodNames)},
        {"--triangle-rule", "triangle_rule", one_of(api::kTriangleRuleNames)},
        {"--loop-weights", "loop_weights", one_of(api::kLoopWeightNames)},
        {"--uv-interpolation", "uv_interpolation", one_of(api::kUvInterpolationNames)},
        {"--max-faces", "max_faces", integer(1, 4'000'000'000LL)},
        flag("--limit-surface", "limit_surface"),
        {"--quantize-position", "quantize_position", integer(1, 24)},
        {"--max-output-faces", "", integer(1, 4'000'000'000LL)},
        flag("--no-draco"),
        flag("--normals", "normals"),
    };
    const auto parsed = parse_file_command(args, "subdivide", kSubdivideHelp, options);
    if (!parsed) return kExitOk;
    const MeshFormat in_format = mesh_input_format(parsed->input);
    const api::OutputFormat out_format = mesh_output_format(parsed->output);
    if (parsed->has("--quantize-position") && !is_gltf(out_format))
        throw UsageError{"--quantize-position applies only to .glb and .gltf output"};
    if (parsed->has("--quantize-position") && parsed->has("--no-draco"))
        throw UsageError{"--quantize-position applies only with Draco (drop --no-draco)"};
    if (parsed->has("--normals") && out_format == api::OutputFormat::Json)
        throw UsageError{"--normals is not available for .json output"};
    if (parsed->has("--max-output-faces"))
        context.limits.max_output_faces = std::stoull(parsed->value("--max-output-faces"));

    return upload_mesh(
        "/subdivide", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            std::cout << "wrote " << parsed->output << ": " << header(response, "X-Output-Vertices") << " vertices, "
                      << header(response, "X-Output-Faces") << " faces (from " << header(response, "X-Input-Vertices")
                      << " vertices, " << header(response, "X-Input-Faces") << " faces) in "
                      << header(response, "X-Elapsed-Ms") << " ms\n";
        });
}

// ---- tessellate ----------------------------------------------------------------------------------------------

constexpr std::string_view kTessellateHelp =
    R"(Usage: surfaced tessellate IN -o OUT (--tolerance T | --segments N) [options]

Tessellates the Bezier patches in IN (a geomview .bez/.bbp file, an .obj with cstype bezier surfaces, or
sample:teapot for a built-in sample) into a crack-free triangle mesh with normals and UVs, through the same
operation as POST /tessellate (GET /patches/NAME).

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
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--tolerance", "tolerance",
         [](std::string_view, const std::string& text) {
             double value = 0;
             const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
             if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || !(value > 0))
                 throw UsageError{"--tolerance needs a number > 0, got \"" + text + "\""};
             return text;
         }},
        {"--segments", "segments", integer(1, 1'000'000)},
        {"--quantize-position", "quantize_position", integer(1, 30)},
        {"--max-output-faces", "", integer(1, 4'000'000'000LL)},
        flag("--no-draco"),
        flag("--no-normals", "normals", "false"),
    };
    const auto parsed = parse_file_command(args, "tessellate", kTessellateHelp, options);
    if (!parsed) return kExitOk;
    if (parsed->has("--tolerance") && parsed->has("--segments"))
        throw UsageError{"tessellate: give --tolerance or --segments, not both"};
    using enum api::OutputFormat;
    const api::OutputFormat format = output_format(parsed->output, {Glb, Obj, Ply}, ".glb .obj .ply");
    if (parsed->has("--quantize-position") && (format != Glb || parsed->has("--no-draco")))
        throw UsageError{"--quantize-position applies only to .glb output with Draco"};
    if (parsed->has("--max-output-faces"))
        context.limits.max_output_faces = std::stoull(parsed->value("--max-output-faces"));

    // The request POST /tessellate (or GET /patches/NAME) would receive: one code path for CLI and service.
    std::optional<std::string> bytes;
    api::ApiRequest request;
    if (parsed->input.starts_with("sample:")) {
        request.method = "GET";
        request.path = "/patches/" + parsed->input.substr(7);
        request.query = file_query(*parsed, options, format);
    } else {
        bytes = read_input(parsed->input);
        if (!bytes) return kExitFailed;
        const bool obj = lower_extension(parsed->input) == ".obj";  // free-form cstype bezier surfaces
        request = upload_request("/tessellate", obj ? "model/obj" : "application/x-geomview-bez", *bytes,
                                 file_query(*parsed, options, format));
    }
    return finish(
        api::dispatch(request, context), *parsed,
        [&](const api::ApiResponse& response) {
            std::cout << "wrote " << parsed->output << ": " << header(response, "X-Output-Vertices") << " vertices, "
                      << header(response, "X-Output-Faces") << " triangles from " << header(response, "X-Patches")
                      << " patches, max deviation <= " << header(response, "X-Error-Bound") << ", in "
                      << header(response, "X-Elapsed-Ms") << " ms\n";
        },
        ProblemStyle{.line = true, .offset = false});
}

// ---- simplify ------------------------------------------------------------------------------------------------

constexpr std::string_view kSimplifyHelp =
    R"(Usage: surfaced simplify IN -o OUT (--target-faces N | --ratio R | --max-error E) [options]

Simplifies the mesh in IN by quadric-error edge collapse and writes it to OUT, through the same operation as
POST /simplify. Polygons are triangulated first. Stops at whichever of the given criteria is reached first.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required)
  --target-faces N          stop at N triangles or fewer
  --ratio R                 stop at R times the input's triangles, 0 < R <= 1
  --max-error E             keep the Hausdorff distance to the input <= E (model units)
  --lock-border             boundary vertices stay exactly where they are
  --locked-vertices LIST    vertices that stay exactly where they are (0-based indices into IN: 0,5,100)
  --restore-volume A        volume restoration, 0..1 (default 0): 1 keeps the volume, 0.5 lowers the RMS error
                            by 4-20% on smooth meshes, for 0-14% more time
  --threads N               1 (default) or 2: meshes of 20,000 triangles or more first collapse on two
                            threads, one half of the mesh each; 1.3-2x faster, a slightly different result
  --report-error            measure and print the Hausdorff and RMS distance to the input
  --repair MODE             auto (default): repair the mesh first when it needs it (printed on stderr);
                            none: refuse a non-manifold mesh
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

int simplify(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--target-faces", "target_faces", integer(0, 4'000'000'000LL)},
        {"--ratio", "ratio", real()},
        {"--max-error", "max_error", real()},
        flag("--lock-border", "lock_border"),
        {"--restore-volume", "restore_volume", real()},
        {"--threads", "threads", integer(1, 2)},
        {"--locked-vertices", "locked_vertices", any_text()},
        flag("--report-error", "report_error"),
        {"--repair", "repair", any_text()},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
    };
    const auto parsed = parse_file_command(args, "simplify", kSimplifyHelp, options);
    if (!parsed) return kExitOk;
    if (!parsed->has("--target-faces") && !parsed->has("--ratio") && !parsed->has("--max-error"))
        throw UsageError{"simplify: give --target-faces, --ratio or --max-error"};
    const MeshFormat in_format = mesh_input_format(parsed->input);
    const api::OutputFormat out_format = mesh_output_format(parsed->output);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh(
        "/simplify", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            print_repairs(*parsed, response);
            print_triangulated_result(*parsed, response);
            std::cout << ", error " << header(response, "X-Achieved-Error") << " ("
                      << header(response, "X-Relative-Error") << " of the bounding-box diagonal)";
            if (parsed->has("--report-error"))
                std::cout << ", Hausdorff " << header(response, "X-Hausdorff") << ", RMS " << header(response, "X-RMS");
            std::cout << ", in " << header(response, "X-Elapsed-Ms") << " ms\n";
        });
}

// ---- remesh --------------------------------------------------------------------------------------------------

constexpr std::string_view kRemeshHelp =
    R"(Usage: surfaced remesh IN -o OUT [--edge-length L] [--iterations K] [options]

Remeshes the mesh in IN isotropically (split, collapse, flip, relax, project; Botsch-Kobbelt) towards edges of
length L and writes it to OUT, through the same operation as POST /remesh. Polygons are triangulated first. Sharp
edges and the boundary are kept. Prints the triangle quality before and after and the Hausdorff distance.
  IN:  .obj .off .ply .stl .glb .gltf  OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required)
  --edge-length L           target edge length in model units (default: the input's mean edge length)
  --iterations K            rounds of split/collapse/flip/relax, 0..100 (default 10)
  --feature-angle DEG       dihedral angle above which an edge is sharp, 0..180 (default 60; 180: none)
  --free-boundary           relax boundary vertices like interior ones (default: keep the boundary)
  --smoothing S             tangential (default), laplacian or none
  --repair MODE             auto (default): repair the mesh first when it needs it (printed on stderr);
                            none: refuse a non-manifold mesh
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

int remesh(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--edge-length", "edge_length", real()},
        {"--iterations", "iterations", integer(0, 100)},
        {"--feature-angle", "feature_angle", real()},
        {"--smoothing", "smoothing", any_text()},
        flag("--free-boundary", "keep_boundary", "false"),
        {"--repair", "repair", any_text()},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
    };
    const auto parsed = parse_file_command(args, "remesh", kRemeshHelp, options);
    if (!parsed) return kExitOk;
    const MeshFormat in_format = mesh_input_format(parsed->input);
    const api::OutputFormat out_format = mesh_output_format(parsed->output);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh(
        "/remesh", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            print_repairs(*parsed, response);
            print_triangulated_result(*parsed, response);
            std::cout << ", edge length " << header(response, "X-Edge-Length") << " (mean "
                      << header(response, "X-Mean-Edge-Length-After") << "), min angle "
                      << header(response, "X-Min-Angle-Before") << " -> " << header(response, "X-Min-Angle-After")
                      << " deg, below 30 deg " << header(response, "X-Below-30-Before") << " -> "
                      << header(response, "X-Below-30-After") << ", radius ratio "
                      << header(response, "X-Radius-Ratio-Before") << " -> " << header(response, "X-Radius-Ratio-After")
                      << ", Hausdorff " << header(response, "X-Hausdorff") << ", in "
                      << header(response, "X-Elapsed-Ms") << " ms\n";
        });
}

// ---- repair --------------------------------------------------------------------------------------------------

constexpr std::string_view kRepairHelp =
    R"(Usage: surfaced repair IN -o OUT [options]

Repairs the mesh in IN and writes it to OUT, through the same operation as POST /repair: welds vertices at the same
position, drops degenerate and duplicate faces, orients faces consistently (outward for closed parts), cuts
non-manifold edges and vertices apart, drops unreferenced vertices; optionally drops small components and fills small
holes. Prints what it did.
  IN:  .obj .off .ply .stl .glb        OUT: .obj .ply .glb .gltf .json

Options:
  -o, --output OUT          output file (required)
  --weld-tolerance D        also weld vertices closer than D (model units; default 0: identical positions only)
  --no-orient               leave the faces' orientation as it is
  --min-component-faces N   drop connected components with fewer than N faces (default 0: keep all)
  --max-hole-edges N        fill holes with at most N boundary edges, 0..10000 (default 0: none)
  --no-draco                write an uncompressed .glb
  --quantize-position BITS  Draco position quantization, 1..24 (default 14; .glb/.gltf only)
  --normals                 also write vertex normals (.glb .gltf .obj .ply)
  -h, --help                this text
)";

int repair(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--weld-tolerance", "weld_tolerance", real()},
        flag("--no-orient", "orient", "false"),
        {"--min-component-faces", "min_component_faces", integer(0, 4'000'000'000LL)},
        {"--max-hole-edges", "max_hole_edges", integer(0, 10'000)},
        {"--quantize-position", "quantize_position", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals", "normals"),
    };
    const auto parsed = parse_file_command(args, "repair", kRepairHelp, options);
    if (!parsed) return kExitOk;
    const MeshFormat in_format = mesh_input_format(parsed->input);
    const api::OutputFormat out_format = mesh_output_format(parsed->output);
    check_mesh_output_options(*parsed, out_format);

    return upload_mesh(
        "/repair", *parsed, options, in_format, out_format, context, [&](const api::ApiResponse& response) {
            std::cout << "wrote " << parsed->output << ": " << header(response, "X-Output-Faces") << " faces, "
                      << header(response, "X-Output-Vertices") << " vertices (from "
                      << header(response, "X-Input-Faces") << " faces, " << header(response, "X-Input-Vertices")
                      << " vertices): " << header(response, "X-Repairs") << ", in " << header(response, "X-Elapsed-Ms")
                      << " ms\n";
        });
}

// ---- implicit ------------------------------------------------------------------------------------------------

constexpr std::string_view kImplicitHelp =
    R"(Usage: surfaced implicit SCENE.json -o OUT [--resolution N | --cell-size H] [options]

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
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--resolution", "", integer(2, 65536)},
        {"--cell-size", "", real()},
        {"--mode", "",
         [](std::string_view, const std::string& text) {
             if (text != "uniform" && text != "adaptive")
                 throw UsageError{"--mode: unknown value \"" + text + "\" (allowed: uniform, adaptive)"};
             return text;
         }},
        {"--simplify-tolerance", "", real()},
        {"--max-grid-cells", "", integer(1, 1'000'000'000'000LL)},
        {"--quantize-position", "", integer(1, 24)},
        flag("--no-draco"),
        flag("--normals"),
    };
    const auto parsed = parse_file_command(args, "implicit", kImplicitHelp, options, "SCENE.json");
    if (!parsed) return kExitOk;
    if (parsed->has("--resolution") && parsed->has("--cell-size"))
        throw UsageError{"give --resolution or --cell-size, not both"};
    const api::OutputFormat out_format = mesh_output_format(parsed->output);
    check_mesh_output_options(*parsed, out_format);
    // The overrides implicit_mesh_from_file lays over the file's request.
    api::operations::ImplicitMeshOverrides overrides;
    if (parsed->has("--resolution")) overrides.resolution = std::stoll(parsed->value("--resolution"));
    if (parsed->has("--cell-size")) overrides.cell_size = std::stod(parsed->value("--cell-size"));
    if (parsed->has("--mode")) overrides.mode = parsed->value("--mode");
    if (parsed->has("--simplify-tolerance"))
        overrides.simplify_tolerance = std::stod(parsed->value("--simplify-tolerance"));
    if (parsed->has("--max-grid-cells")) context.limits.max_grid_cells = std::stoull(parsed->value("--max-grid-cells"));
    overrides.output.format = out_format;
    if (parsed->has("--no-draco") && is_gltf(out_format)) overrides.output.draco = false;
    if (parsed->has("--quantize-position"))
        overrides.output.quantize_position = std::stoll(parsed->value("--quantize-position"));
    if (parsed->has("--normals")) overrides.output.normals = true;

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    return finish(
        api::operations::implicit_mesh_from_file(*bytes, overrides, context), *parsed,
        [&](const api::ApiResponse& response) {
            std::cout << "wrote " << parsed->output << ": " << header(response, "X-Output-Faces") << " triangles, "
                      << header(response, "X-Output-Vertices") << " vertices, grid " << header(response, "X-Grid")
                      << " (" << header(response, "X-Surface-Cells") << " surface cells, "
                      << header(response, "X-Field-Evaluations") << " field evaluations), in "
                      << header(response, "X-Elapsed-Ms") << " ms\n";
        },
        ProblemStyle{.field = true, .line = false, .offset = true});
}

// ---- pointcloud ----------------------------------------------------------------------------------------------

constexpr std::string_view kPointcloudHelp =
    R"(Usage: surfaced pointcloud IN -o OUT [--estimate-normals [--k N]] [options]

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
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        flag("--estimate-normals", "estimate_normals"),
        {"--k", "k", integer(3, 256)},
        flag("--no-normals", "normals", "false"),
        flag("--no-draco"),
        {"--quantize-position", "quantize_position", integer(1, 24)},
    };
    const auto parsed = parse_file_command(args, "pointcloud", kPointcloudHelp, options);
    if (!parsed) return kExitOk;
    if (parsed->has("--k") && !parsed->has("--estimate-normals"))
        throw UsageError{"--k applies only with --estimate-normals"};
    const auto in_format = point_format_from_extension(parsed->input);
    if (!in_format)
        throw UsageError{"cannot tell the point format of " + parsed->input +
                         " from its extension (use .ply .obj .xyz)"};
    using enum api::OutputFormat;
    const api::OutputFormat out_format = output_format(parsed->output, {Glb, Ply, Json}, ".glb .ply .json");
    const bool no_draco = parsed->has("--no-draco"), quantize = parsed->has("--quantize-position");
    if ((no_draco || quantize) && out_format != Glb)
        throw UsageError{"--no-draco and --quantize-position apply only to .glb output"};
    if (quantize && no_draco) throw UsageError{"--quantize-position applies only with Draco"};

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    const std::string content_type = *in_format == PointFormat::Ply   ? "application/ply"
                                     : *in_format == PointFormat::Obj ? "model/obj"
                                                                      : "text/x-xyz";
    const api::ApiRequest request =
        upload_request("/pointcloud", content_type, *bytes, file_query(*parsed, options, out_format));
    return finish(api::dispatch(request, context), *parsed, [&](const api::ApiResponse& response) {
        std::cout << "wrote " << parsed->output << ": " << header(response, "X-Output-Points") << " points"
                  << (header(response, "X-Normals") == "true" ? ", normals" : "")
                  << (header(response, "X-Colors") == "true" ? ", colors" : "") << ", in "
                  << header(response, "X-Elapsed-Ms") << " ms\n";
    });
}

// ---- curve ---------------------------------------------------------------------------------------------------

constexpr std::string_view kCurveHelp =
    R"(Usage: surfaced curve IN.json|IN.svg -o OUT [--tolerance T] [--continuity] [--enforce-c1 MODE]

Runs curve queries on the curve in IN and writes the answer to OUT, through the same operation as POST /curves.
  IN:  .json  a POST /curves body: one of "points", "chain", "svg", "bspline", and its queries
       .svg   the d attributes of the <path> elements (one chain per subpath; transforms are not applied),
              or a file of bare path data
  OUT: .json (the answer) .glb .gltf (the tessellation as glTF line strips; no Draco, which is for triangles)

Options:
  -o, --output OUT       output file (required)
  --tolerance T          tessellate within T model units (.glb/.gltf: default the file's, else 0.001)
  --continuity           report every joint: gap, derivative mismatch, angle, class (chains, SVG paths)
  --enforce-c1 MODE      make every joint C1 or G1 (MODE: C1, G1) by the mirror rule (chains, SVG paths);
                         the answer has the modified chain, and the tessellation is of it
  -h, --help             this text
)";

int curve(Args& args) {
    api::ApiContext context = file_context();
    const std::vector<Option> options = {
        {"--tolerance", "", real()},
        flag("--continuity"),
        {"--enforce-c1", "",
         [](std::string_view, const std::string& text) {
             if (text != "C1" && text != "G1")
                 throw UsageError{"--enforce-c1: unknown value \"" + text + "\" (allowed: C1, G1)"};
             return text;
         }},
    };
    const auto parsed = parse_file_command(args, "curve", kCurveHelp, options, "IN.json or IN.svg");
    if (!parsed) return kExitOk;
    const std::string in_ext = lower_extension(parsed->input);
    if (in_ext != ".json" && in_ext != ".svg")
        throw UsageError{"cannot tell the curve format of " + parsed->input + " from its extension (use .json .svg)"};
    using enum api::OutputFormat;
    const api::OutputFormat out_format = output_format(parsed->output, {Json, Glb, Gltf}, ".json .glb .gltf");
    api::operations::CurveFileOverrides overrides;
    overrides.svg = in_ext == ".svg";
    overrides.format = out_format;
    if (parsed->has("--tolerance")) overrides.tolerance = std::stod(parsed->value("--tolerance"));
    overrides.continuity = parsed->has("--continuity");
    if (parsed->has("--enforce-c1")) overrides.enforce_c1 = parsed->value("--enforce-c1");

    const auto bytes = read_input(parsed->input);
    if (!bytes) return kExitFailed;
    return finish(
        api::operations::curves_from_file(*bytes, overrides, context), *parsed,
        [&](const api::ApiResponse& response) {
            std::cout << "wrote " << parsed->output;
            if (out_format != Json)
                std::cout << ": " << header(response, "X-Polylines") << " line strip(s), "
                          << header(response, "X-Segments") << " segments within " << header(response, "X-Error-Bound")
                          << " of the curve";
            std::cout << "\n";
        },
        ProblemStyle{.field = true, .line = true, .offset = true});
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
        if (command == "repair") return repair(args);
        if (command == "implicit") return implicit(args);
        if (command == "pointcloud") return pointcloud(args);
        if (command == "curve") return curve(args);
        throw UsageError{"unknown command \"" + command +
                         "\" (commands: serve, healthcheck, subdivide, tessellate, simplify, remesh, repair, implicit, "
                         "pointcloud, curve; see surfaced --help)"};
    } catch (const UsageError& e) {
        std::cerr << "surfaced: " << e.message << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "surfaced: internal error: " << e.what() << "\n";
        return kExitFailed;
    }
}

}  // namespace surfaced::cli
