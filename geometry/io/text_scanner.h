// Internal to geo_formats: the one tokenizer shared by the text readers (OBJ, OFF, PLY ascii, STL ascii), plus
// error helpers that put the location into both the message and the GeoError fields.
//
// Everything works on string_views into the caller's buffer: no per-line or per-token allocation. Numbers go
// through std::from_chars (locale-independent, no allocation). Lines end at '\n'; a trailing '\r' is dropped, so
// CRLF files read like LF files.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>
#include <system_error>

#include "geometry/core/result.h"

namespace surfaced::io_detail {

inline GeoError error_at_line(ErrorCode code, std::int64_t line, std::string_view what) {
    std::string message = "line " + std::to_string(line) + ": ";
    message.append(what);
    return make_error(code, std::move(message), line);
}

inline GeoError error_at_offset(ErrorCode code, std::int64_t offset, std::string_view what) {
    std::string message = "offset " + std::to_string(offset) + ": ";
    message.append(what);
    return make_error(code, std::move(message), -1, offset);
}

//! Quotes a token for an error message, cut short and with control bytes escaped so garbage stays readable.
inline std::string quote(std::string_view token) {
    constexpr std::size_t kMax = 32;
    std::string out = "'";
    for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
        const auto c = static_cast<unsigned char>(token[i]);
        if (c >= 0x20 && c < 0x7f) {
            out += static_cast<char>(c);
        } else {
            static constexpr char kHex[] = "0123456789abcdef";
            out += "\\x";
            out += kHex[c >> 4];
            out += kHex[c & 15];
        }
    }
    if (token.size() > kMax) out += "...";
    out += "'";
    return out;
}

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

//! 1-based line number of byte `offset` (only used on error paths: it counts newlines).
inline std::int64_t line_of_offset(std::string_view text, std::size_t offset) {
    std::int64_t line = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i)
        if (text[i] == '\n') ++line;
    return line;
}

enum class NumberStatus { Ok, Invalid, OutOfRange };

//! Parses a whole token as a double ("+1", "1e5", "nan", "inf" accepted; the caller checks finiteness).
inline NumberStatus parse_double(std::string_view token, double& out) {
    const char* first = token.data();
    const char* last = first + token.size();
    if (first != last && *first == '+') ++first;
    if (first == last) return NumberStatus::Invalid;
    auto [ptr, ec] = std::from_chars(first, last, out);
    if (ptr != last) return NumberStatus::Invalid;
    if (ec == std::errc::result_out_of_range) {
        // from_chars reports overflow and underflow alike and leaves `out` alone; strtod (error path only)
        // gives the IEEE answer: +-HUGE_VAL (then rejected as non-finite) or a tiny/zero value (accepted).
        char buffer[128];
        if (token.size() >= sizeof(buffer)) return NumberStatus::OutOfRange;
        std::memcpy(buffer, token.data(), token.size());
        buffer[token.size()] = '\0';
        out = std::strtod(buffer, nullptr);
        return NumberStatus::Ok;
    }
    return ec == std::errc() ? NumberStatus::Ok : NumberStatus::Invalid;
}

//! Parses a whole token as a signed 64-bit integer ("+3" accepted).
inline NumberStatus parse_int(std::string_view token, std::int64_t& out) {
    const char* first = token.data();
    const char* last = first + token.size();
    if (first != last && *first == '+') ++first;
    if (first == last) return NumberStatus::Invalid;
    auto [ptr, ec] = std::from_chars(first, last, out);
    if (ptr != last) return NumberStatus::Invalid;
    if (ec == std::errc::result_out_of_range) return NumberStatus::OutOfRange;
    return ec == std::errc() ? NumberStatus::Ok : NumberStatus::Invalid;
}

//! Whitespace-separated tokens of one line.
class Tokens {
public:
    Tokens() = default;
    explicit Tokens(std::string_view text) : text_(text) {}

