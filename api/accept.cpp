#include "api/accept.h"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace surfaced::api {
namespace {

struct Range {
    std::string type;     //!< "model", or "*"
    std::string subtype;  //!< "obj", or "*"
    double q = 1;
};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

//! A qvalue: "0", "1", or up to three decimals ("0.5", "1.000").
std::optional<double> parse_q(std::string_view text) {
    if (text.empty() || (text[0] != '0' && text[0] != '1') || text.size() > 5) return std::nullopt;
    if (text.size() == 1) return text[0] - '0';
    if (text[1] != '.') return std::nullopt;
    double value = text[0] - '0', scale = 0.1;
    for (char c : text.substr(2)) {
        if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
        value += (c - '0') * scale;
        scale /= 10;
    }
    if (value > 1) return std::nullopt;
    return value;
}

//! One element of the list; nullopt when it is not a well-formed media range.
std::optional<Range> parse_range(std::string_view element) {
    std::string_view params = element.substr(std::min(element.find(';'), element.size()));
    const std::string_view type = trim(element.substr(0, element.size() - params.size()));
    const std::size_t slash = type.find('/');
    if (slash == std::string_view::npos || slash == 0 || slash + 1 == type.size()) return std::nullopt;
    Range range{lower(type.substr(0, slash)), lower(type.substr(slash + 1))};
    if (range.type == "*" && range.subtype != "*") return std::nullopt;
    while (!params.empty()) {
        params.remove_prefix(1);  // ';'
        const std::size_t next = std::min(params.find(';'), params.size());
        const std::string_view param = trim(params.substr(0, next));
        params.remove_prefix(next);
        const std::size_t equals = param.find('=');
        if (equals == std::string_view::npos || lower(trim(param.substr(0, equals))) != "q") continue;
        const auto q = parse_q(trim(param.substr(equals + 1)));
        if (!q) return std::nullopt;
        range.q = *q;
        break;  // what follows q are accept-ext parameters
    }
    return range;
}

}  // namespace

std::optional<std::size_t> negotiate_media_type(std::string_view accept, std::span<const std::string_view> offered,
                                                std::size_t preferred) {
    std::vector<Range> ranges;
    while (!accept.empty()) {
        const std::size_t comma = std::min(accept.find(','), accept.size());
        if (auto range = parse_range(accept.substr(0, comma))) ranges.push_back(std::move(*range));
        accept.remove_prefix(std::min(accept.size(), comma + 1));
    }
    if (ranges.empty()) return preferred < offered.size() ? std::optional<std::size_t>(preferred) : std::nullopt;
    std::optional<std::size_t> best;
    double best_q = 0;
    for (std::size_t i = 0; i < offered.size(); ++i) {
        const std::string_view name = offered[i];
        const std::size_t slash = name.find('/');
        const std::string_view type = name.substr(0, slash);
        const std::string_view subtype = slash == std::string_view::npos ? "" : name.substr(slash + 1);
        int specificity = 0;
        double q = 0;
        for (const Range& range : ranges) {
            int s = 0;
            if (range.type == type && range.subtype == subtype)
                s = 3;
            else if (range.type == type && range.subtype == "*")
                s = 2;
            else if (range.type == "*")
                s = 1;
            if (s > specificity) {
                specificity = s;
                q = range.q;
            }
        }
        if (q <= 0) continue;
        if (!best || q > best_q || (q == best_q && i == preferred)) {
            best = i;
            best_q = q;
        }
    }
    return best;
}

}  // namespace surfaced::api
