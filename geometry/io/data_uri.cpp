// Base64 data: URIs: see data_uri.h.
#include "geometry/io/data_uri.h"

#include "geometry/io/base64.h"

#include <cstdint>
#include <string>

namespace surfaced::io_detail {

namespace {

bool iequals_ascii(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

}  // namespace

bool is_data_uri(std::string_view uri) { return uri.size() >= 5 && iequals_ascii(uri.substr(0, 5), "data:"); }

Result<std::vector<unsigned char>> decode_data_uri(std::string_view uri,
                                                   std::initializer_list<std::string_view> media_types) {
    if (!is_data_uri(uri)) return make_error(ErrorCode::ParseError, "is not a data: URI");
    const std::size_t comma = uri.find(',');
    if (comma == std::string_view::npos) return make_error(ErrorCode::ParseError, "data: URI has no ','");
    std::string_view header = uri.substr(5, comma - 5);
    constexpr std::string_view kBase64 = ";base64";
    if (header.size() < kBase64.size() || !iequals_ascii(header.substr(header.size() - kBase64.size()), kBase64))
        return make_error(ErrorCode::Unsupported, "data: URI is not base64 (\";base64,\" expected)");
    header.remove_suffix(kBase64.size());
    bool known = false;
    for (std::string_view type : media_types) known = known || iequals_ascii(header, type);
    if (!known) {
        std::string expected;
        for (std::string_view type : media_types) expected += (expected.empty() ? "" : " or ") + std::string(type);
        return make_error(ErrorCode::Unsupported, "data: URI has media type \"" + std::string(header.substr(0, 100)) +
                                                      "\" (expected " + expected + ")");
    }
    return surfaced::decode_base64(uri.substr(comma + 1));
}

}  // namespace surfaced::io_detail
