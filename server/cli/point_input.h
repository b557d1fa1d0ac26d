#pragma once
// What `surfaced pointcloud` and `surfaced reconstruct` share about their input: the --input-format option and the
// point format it, or IN's extension, names.
#include <optional>

#include "geometry/io/pointcloud_io.h"
#include "server/cli/args.h"

namespace surfaced::cli {

//! --input-format NAME: ply obj xyz glb gltf.
Option point_input_format_option();

//! IN's point format from --input-format, else from its extension; empty for standard input without
//! --input-format (the bytes decide). Throws UsageError when a file's extension names no point format.
std::optional<PointFormat> point_input_format(const Parsed& parsed);

}  // namespace surfaced::cli
