#include "api/multipart.h"

#include <algorithm>
#include <cctype>

namespace surfaced::api {
namespace {

ApiError malformed(std::string detail) { return make_problem(Problem::MalformedMultipart, std::move(detail)); }

bool is_blank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && is_blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_blank(s.back())) s.remove_suffix(1);
    return s;
}

bool iequals(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

//! Printable ASCII (for quoting a name in a message); anything else is shown as '?'.
std::string printable(std::string_view s, std::size_t max = 64) {
    std::string out;
    for (char c : s.substr(0, max)) out += c >= 0x20 && c < 0x7f ? c : '?';
    if (s.size() > max) out += "...";
    return out;
}

//! RFC 2046 bchars: DIGIT / ALPHA / "'()+_,-./:=?" and space (not last).
bool boundary_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) ||
           std::string_view("'()+_,-./:=? ").find(c) != std::string_view::npos;
}

//! Parameters after the first ';' of a header value: name=token or name="quoted", names lower-cased. A quoted value
//! may escape a character with a backslash.
struct Parameter {
    std::string name;
    std::string value;
};
ApiResult<std::vector<Parameter>> parse_parameters(std::string_view rest, std::string_view what) {
    std::vector<Parameter> out;
    while (true) {
        rest = trim(rest);
        if (rest.empty()) return out;
        if (rest.front() != ';')
            return malformed(std::string(what) + ": expected ';' before \"" + printable(rest) + "\"");
        rest = trim(rest.substr(1));
        if (rest.empty()) return out;  // a trailing ';'
        const std::size_t equals = rest.find('=');
        if (equals == std::string_view::npos)
            return malformed(std::string(what) + ": parameter \"" + printable(rest) + "\" has no value");
        Parameter parameter;
        for (char c : trim(rest.substr(0, equals)))
            parameter.name += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (parameter.name.empty()) return malformed(std::string(what) + ": a parameter has no name");
        rest = trim(rest.substr(equals + 1));
        if (!rest.empty() && rest.front() == '"') {
            std::size_t i = 1;
            for (; i < rest.size() && rest[i] != '"'; ++i) {
                if (rest[i] == '\\' && i + 1 < rest.size()) ++i;
                parameter.value += rest[i];
            }
            if (i >= rest.size())
                return malformed(std::string(what) + ": the quoted value of " + parameter.name + " is not closed");
            rest.remove_prefix(i + 1);
        } else {
            const std::size_t end = std::min(rest.find(';'), rest.size());
            parameter.value = std::string(trim(rest.substr(0, end)));
            rest.remove_prefix(end);
        }
        out.push_back(std::move(parameter));
    }
}

//! The headers of one part (the block before its blank line, without that line): Content-Disposition and
//! Content-Type; other headers are allowed and ignored, except a Content-Transfer-Encoding other than an identity.
std::optional<ApiError> read_part_headers(std::string_view block, std::size_t index, MultipartPart& part) {
    const std::string where = "part " + std::to_string(index);
    bool disposition = false;
    while (!block.empty()) {
        const std::size_t eol = std::min(block.find("\r\n"), block.size());
        const std::string_view line = block.substr(0, eol);
        block.remove_prefix(std::min(block.size(), eol + 2));
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos || colon == 0 || is_blank(line.front()))
            return malformed(where + ": header line \"" + printable(line) + "\" is not \"Name: value\"");
        const std::string_view name = line.substr(0, colon);
        const std::string_view value = trim(line.substr(colon + 1));
        if (iequals(name, "Content-Disposition")) {
            if (disposition) return malformed(where + " has two Content-Disposition headers");
            disposition = true;
            const std::size_t semicolon = std::min(value.find(';'), value.size());
            const std::string_view type = trim(value.substr(0, semicolon));
            if (!iequals(type, "form-data"))
                return malformed(where + ": Content-Disposition is \"" + printable(type) + "\", not form-data");
            auto parameters = parse_parameters(value.substr(semicolon), where + " Content-Disposition");
            if (!parameters) return std::move(parameters.error());
            bool named = false;
            for (const Parameter& parameter : parameters.value()) {
                if (parameter.name == "name") {
                    part.name = parameter.value;
                    named = true;
                } else if (parameter.name == "filename") {
                    part.filename = parameter.value;
                } else if (parameter.name == "filename*" && !part.filename) {
                    // RFC 5987 ext-value, charset'language'percent-encoded: only its presence matters here
                    const std::size_t quote = parameter.value.rfind('\'');
                    part.filename = quote == std::string::npos ? parameter.value : parameter.value.substr(quote + 1);
                }
            }
            if (!named || part.name.empty())
                return malformed(where + ": Content-Disposition has no name (form-data; name=\"...\")");
        } else if (iequals(name, "Content-Type")) {
            part.content_type = std::string(value);
        } else if (iequals(name, "Content-Transfer-Encoding")) {
            if (!iequals(value, "binary") && !iequals(value, "8bit") && !iequals(value, "7bit"))
                return malformed(where + ": Content-Transfer-Encoding \"" + printable(value) +
                                 "\" is not supported (send the bytes as they are)");
        }
    }
    if (!disposition) return malformed(where + " has no Content-Disposition header");
    return std::nullopt;
}

}  // namespace

