// libFuzzer target: the point-cloud readers (geometry/io/pointcloud_io.h: PLY, OBJ, XYZ), the first byte picking
// the format. An accepted cloud must pass validate(); an error must carry a message.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/fuzz_check.h"
#include "geometry/io/pointcloud_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace surfaced;
    if (size == 0) return 0;
    const PointFormat formats[] = {PointFormat::Ply, PointFormat::Obj, PointFormat::Xyz};
    const PointFormat format = formats[data[0] % 3];
    const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    const auto result = read_points(bytes, format);
    if (!result.ok()) {
        if (result.error().message.empty()) fuzz::fail("read_points error", "empty message");
        if (result.error().code == ErrorCode::Internal)
            fuzz::fail("read_points error is Internal", result.error().message);
        return 0;
    }
    const Status valid = validate(*result);
    if (!valid.ok()) fuzz::fail("read_points returned a cloud that validate() rejects", valid.error().message);
    return 0;
}
