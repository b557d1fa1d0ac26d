// `surfaced serve` (the HTTP service until a stop signal) and `surfaced healthcheck` (a probe of a running one).
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>

#include "api/routes.h"
#include "server/cli/commands.h"
#include "server/cli/files.h"
#include "server/cli/limit_flags.h"
#include "server/http_server.h"

#ifndef SURFACED_VERSION
#define SURFACED_VERSION "unknown"
#endif
#ifndef SURFACED_DEFAULT_WEB_ROOT
#define SURFACED_DEFAULT_WEB_ROOT ""
#endif

namespace surfaced::cli {
namespace {

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
)";

constexpr std::string_view kServeHelpEnd = R"(  -h, --help             this text

Every budget is checked before the work it bounds starts; a request over one gets 422 budget_exceeded.

Endpoints:
)";

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
        std::cout << kServeHelp << limit_flags_help() << kServeHelpEnd;
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
    } else if (std::ranges::count(limit_flag_names(), arg) > 0) {
        apply_limit_flag(arg, args.value(arg, inline_value), config.limits);  // a budget of api/limits.h
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
        const std::string where = one_of_names({"off", "stdout", "stderr"})(arg, args.value(arg, inline_value));
        if (where == "off")
            config.access_log = server::ServerConfig::AccessLog::Off;
        else if (where == "stdout")
            config.access_log = server::ServerConfig::AccessLog::Stdout;
        else
            config.access_log = server::ServerConfig::AccessLog::Stderr;
    } else if (arg == "--auth-token-file") {
        options.auth_token_file = args.value(arg, inline_value);
    } else if (arg == "--cors-origin") {
        const std::string origin = args.value(arg, inline_value);
        if (origin.empty() || origin.find_first_of("\r\n ,") != std::string::npos)
            throw UsageError{"--cors-origin: \"" + origin + "\" is not an origin (scheme://host[:port], or *)"};
        config.cors_origins.push_back(origin);
    } else {
        if (!arg.starts_with("-")) throw UsageError{"serve: unexpected argument \"" + arg + "\""};
        std::vector<std::string_view> known = {"--host",
                                               "--port",
                                               "--threads",
                                               "--queue",
                                               "--deadline-ms",
                                               "--keep-alive-max",
                                               "--keep-alive-timeout",
                                               "--header-timeout",
                                               "--body-timeout",
                                               "--body-min-rate",
                                               "--drain-timeout",
                                               "--drain-delay-ms",
                                               "--access-log",
                                               "--auth-token-file",
                                               "--cors-origin",
                                               "--web-root",
                                               "--max-body-mb",
                                               "--max-levels",
                                               "--max-output-faces",
                                               "--help"};
        for (std::string_view flag : limit_flag_names()) known.push_back(flag);
        throw unknown_option("serve", arg, known);
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

}  // namespace

int serve(Args& args) {
    const std::optional<server::ServerConfig> config = serve_config(args);
    if (!config) return kExitOk;
    return serve_until_signalled(*config);
}

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
                if (!arg.starts_with("-")) throw UsageError{"healthcheck: unexpected argument \"" + arg + "\""};
                throw unknown_option("healthcheck", arg, {"--host", "--port", "--timeout", "--path", "--help"});
            }
            return true;
        });
    if (!complete) return kExitOk;
    std::string detail;
    if (server::probe_http(host, port, path, timeout, &detail)) return kExitOk;
    std::cerr << "surfaced healthcheck: " << detail << "\n";
    return kExitFailed;
}

}  // namespace surfaced::cli
