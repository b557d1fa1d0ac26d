// libFuzzer target: multipart/form-data intake. The input's first line is the Content-Type (its boundary parameter
// read by multipart_boundary), the rest the body: parse_multipart must give parts whose content lies inside the body
// and whose names are not empty, or a 400 malformed_multipart with a detail; check_upload (the form as the raw-file
// request it stands for) must answer 4xx problems only.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "api/multipart.h"
#include "api/operations/request_forms.h"
#include "fuzz/fuzz_api_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const std::size_t newline = input.find('\n');
    const std::string_view content_type = input.substr(0, newline);
    const std::string_view body = newline == std::string_view::npos ? std::string_view() : input.substr(newline + 1);

    const auto boundary = api::multipart_boundary(content_type);
    fuzz::check_api_result(boundary);
    if (boundary.ok()) {
        api::MultipartLimits limits;
        limits.max_parts = 16;
        limits.max_header_bytes = 512;
        const auto parts = api::parse_multipart(body, boundary.value(), limits);
        fuzz::check_api_result(parts);
        if (!parts.ok() && parts.error().code != "malformed_multipart")
            fuzz::fail("parse_multipart answered another code", parts.error().code);
        if (parts.ok()) {
            if (parts->size() > limits.max_parts) fuzz::fail("more parts than the limit", "");
            for (const api::MultipartPart& part : parts.value()) {
                if (part.name.empty()) fuzz::fail("a part without a name", "");
                if (part.body.data() < body.data() || part.body.data() + part.body.size() > body.data() + body.size())
                    fuzz::fail("a part's content lies outside the body", part.name);
            }
        }
    }

    api::ApiRequest request;
    request.method = "POST";
    request.path = "/subdivide";
    request.content_type = std::string(content_type);
    request.body = body;
    api::operations::Upload upload;
    const auto error = api::operations::check_upload(request, api::Limits{}, "multipart/form-data",
                                                     api::operations::reads_mesh_media_type, upload);
    if (error) {
        if (error->status < 400 || error->status >= 500) fuzz::fail("check_upload answered non-4xx", error->code);
        if (error->detail.empty()) fuzz::fail("check_upload error", "empty detail for " + error->code);
    } else if (upload.request == nullptr || upload.media_type.empty()) {
        fuzz::fail("check_upload accepted a request without a media type", "");
    }
    return 0;
}
