// Internal to geo_formats: the PLY header (elements, properties, encoding) and the binary value decoding shared by
// the mesh reader (ply.cpp) and the point reader (pointcloud_io.cpp). parse_header checks every declared element
// count against the bytes that follow the header, and the vertex/face counts against ReadOptions, before anything
// is reserved.
#pragma once

#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"

namespace surfaced::io_detail::ply {

using io_detail::error_at_line;
using io_detail::NumberStatus;
using io_detail::quote;

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncodingIn { Ascii, BinaryLittleEndian, BinaryBigEndian };

inline std::optional<PlyType> parse_type(std::string_view name) {
    if (name == "char" || name == "int8") return PlyType::Int8;
    if (name == "uchar" || name == "uint8") return PlyType::UInt8;
    if (name == "short" || name == "int16") return PlyType::Int16;
    if (name == "ushort" || name == "uint16") return PlyType::UInt16;
    if (name == "int" || name == "int32") return PlyType::Int32;
    if (name == "uint" || name == "uint32") return PlyType::UInt32;
    if (name == "float" || name == "float32") return PlyType::Float32;
    if (name == "double" || name == "float64") return PlyType::Float64;
    return std::nullopt;
}

inline std::size_t type_size(PlyType type) {
    switch (type) {
        case PlyType::Int8:
        case PlyType::UInt8: return 1;
        case PlyType::Int16:
        case PlyType::UInt16: return 2;
        case PlyType::Int32:
        case PlyType::UInt32:
        case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 1;
}

inline bool is_integer(PlyType type) { return type != PlyType::Float32 && type != PlyType::Float64; }

struct PlyProperty {
    std::string_view name;
    PlyType type = PlyType::Float32;  //!< the value type, or the item type of a list
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
    std::string_view name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> properties;
    std::int64_t line = 0;  //!< header line that declares it

    //! Fewest bytes one item can take in a binary body (lists counted as empty).
    std::uint64_t min_binary_size() const {
        std::uint64_t size = 0;
        for (const auto& p : properties) size += p.is_list ? type_size(p.count_type) : type_size(p.type);
        return size;
    }
    int find(std::string_view property) const {
        for (std::size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == property) return static_cast<int>(i);
        return -1;
    }
};

struct PlyHeader {
    PlyEncodingIn encoding = PlyEncodingIn::Ascii;
    std::vector<PlyElement> elements;
    std::size_t body_offset = 0;
    std::int64_t body_line = 0;  //!< first line of an ascii body
};

// Values are assembled byte by byte in the file's order, which works the same on any host.
inline std::uint64_t load_bits(const unsigned char* p, std::size_t size, bool big_endian) {
    std::uint64_t bits = 0;
    if (big_endian) {
        for (std::size_t i = 0; i < size; ++i) bits = (bits << 8) | p[i];
    } else {
        for (std::size_t i = size; i-- > 0;) bits = (bits << 8) | p[i];
    }
    return bits;
}

inline double bits_to_double(std::uint64_t bits, PlyType type) {
    switch (type) {
        case PlyType::Int8: return static_cast<std::int8_t>(bits);
        case PlyType::UInt8: return static_cast<std::uint8_t>(bits);
        case PlyType::Int16: return static_cast<std::int16_t>(bits);
        case PlyType::UInt16: return static_cast<std::uint16_t>(bits);
        case PlyType::Int32: return static_cast<std::int32_t>(bits);
        case PlyType::UInt32: return static_cast<std::uint32_t>(bits);
        case PlyType::Float32: return std::bit_cast<float>(static_cast<std::uint32_t>(bits));
        case PlyType::Float64: return std::bit_cast<double>(bits);
    }
    return 0;
}

//! Integer types only (the header parser rejects float list counts and indices).
inline std::int64_t bits_to_int(std::uint64_t bits, PlyType type) {
    switch (type) {
        case PlyType::Int8: return static_cast<std::int8_t>(bits);
        case PlyType::UInt8: return static_cast<std::uint8_t>(bits);
        case PlyType::Int16: return static_cast<std::int16_t>(bits);
        case PlyType::UInt16: return static_cast<std::uint16_t>(bits);
        case PlyType::Int32: return static_cast<std::int32_t>(bits);
        case PlyType::UInt32: return static_cast<std::uint32_t>(bits);
        default: return 0;
    }
}

//! The read position in a binary PLY body, shared by the mesh and point readers: `take` hands out the next n bytes
//! or fails at the end of the file; `truncated` is the error naming the element and item cut short.
class BinaryCursor {
protected:
    explicit BinaryCursor(std::string_view bytes) : bytes_(bytes) {}

    bool take(std::size_t n, const unsigned char*& p) {
        if (bytes_.size() - pos_ < n) return false;
        p = reinterpret_cast<const unsigned char*>(bytes_.data()) + pos_;
        pos_ += n;
        return true;
    }
    GeoError truncated(const PlyElement& e, std::uint64_t item) const {
        return error_at_offset(ErrorCode::ParseError, static_cast<std::int64_t>(pos_),
                               "unexpected end of file in " + quote(e.name) + " element " + std::to_string(item) +
                                   " of " + std::to_string(e.count));
    }

    std::string_view bytes_;
    std::size_t pos_ = 0;
};

//! Where the header starts (after a UTF-8 byte order mark), or the error for a file that is empty or UTF-16 without
//! a byte order mark (UTF-16 with one has been converted by io_detail::with_text).
inline Result<std::size_t> header_start(std::string_view bytes) {
    if (bytes.empty()) return make_error(ErrorCode::ParseError, "empty file", -1, 0);
    std::size_t start = 0;
    if (bytes.size() >= 3 && bytes.substr(0, 3) == "\xef\xbb\xbf") start = 3;
    if (bytes.size() >= start + 2 && (bytes[start] == 0 || bytes[start + 1] == 0))
        return make_error(ErrorCode::ParseError,
                          "UTF-16 is not supported (NUL byte in the header): save the file as UTF-8", 1,
                          static_cast<std::int64_t>(start));
    return start;
}

//! `format ENCODING VERSION` (the keyword already read).
inline std::optional<GeoError> parse_format_line(io_detail::Tokens& tokens, std::int64_t at, PlyHeader& header) {
    std::string_view name, version;
    if (!tokens.next(name) || !tokens.next(version))
        return error_at_line(ErrorCode::ParseError, at, "format line needs an encoding and a version");
    if (name == "ascii")
        header.encoding = PlyEncodingIn::Ascii;
    else if (name == "binary_little_endian")
        header.encoding = PlyEncodingIn::BinaryLittleEndian;
    else if (name == "binary_big_endian")
        header.encoding = PlyEncodingIn::BinaryBigEndian;
    else
        return error_at_line(ErrorCode::ParseError, at, "unknown PLY format " + quote(name));
    if (!version.starts_with("1"))
        return error_at_line(ErrorCode::Unsupported, at, "PLY version " + quote(version) + " is not supported");
    return std::nullopt;
}

//! `element NAME COUNT` (the keyword already read).
inline std::optional<GeoError> parse_element_line(io_detail::Tokens& tokens, std::int64_t at, PlyHeader& header) {
    PlyElement element;
    std::string_view count;
    std::int64_t n = 0;
    if (!tokens.next(element.name) || !tokens.next(count))
        return error_at_line(ErrorCode::ParseError, at, "element line needs a name and a count");
    if (io_detail::parse_int(count, n) != NumberStatus::Ok || n < 0)
        return error_at_line(ErrorCode::ParseError, at,
                             "element count " + quote(count) + " is not a non-negative integer");
    element.count = static_cast<std::uint64_t>(n);
    element.line = at;
    for (const auto& other : header.elements)
        if (other.name == element.name)
            return error_at_line(ErrorCode::ParseError, at, "element " + quote(element.name) + " declared twice");
    header.elements.push_back(element);
    return std::nullopt;
}

//! `property TYPE NAME` or `property list COUNT_TYPE ITEM_TYPE NAME` (the keyword already read), added to the last
//! element.
inline std::optional<GeoError> parse_property_line(io_detail::Tokens& tokens, std::int64_t at, PlyHeader& header) {
    if (header.elements.empty()) return error_at_line(ErrorCode::ParseError, at, "property before any element");
    PlyProperty property;
    std::string_view type;
    if (!tokens.next(type)) return error_at_line(ErrorCode::ParseError, at, "property line has no type");
    if (type == "list") {
        std::string_view count_type, item_type;
        if (!tokens.next(count_type) || !tokens.next(item_type) || !tokens.next(property.name))
            return error_at_line(ErrorCode::ParseError, at,
                                 "list property needs a count type, an item type and a name");
        auto ct = parse_type(count_type);
        auto it = parse_type(item_type);
        if (!ct) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(count_type));
        if (!it) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(item_type));
        if (!is_integer(*ct))
            return error_at_line(ErrorCode::ParseError, at,
                                 "list count type " + quote(count_type) + " is not an integer type");
        property.is_list = true;
        property.count_type = *ct;
        property.type = *it;
    } else {
        auto t = parse_type(type);
        if (!t) return error_at_line(ErrorCode::ParseError, at, "unknown property type " + quote(type));
        if (!tokens.next(property.name)) return error_at_line(ErrorCode::ParseError, at, "property has no name");
        property.type = *t;
    }
    header.elements.back().properties.push_back(property);
    return std::nullopt;
}

