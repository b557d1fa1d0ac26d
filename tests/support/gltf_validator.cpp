// Runs tests/tools/validate_gltf.mjs (the Khronos validator from tests/node_modules) through the shell. The script
// prints "errors warnings infos hints" on its first line, so no JSON parser is needed here.
#include "tests/support/gltf_validator.h"

#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>

namespace surfaced::testing {

namespace {

//! Single-quoted for /bin/sh (a quote inside becomes '\'').
std::string shell_quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) {
        if (c == '\'')
            out += "'\\''";
        else
            out += c;
    }
    return out + "'";
}

//! A unique file that deletes itself, so parallel test processes (ctest -j) never share a path.
struct TempFile {
    std::string path;
    TempFile() {
        std::string pattern = (std::filesystem::temp_directory_path() / "surfaced-gltf-XXXXXX").string();
        const int fd = mkstemp(pattern.data());
        if (fd >= 0) {
            close(fd);
            path = pattern;
        }
    }
    ~TempFile() {
        if (!path.empty()) std::remove(path.c_str());
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;
};

}  // namespace

GltfValidation run_gltf_validator(std::string_view glb_bytes) {
    GltfValidation result;
    TempFile file;
    if (file.path.empty()) {
        result.report = "could not create a temporary file";
        return result;
    }
    {
        std::ofstream out(file.path, std::ios::binary);
        out.write(glb_bytes.data(), static_cast<std::streamsize>(glb_bytes.size()));
        if (!out) {
            result.report = "could not write " + file.path;
            return result;
        }
    }
    const std::string script = std::string(SURFACED_SOURCE_DIR) + "/tests/tools/validate_gltf.mjs";
    const std::string command = "node " + shell_quote(script) + " " + shell_quote(file.path) + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    if (pipe == nullptr) {
        result.report = "could not run: " + command;
        return result;
    }
    std::string output;
    std::array<char, 4096> chunk;
    std::size_t n;
    while ((n = std::fread(chunk.data(), 1, chunk.size(), pipe)) > 0) output.append(chunk.data(), n);
    const int status = pclose(pipe);
    result.report = output;
    if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        result.report = "validator did not run (" + command +
                        "; is node installed and `npm install --prefix tests` done?):\n" + output;
        return result;
    }
    int hints = 0;
    if (std::sscanf(output.c_str(), "%d %d %d %d", &result.errors, &result.warnings, &result.infos, &hints) != 4) {
        result.report = "unexpected validator output:\n" + output;
        return result;
    }
    result.ran = true;
    return result;
}

}  // namespace surfaced::testing
