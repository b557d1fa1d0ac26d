// Files and formats: reading and writing whole files, and the formats their extensions name.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "api/dto.h"
#include "api/options/option_spec.h"
#include "geometry/io/mesh_io.h"
#include "server/cli/args.h"

namespace surfaced::cli {

std::string lower_extension(const std::string& path);
//! The whole file at `path` ("-": standard input) into `out`; false with `error` set when it cannot be read.
bool read_file(const std::string& path, std::string& out, std::string& error);
//! `bytes` as the file at `path` ("-": standard output); false with `error` set when it cannot be written.
bool write_file(const std::string& path, std::string_view bytes, std::string& error);

//! The bytes of IN ("-": standard input); nullopt (and why, printed) when it cannot be read.
std::optional<std::string> read_input(const std::string& path);

//! The mesh format of IN: --input-format if given, else IN's extension; nullopt for standard input without
//! --input-format (the bytes tell: sniff_mesh_format()).
std::optional<MeshFormat> mesh_input_format(const Parsed& parsed);
//! The format of a mesh read from standard input, as the service sniffs an application/octet-stream upload.
MeshFormat sniff_mesh_format(std::string_view bytes);

//! The output format: --format if given, else OUT's extension ("-o -" needs --format), one of the values of the
//! `format` row of `operation`'s table; the extension ".EXT" names the format whose name (api::kOutputFormatNames)
//! is EXT.
api::OutputFormat output_format(const Parsed& parsed, const api::options::OperationOptions& operation);

bool is_gltf(api::OutputFormat format);

}  // namespace surfaced::cli