//! Checks each element against the bytes that follow the header and against the limits, before anything is
//! reserved: a header cannot promise more items than the body can hold.
inline std::optional<GeoError> check_element_sizes(const PlyHeader& header, std::string_view bytes,
                                                   const ReadOptions& options) {
    const std::uint64_t remaining = bytes.size() - header.body_offset;
    std::uint64_t needed = 0;
    for (const PlyElement& e : header.elements) {
        // ascii: every value is at least one character and a separator
        const std::uint64_t item =
            header.encoding == PlyEncodingIn::Ascii ? 2 * e.properties.size() : e.min_binary_size();
        if (e.properties.empty()) {
            // Nothing to read per item, yet the readers would still loop `count` times (a header of 19 bytes could
            // ask for 10^15 iterations): refuse it rather than guess what such an element means.
            if (e.count == 0) continue;
            return error_at_line(
                ErrorCode::ParseError, e.line,
                "element " + quote(e.name) + " declares " + std::to_string(e.count) + " items but no properties");
        }
        const std::uint64_t left = remaining + 1 > needed ? remaining + 1 - needed : 0;  // +1: no final newline
        if (e.count > left / item) {
            GeoError error =
                error_at_line(ErrorCode::ParseError, e.line,
                              "header declares " + std::to_string(e.count) + " " + quote(e.name) +
                                  " elements (at least " + std::to_string(item) + " bytes each) but only " +
                                  std::to_string(remaining) + " bytes follow the header");
            error.offset = static_cast<std::int64_t>(header.body_offset);
            return error;
        }
        needed += e.count * item;
    }
    for (const PlyElement& e : header.elements) {
        if (e.name == "vertex" && e.count > options.max_vertices)
            return error_at_line(ErrorCode::BudgetExceeded, e.line,
                                 "header declares " + std::to_string(e.count) + " vertices, more than max_vertices (" +
                                     std::to_string(options.max_vertices) + ")");
        if (e.name == "face" && e.count > options.max_faces)
            return error_at_line(ErrorCode::BudgetExceeded, e.line,
                                 "header declares " + std::to_string(e.count) + " faces, more than max_faces (" +
                                     std::to_string(options.max_faces) + ")");
    }
    return std::nullopt;
}

