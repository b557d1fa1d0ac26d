// StaticFiles: the web client's files served at "/" from a web root, confined to it (no "..", no symlinks out of
// it), with a Content-Type from the file extension.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace surfaced::server {

class StaticFiles {
public:
    //! Serves the directory `web_root`; serves nothing when it is empty or not a directory.
    explicit StaticFiles(const std::string& web_root);

    bool enabled() const { return root_.has_value(); }

    //! Whether the decoded URL path names a file under the root.
    bool has(std::string_view url_path) const;

    struct File {
        std::string body;
        const char* content_type;
    };
    //! The file the decoded URL path names ("/dir/" means "/dir/index.html"), or nothing: no such file under the
    //! root, unreadable, or larger than 256 MiB.
    std::optional<File> load(std::string_view url_path) const;

private:
    std::optional<std::filesystem::path> resolve(std::string_view url_path) const;

    std::optional<std::filesystem::path> root_;  // canonical
};

}  // namespace surfaced::server
