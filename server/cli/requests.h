// The requests the file commands send: the ApiRequest an upload of IN with the given options would be, the context
// of a run in process, and the common path of the mesh commands (read IN, dispatch, finish).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/operation.h"
#include "api/routes.h"
#include "server/cli/args.h"
#include "server/cli/files.h"
#include "server/cli/output.h"

namespace surfaced::cli {

//! The query parameters of the raw-file request form: the operation's options given, and the output format. Whether
//! an option applies to the format is the operation's to say (a 400 naming it, which is exit code 2).
std::multimap<std::string, std::string> file_query(const Parsed& parsed, api::OutputFormat format);

//! The request POST `path` would receive for an upload of `body`: one code path for the CLI and the service.
api::ApiRequest upload_request(std::string path, std::string content_type, std::string_view body,
                               std::multimap<std::string, std::string> query);

//! The context of a command run in process. Files are the user's own: the body limit protects the server's memory,
//! not the CLI's.
api::ApiContext file_context();

//! subdivide, simplify, remesh, repair after their own checks: IN read and sent as the raw-file form of POST `path`
//! with the query of the options given (`in_format` nullopt: sniffed from the bytes); then `finish`.
template <class Summary>
int upload_mesh(std::string path, const Parsed& parsed, std::optional<MeshFormat> in_format,
                api::OutputFormat out_format, const api::ApiContext& context, Summary&& summary) {
    const auto bytes = read_input(parsed.input);
    if (!bytes) return kExitFailed;
    if (!in_format) in_format = sniff_mesh_format(*bytes);
    const api::ApiRequest request =
        upload_request(std::move(path), std::string(api::enum_name(api::kMeshMediaTypes, *in_format)), *bytes,
                       file_query(parsed, out_format));
    return finish(api::dispatch(request, context), parsed, std::forward<Summary>(summary));
}

}  // namespace surfaced::cli
