#include "server/cli/point_input.h"

#include <string>

namespace surfaced::cli {

Option point_input_format_option() {
    return Option{.name = "--input-format",
                  .check = one_of_names({"ply", "obj", "xyz", "glb", "gltf"}),
                  .synopsis = "--input-format NAME",
                  .description = "IN's format instead of its extension: ply obj xyz glb gltf (IN -: from the bytes)"};
}

std::optional<PointFormat> point_input_format(const Parsed& parsed) {
    if (parsed.has("--input-format")) return point_format_from_extension("." + parsed.value("--input-format"));
    if (parsed.from_stdin()) return std::nullopt;
    std::optional<PointFormat> format = point_format_from_extension(parsed.input);
    if (!format)
        throw UsageError{"cannot tell the point format of " + parsed.input +
                         " from its extension (use .ply .obj .xyz .glb .gltf, or --input-format)"};
    return format;
}

}  // namespace surfaced::cli
