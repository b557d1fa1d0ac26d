// A stable LSD radix sort of 64-bit words by their upper 32 bits (three passes of 11, 11 and 10 bits), for the repair
// steps that group elements by a 32-bit key with the element's index in the lower half: equal keys come out in the
// order they went in. Several times faster than hashing into a table of millions of slots, whose every probe is a
// cache miss.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace surfaced::repair_detail {

//! Sorts `words` by bits 32..63, stably; `scratch` is resized and clobbered.
inline void radix_sort_by_high_half(std::vector<std::uint64_t>& words, std::vector<std::uint64_t>& scratch) {
    constexpr int kShift[3] = {32, 43, 54};
    constexpr std::uint64_t kMask[3] = {0x7FF, 0x7FF, 0x3FF};
    std::array<std::array<std::size_t, 2048>, 3> count{};
    for (std::uint64_t w : words)
        for (int pass = 0; pass < 3; ++pass) ++count[pass][(w >> kShift[pass]) & kMask[pass]];
    scratch.resize(words.size());
    std::vector<std::uint64_t>* from = &words;
    std::vector<std::uint64_t>* to = &scratch;
    for (int pass = 0; pass < 3; ++pass) {
        std::size_t sum = 0;
        for (std::size_t& c : count[pass]) {
            const std::size_t n = c;
            c = sum;
            sum += n;
        }
        std::uint64_t* out = to->data();
        for (std::uint64_t w : *from) out[count[pass][(w >> kShift[pass]) & kMask[pass]]++] = w;
        std::swap(from, to);
    }
    // three passes leave the result in scratch
    words.swap(scratch);
}

}  // namespace surfaced::repair_detail
