// Choosing a mesh format from a file name, a media type or the bytes themselves.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "geometry/io/mesh_io.h"
#include "geometry/io/text_encoding.h"
#include "geometry/io/text_scanner.h"

namespace surfaced {
namespace {

std::string lower(std::string_view s) {
    std::string out(s);
    for (char& c : out)
        if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    return out;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (io_detail::is_space(s.front()) || s.front() == '\n')) s.remove_prefix(1);
    while (!s.empty() && (io_detail::is_space(s.back()) || s.back() == '\n')) s.remove_suffix(1);
    return s;
}

bool binary_stl_size_matches(std::string_view bytes) {
    if (bytes.size() < 84) return false;
    std::uint64_t count = 0;
    for (int i = 83; i >= 80; --i)
        count = (count << 8) | static_cast<unsigned char>(bytes[static_cast<std::size_t>(i)]);
    return 84 + count * 50 == bytes.size();
}

//! First whitespace-delimited word of a line.
std::string_view first_word(std::string_view line) {
    io_detail::Tokens tokens(line);
    std::string_view word;
    return tokens.next(word) ? word : std::string_view{};
}

//! A JSON object (after whitespace) that mentions "asset", which every glTF document has.
bool looks_like_gltf_json(std::string_view text) {
    while (!text.empty() && (io_detail::is_space(text.front()) || text.front() == '\n')) text.remove_prefix(1);
    return !text.empty() && text.front() == '{' && text.find("\"asset\"") != std::string_view::npos;
}

}  // namespace

std::optional<MeshFormat> format_from_extension(std::string_view path) {
    const std::size_t slash = path.find_last_of("/\\");
    if (slash != std::string_view::npos) path.remove_prefix(slash + 1);
    const std::size_t dot = path.rfind('.');
    if (dot == std::string_view::npos || dot + 1 == path.size()) return std::nullopt;
    const std::string ext = lower(path.substr(dot + 1));
    if (ext == "obj") return MeshFormat::Obj;
    if (ext == "off") return MeshFormat::Off;
    if (ext == "ply") return MeshFormat::Ply;
    if (ext == "stl") return MeshFormat::Stl;
    if (ext == "glb") return MeshFormat::Glb;
    if (ext == "gltf") return MeshFormat::Gltf;
    return std::nullopt;
}

std::optional<MeshFormat> format_from_media_type(std::string_view media_type) {
    // Parameters ("; charset=utf-8") do not change the format.
    const std::size_t semicolon = media_type.find(';');
    const std::string type = lower(trim(media_type.substr(0, semicolon)));
    if (type == "model/obj" || type == "text/x-obj" || type == "application/x-obj" || type == "application/x-tgif")
        return MeshFormat::Obj;
    if (type == "model/off" || type == "model/x-off" || type == "application/off" || type == "application/x-off")
        return MeshFormat::Off;
    if (type == "application/ply" || type == "model/ply" || type == "model/x-ply" || type == "application/x-ply" ||
        type == "text/x-ply")
        return MeshFormat::Ply;
    if (type == "model/stl" || type == "model/x.stl-ascii" || type == "model/x.stl-binary" ||
        type == "application/sla" || type == "application/vnd.ms-pki.stl" || type == "application/x-stl" ||
        type == "model/x-stl")
        return MeshFormat::Stl;
    if (type == "model/gltf-binary") return MeshFormat::Glb;
    if (type == "model/gltf+json") return MeshFormat::Gltf;
    return std::nullopt;
}

std::optional<MeshFormat> sniff_format(std::string_view bytes) {
    if (bytes.substr(0, 4) == "glTF") return MeshFormat::Glb;
    std::string_view text = bytes;
    if (text.substr(0, 3) == "\xef\xbb\xbf") text.remove_prefix(3);
    if (text.substr(0, 4) == "ply\n" || text.substr(0, 5) == "ply\r\n") return MeshFormat::Ply;
    // Before looking at words: binary STL headers often start with "solid" too.
    if (binary_stl_size_matches(bytes)) return MeshFormat::Stl;
    if (looks_like_gltf_json(text)) return MeshFormat::Gltf;
    // UTF-16 text (the readers convert it): sniff its first characters as ASCII.
    if (bool big_endian = false; io_detail::utf16_bom(bytes, big_endian)) {
        const std::size_t units = std::min<std::size_t>(bytes.size() - 2, 8192) & ~std::size_t{1};
        const std::string head = io_detail::utf16_to_ascii(bytes.substr(2, units), big_endian);
        const auto format = sniff_format(head);
        return format == MeshFormat::Gltf ? std::nullopt : format;  // JSON is UTF-8: read_gltf would refuse it
    }

    // Text formats: look at the first few meaningful lines only.
    io_detail::LineReader lines(text, 0);
    std::string_view line;
    int seen = 0;
    while (lines.next(line) && seen < 64) {
        const std::string_view word = first_word(line);
        if (word.empty()) continue;
        if (word[0] == '#') continue;
        ++seen;
        if (seen == 1) {
            if (word == "solid") return MeshFormat::Stl;
            const std::size_t n = word.size();
            if (n >= 3 && word.substr(n - 3) == "OFF" && n <= 7) return MeshFormat::Off;
        }
        if (word == "v" || word == "f" || word == "vt" || word == "vn" || word == "mtllib" || word == "usemtl" ||
            word == "o" || word == "g")
            return MeshFormat::Obj;
        if (word.find('\0') != std::string_view::npos) return std::nullopt;
    }
    return std::nullopt;
}

}  // namespace surfaced