ApiResult<std::string> multipart_boundary(std::string_view content_type) {
    const std::size_t semicolon = std::min(content_type.find(';'), content_type.size());
    auto parameters = parse_parameters(content_type.substr(semicolon), "Content-Type");
    if (!parameters) return std::move(parameters.error());
    for (const Parameter& parameter : parameters.value()) {
        if (parameter.name != "boundary") continue;
        const std::string& b = parameter.value;
        if (b.empty() || b.size() > 70 || b.back() == ' ' || !std::all_of(b.begin(), b.end(), boundary_char))
            return malformed("the boundary \"" + printable(b, 80) +
                             "\" is not 1 to 70 of the characters RFC 2046 allows (letters, digits, '()+_,-./:=? )");
        return b;
    }
    return malformed(
        "the Content-Type multipart/form-data has no boundary parameter (multipart/form-data; "
        "boundary=...)");
}

ApiResult<std::vector<MultipartPart>> parse_multipart(std::string_view body, std::string_view boundary,
                                                      const MultipartLimits& limits) {
    const std::string delimiter = "--" + std::string(boundary);
    const std::string inner = "\r\n" + delimiter;  // a delimiter after content (the CRLF belongs to it)
    // The first delimiter opens the body or follows a preamble's CRLF.
    std::size_t at = 0;
    if (body.substr(0, delimiter.size()) != delimiter) {
        const std::size_t found = body.find(inner);
        if (found == std::string_view::npos)
            return malformed("the body has no delimiter line \"" + printable(delimiter, 80) +
                             "\" (does the boundary in Content-Type match the body's?)");
        at = found + 2;
    }
    std::vector<MultipartPart> parts;
    for (;;) {
        at += delimiter.size();  // `at` is at a delimiter
        const std::string_view after = body.substr(at);
        if (after.substr(0, 2) == "--") return parts;  // the close delimiter; an epilogue may follow
        std::size_t i = 0;
        while (i < after.size() && is_blank(after[i])) ++i;  // transport padding
        if (after.substr(i, 2) != "\r\n") {
            if (after.empty())
                return malformed("the body ends after a delimiter without the close delimiter \"" +
                                 printable(delimiter, 80) + "--\"");
            return malformed("a delimiter line \"" + printable(delimiter, 80) + "\" is followed by \"" +
                             printable(after.substr(i, 16)) + "\" instead of CRLF or \"--\"");
        }
        at += i + 2;
        if (parts.size() == limits.max_parts)
            return malformed("more than " + std::to_string(limits.max_parts) + " parts");
        const std::size_t index = parts.size() + 1;
        // headers: up to a blank line (none: the part opens with it)
        const std::string_view rest = body.substr(at);
        std::string_view block;
        if (rest.substr(0, 2) == "\r\n") {
            at += 2;
        } else {
            const std::size_t end = rest.substr(0, limits.max_header_bytes + 4).find("\r\n\r\n");
            if (end == std::string_view::npos) {
                if (rest.size() > limits.max_header_bytes)
                    return malformed("part " + std::to_string(index) + ": its headers are over " +
                                     std::to_string(limits.max_header_bytes) + " bytes (or lack the blank line)");
                return malformed("part " + std::to_string(index) + ": its headers do not end with a blank line");
            }
            block = rest.substr(0, end);
            at += end + 4;
        }
        MultipartPart part;
        if (auto error = read_part_headers(block, index, part)) return std::move(*error);
        // content: up to CRLF and the next delimiter
        const std::size_t end = body.find(inner, at);
        if (end == std::string_view::npos)
            return malformed("part " + std::to_string(index) + " (\"" + printable(part.name) +
                             "\") is not ended by a delimiter line \"" + printable(delimiter, 80) +
                             "\" (the body is cut short, or the boundary does not match)");
        part.body = body.substr(at, end - at);
        parts.push_back(std::move(part));
        at = end + 2;
    }
}

}  // namespace surfaced::api
