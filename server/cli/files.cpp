#include "server/cli/files.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "server/cli/args.h"

namespace surfaced::cli {

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool read_file(const std::string& path, std::string& out, std::string& error) {
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

MeshFormat mesh_input_format(const std::string& input) {
    const auto format = format_from_extension(input);
    if (!format)
        throw UsageError{"cannot tell the format of " + input +
                         " from its extension (use .obj .off .ply .stl .glb .gltf)"};
    return *format;
}

api::OutputFormat output_format(const std::string& output, std::initializer_list<api::OutputFormat> allowed,
                                std::string_view listed) {
    const std::string ext = lower_extension(output);
    for (const api::OutputFormat format : allowed)
        if (ext == "." + std::string(api::enum_name(api::kOutputFormatNames, format))) return format;
    throw UsageError{"cannot tell the output format of " + output + " from its extension (use " + std::string(listed) +
                     ")"};
}
api::OutputFormat mesh_output_format(const std::string& output) {
    using enum api::OutputFormat;
    return output_format(output, {Obj, Ply, Glb, Gltf, Json}, ".obj .ply .glb .gltf .json");
}

bool is_gltf(api::OutputFormat format) { return format == api::OutputFormat::Glb || format == api::OutputFormat::Gltf; }

}  // namespace surfaced::cli