//! `encoding` is how the input was written: the header of a UTF-16 file read, its body must be ascii too (a binary
//! body was converted along with the header, so its bytes are lost).
inline Result<PlyHeader> parse_header(std::string_view bytes, const ReadOptions& options,
                                      io_detail::TextEncoding encoding = io_detail::TextEncoding::Utf8) {
    auto start = header_start(bytes);
    if (!start.ok()) return start.error();

    io_detail::LineReader lines(bytes, *start);
    std::string_view line;
    if (!lines.next(line) || line != "ply")
        return error_at_line(ErrorCode::ParseError, 1, "not a PLY file (the first line must be 'ply')");

    PlyHeader header;
    bool have_format = false;
    std::int64_t format_line = 0;
    while (true) {
        if (!lines.next(line))
            return error_at_line(ErrorCode::ParseError, lines.line_number(), "header has no end_header line");
        const std::int64_t at = lines.line_number();
        if (line.find('\0') != std::string_view::npos)
            return error_at_line(ErrorCode::ParseError, at, "NUL byte in the header");
        io_detail::Tokens tokens(line);
        std::string_view keyword;
        if (!tokens.next(keyword)) continue;
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") break;
        std::optional<GeoError> error;
        if (keyword == "format") {
            error = parse_format_line(tokens, at, header);
            have_format = true;
            format_line = at;
        } else if (keyword == "element") {
            error = parse_element_line(tokens, at, header);
        } else if (keyword == "property") {
            error = parse_property_line(tokens, at, header);
        }
        // Any other first word is a stray line some exporters write ("Created by Blender 2.49"): not ours to judge.
        if (error) return std::move(*error);
    }
    if (!have_format) return error_at_line(ErrorCode::ParseError, lines.line_number(), "header has no format line");
    if (encoding == io_detail::TextEncoding::Utf16 && header.encoding != PlyEncodingIn::Ascii)
        return error_at_line(ErrorCode::ParseError, format_line,
                             "binary PLY with a UTF-16 header: a binary PLY's header is ASCII (save it as UTF-8 or "
                             "ASCII), only an ascii PLY can be UTF-16 as a whole");
    header.body_offset = lines.position();
    header.body_line = lines.line_number() + 1;
    if (auto error = check_element_sizes(header, bytes, options)) return std::move(*error);
    return header;
}

}  // namespace surfaced::io_detail::ply
