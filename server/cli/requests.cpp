#include "server/cli/requests.h"

namespace surfaced::cli {

void check_mesh_output_options(const Parsed& parsed, api::OutputFormat format) {
    if (parsed.has("--quantize-position") && (!is_gltf(format) || parsed.has("--no-draco")))
        throw UsageError{"--quantize-position applies only to .glb/.gltf output with Draco"};
    if (parsed.has("--normals") && format == api::OutputFormat::Json)
        throw UsageError{"--normals is not available for .json output"};
}

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

api::ApiContext file_context() {
    api::ApiContext context;
    context.limits.max_body_bytes = static_cast<std::size_t>(-1);
    return context;
}

}  // namespace surfaced::cli
