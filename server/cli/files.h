// Files and formats: reading and writing whole files, and the formats their extensions name.
#pragma once

#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include "api/dto.h"
#include "geometry/io/mesh_io.h"

namespace surfaced::cli {

std::string lower_extension(const std::string& path);
bool read_file(const std::string& path, std::string& out, std::string& error);
bool write_file(const std::string& path, std::string_view bytes, std::string& error);

//! The bytes of IN; nullopt (and why, printed) when it cannot be read.
std::optional<std::string> read_input(const std::string& path);

//! The mesh format of IN, from its extension.
MeshFormat mesh_input_format(const std::string& input);

//! The output format of OUT, from its extension; `allowed` as the error lists them (".obj .ply .glb").
api::OutputFormat output_format(const std::string& output, std::initializer_list<api::OutputFormat> allowed,
                                std::string_view listed);
api::OutputFormat mesh_output_format(const std::string& output);

bool is_gltf(api::OutputFormat format);

}  // namespace surfaced::cli