    bool next(std::string_view& token) {
        std::size_t i = 0;
        const std::size_t n = text_.size();
        while (i < n && is_space(text_[i])) ++i;
        if (i == n) {
            text_ = {};
            return false;
        }
        std::size_t j = i + 1;
        while (j < n && !is_space(text_[j])) ++j;
        token = text_.substr(i, j - i);
        text_.remove_prefix(j);
        return true;
    }
    //! True when only whitespace is left.
    bool empty() const {
        for (char c : text_)
            if (!is_space(c)) return false;
        return true;
    }
    std::string_view rest() const { return text_; }

private:
    std::string_view text_;
};

//! Lines of a text, numbered from 1. With continuations on, a line ending in '\' is joined with the next one
//! (OBJ); the joined line is built in a buffer reused across lines, and it reports the number of its first line.
class LineReader {
public:
    //! `first_line` numbers the line at `start` (a PLY body starts after its header lines).
    LineReader(std::string_view text, std::size_t start, bool continuations = false, std::int64_t first_line = 1)
        : text_(text), pos_(start), continuations_(continuations), next_line_(first_line) {}

    bool next(std::string_view& line) {
        if (pos_ >= text_.size()) return false;
        line_ = next_line_;
        std::string_view piece = take_physical_line();
        if (!continuations_ || !ends_with_backslash(piece)) {
            line = piece;
            return true;
        }
        joined_.clear();
        while (true) {
            piece.remove_suffix(1);  // the backslash
            joined_.append(piece);
            joined_ += ' ';
            if (pos_ >= text_.size()) break;
            piece = take_physical_line();
            if (!ends_with_backslash(piece)) {
                joined_.append(piece);
                break;
            }
        }
        line = joined_;
        return true;
    }

    //! Number of the line last returned by next().
    std::int64_t line_number() const { return line_; }
    //! Byte offset of the next unread line.
    std::size_t position() const { return pos_; }
    std::size_t remaining_bytes() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

private:
    std::string_view take_physical_line() {
        const char* begin = text_.data() + pos_;
        const std::size_t left = text_.size() - pos_;
        const void* nl = std::memchr(begin, '\n', left);
        std::size_t length = nl ? static_cast<std::size_t>(static_cast<const char*>(nl) - begin) : left;
        pos_ += nl ? length + 1 : length;
        ++next_line_;
        if (length > 0 && begin[length - 1] == '\r') --length;
        return {begin, length};
    }
    static bool ends_with_backslash(std::string_view s) { return !s.empty() && s.back() == '\\'; }

    std::string_view text_;
    std::size_t pos_ = 0;
    bool continuations_ = false;
    std::int64_t next_line_ = 1;
    std::int64_t line_ = 0;
    std::string joined_;
};

//! Tokens across line breaks (OFF, PLY ascii, STL ascii), with an optional comment character that hides the rest
//! of its line. skip_line() drops what is left of the current line (OFF colors after a face, STL solid names).
class TokenReader {
public:
    TokenReader(std::string_view text, std::size_t start, char comment = '\0', std::int64_t first_line = 1)
        : lines_(text, start, false, first_line), comment_(comment) {}

    bool next(std::string_view& token) {
        while (!tokens_.next(token)) {
            if (!load_line()) return false;
        }
        return true;
    }
    //! Next token, but only from the current line.
    bool next_on_line(std::string_view& token) { return tokens_.next(token); }
    bool line_has_more() const { return !tokens_.empty(); }
    void skip_line() { tokens_ = Tokens(); }
    //! Line of the most recent token (or of the last line read).
    std::int64_t line() const { return std::max<std::int64_t>(lines_.line_number(), 1); }
    //! Bytes not yet read, counting the rest of the current line.
    std::size_t remaining_bytes() const { return lines_.remaining_bytes() + tokens_.rest().size(); }

private:
    bool load_line() {
        std::string_view line;
        if (!lines_.next(line)) return false;
        if (comment_ != '\0') {
            const std::size_t hash = line.find(comment_);
            if (hash != std::string_view::npos) line = line.substr(0, hash);
        }
        tokens_ = Tokens(line);
        return true;
    }

    LineReader lines_;
    Tokens tokens_;
    char comment_;
};

//! Case-insensitive ASCII comparison (STL keywords come in either case).
inline bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
        if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
        if (x != y) return false;
    }
    return true;
}

}  // namespace surfaced::io_detail
