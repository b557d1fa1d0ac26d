#include "server/cli/files.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "api/operations/request_forms.h"

namespace surfaced::cli {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool read_file(const std::string& path, std::string& out, std::string& error) {
    if (path == "-") {
        std::ostringstream buffer;
        buffer << std::cin.rdbuf();
        if (std::cin.bad()) {
            error = "cannot read standard input";
            return false;
        }
        out = std::move(buffer).str();
        return true;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        error = "cannot open " + path + ": " + std::strerror(errno);
        return false;
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) {
        error = "cannot read " + path;
        return false;
    }
    out = std::move(buffer).str();
    return true;
}

bool write_file(const std::string& path, std::string_view bytes, std::string& error) {
    if (path == "-") {
        std::cout.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        std::cout.flush();
        if (!std::cout) {
            error = "cannot write standard output";
            return false;
        }
        return true;
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) {
        error = "cannot create " + path + ": " + std::strerror(errno);
        return false;
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
        error = "cannot write " + path;
        return false;
    }
    return true;
}

std::optional<std::string> read_input(const std::string& path) {
    std::string bytes, error;
    if (read_file(path, bytes, error)) return bytes;
    std::cerr << "surfaced: " << error << "\n";
    return std::nullopt;
}

std::optional<MeshFormat> mesh_input_format(const Parsed& parsed) {
    if (parsed.has("--input-format")) return format_from_extension("." + parsed.value("--input-format"));
    if (parsed.from_stdin()) return std::nullopt;
    const auto format = format_from_extension(parsed.input);
    if (!format)
        throw UsageError{"cannot tell the format of " + parsed.input +
                         " from its extension (use .obj .off .ply .stl .glb .gltf, or --input-format)"};
    return *format;
}

MeshFormat sniff_mesh_format(std::string_view bytes) {
    if (const auto format = api::operations::mesh_format_for("application/octet-stream", bytes)) return *format;
    throw UsageError{
        "cannot tell the mesh format of standard input from its bytes (give --input-format: obj, off, "
        "ply, stl, glb, gltf)"};
}

api::OutputFormat output_format(const Parsed& parsed, const api::options::OperationOptions& operation) {
    std::vector<std::string_view> names;
    if (const auto* format = api::options::find_option(operation, "format"))
        for (const std::string_view name : format->values)
            if (api::enum_from_name(api::kOutputFormatNames, name)) names.push_back(name);
    std::string listed, extensions;  // "obj ply", ".obj .ply"
    for (const std::string_view name : names) {
        listed += (listed.empty() ? "" : " ") + std::string(name);
        extensions += (extensions.empty() ? "." : " .") + std::string(name);
    }
    std::string name;
    if (parsed.has("--format")) {
        name = parsed.value("--format");
        if (std::find(names.begin(), names.end(), name) == names.end())
            throw unknown_value(parsed.command + " --format", name, names);
    } else if (parsed.to_stdout()) {
        throw UsageError{parsed.command + ": -o - (standard output) needs --format (" + listed + ")"};
    } else {
        name = lower_extension(parsed.output);
        if (name.starts_with(".")) name.erase(0, 1);
        if (std::find(names.begin(), names.end(), name) == names.end())
            throw UsageError{parsed.command + ": cannot tell the output format of " + parsed.output +
                             " from its extension (use " + extensions + ", or --format)"};
    }
    return *api::enum_from_name(api::kOutputFormatNames, name);
}

bool is_gltf(api::OutputFormat format) { return format == api::OutputFormat::Glb || format == api::OutputFormat::Gltf; }

}  // namespace surfaced::cli
