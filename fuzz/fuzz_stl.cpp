// libFuzzer target: read_stl on arbitrary bytes (fuzz/README.md).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    surfaced::fuzz::check_mesh_result(surfaced::read_stl(bytes));
    return 0;
}
