// The arrays of the repair steps. At a million faces they are tens of MB each and read and written at random, so they
// take whole 2 MiB pages with transparent huge pages requested (BlockAllocator, geometry/core/block_pool.h): with
// 4 KiB pages nearly every random access would also miss the TLB.
#pragma once

#include "geometry/core/block_pool.h"

namespace surfaced::repair_detail {

template <class T>
using Array = BlockVector<T>;

}  // namespace surfaced::repair_detail
