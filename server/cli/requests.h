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

//! --quantize-position and --normals against a mesh output format.
void check_mesh_output_options(const Parsed& parsed, api::OutputFormat format);

//! The query parameters of the raw-file request form: the options that name one, the output format, and
//! compression "none" for --no-draco with glTF output.
std::multimap<std::string, std::string> file_query(const Parsed& parsed, const std::vector<Option>& options,
                                                   api::OutputFormat format);

//! The request POST `path` would receive for an upload of `body`: one code path for the CLI and the service.
api::ApiRequest upload_request(std::string path, std::string content_type, std::string_view body,
                               std::multimap<std::string, std::string> query);

//! The context of a command run in process. Files are the user's own: the body limit protects the server's memory,
//! not the CLI's.
api::ApiContext file_context();

//! subdivide, simplify, remesh, repair after their own checks: IN read and sent as the raw-file form of POST `path`
//! with the query of the options given (`in_format` nullopt: sniffed from the bytes); then `finish`.
template <class Summary>
int upload_mesh(std::string path, const Parsed& parsed, const std::vector<Option>& options,
                std::optional<MeshFormat> in_format, api::OutputFormat out_format, const api::ApiContext& context,
                Summary&& summary) {
    const auto bytes = read_input(parsed.input);
    if (!bytes) return kExitFailed;
    if (!in_format) in_format = sniff_mesh_format(*bytes);
    const api::ApiRequest request =
        upload_request(std::move(path), std::string(api::enum_name(api::kMeshMediaTypes, *in_format)), *bytes,
                       file_query(parsed, options, out_format));
    return finish(api::dispatch(request, context), parsed, std::forward<Summary>(summary));
}

}  // namespace surfaced::cli
