#include "server/cli/requests.h"

namespace surfaced::cli {

std::multimap<std::string, std::string> file_query(const Parsed& parsed, api::OutputFormat format) {
    std::multimap<std::string, std::string> query(parsed.params.begin(), parsed.params.end());
    query.emplace("format", std::string(api::enum_name(api::kOutputFormatNames, format)));
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
