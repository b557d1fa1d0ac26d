#include "server/static_files.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <system_error>

namespace surfaced::server {
namespace {

namespace fs = std::filesystem;

const char* mime_type(const fs::path& file) {
    std::string ext = file.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".html" || ext == ".htm") return "text/html; charset=utf-8";
    if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
    if (ext == ".css") return "text/css; charset=utf-8";
    if (ext == ".json" || ext == ".map") return "application/json";
    if (ext == ".wasm") return "application/wasm";
    if (ext == ".glb") return "model/gltf-binary";
    if (ext == ".gltf") return "model/gltf+json";
    if (ext == ".svg") return "image/svg+xml";
    if (ext == ".png") return "image/png";
    if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
    if (ext == ".ico") return "image/x-icon";
    if (ext == ".txt") return "text/plain; charset=utf-8";
    return "application/octet-stream";
}

//! The file under `root` (canonical) that the decoded URL path names, or nothing: segments "..", backslashes and
//! NULs are refused outright, and the canonical target (symlinks resolved) must still lie under the root.
std::optional<fs::path> resolve_static(const fs::path& root, std::string_view url_path) {
    if (url_path.empty() || url_path.front() != '/') return std::nullopt;
    fs::path relative;
    std::size_t begin = 1;
    while (begin <= url_path.size()) {
        const std::size_t end = std::min(url_path.find('/', begin), url_path.size());
        const std::string_view segment = url_path.substr(begin, end - begin);
        if (segment == ".." || segment.find('\\') != std::string_view::npos ||
            segment.find('\0') != std::string_view::npos)
            return std::nullopt;
        if (!segment.empty() && segment != ".") relative /= std::string(segment);
        begin = end + 1;
    }
    if (url_path.back() == '/') relative /= "index.html";
    std::error_code ec;
    const fs::path target = fs::canonical(root / relative, ec);
    if (ec || !fs::is_regular_file(target, ec)) return std::nullopt;
    const auto [root_end, target_it] = std::mismatch(root.begin(), root.end(), target.begin(), target.end());
    if (root_end != root.end()) return std::nullopt;  // resolved outside the web root (a symlink out of it)
    (void)target_it;
    return target;
}

}  // namespace

StaticFiles::StaticFiles(const std::string& web_root) {
    if (web_root.empty()) return;
    std::error_code ec;
    const fs::path root = fs::canonical(web_root, ec);
    if (!ec && fs::is_directory(root, ec)) root_ = root;
}

bool StaticFiles::has(std::string_view url_path) const { return resolve(url_path).has_value(); }

std::optional<StaticFiles::File> StaticFiles::load(std::string_view url_path) const {
    const auto file = resolve(url_path);
    if (!file) return std::nullopt;
    std::error_code ec;
    const auto size = fs::file_size(*file, ec);
    std::ifstream in(*file, std::ios::binary);
    if (ec || !in || size > (std::uintmax_t{256} << 20)) return std::nullopt;
    File out{std::string(static_cast<std::size_t>(size), '\0'), mime_type(*file)};
    in.read(out.body.data(), static_cast<std::streamsize>(size));
    return out;
}

std::optional<std::filesystem::path> StaticFiles::resolve(std::string_view url_path) const {
    if (!root_) return std::nullopt;
    return resolve_static(*root_, url_path);
}

}  // namespace surfaced::server
