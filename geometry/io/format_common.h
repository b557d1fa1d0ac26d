// Internal to geo_formats: small pieces shared by the readers and writers that are not about tokenizing.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "geometry/core/types.h"
#include "geometry/io/mesh_io.h"
#include "geometry/io/number_text.h"

namespace surfaced::io_detail {

//! Records `line` as the next face's line (ReadReport::face_lines), when there is a report to fill.
inline void record_face_line(ReadReport* report, std::int64_t line) {
    if (report && line > 0 && line <= std::int64_t{std::numeric_limits<std::uint32_t>::max()})
        report->face_lines.push_back(static_cast<std::uint32_t>(line));
}

//! A vertex used twice in one face, if any. Small faces (the usual case) are checked pairwise without touching
//! `scratch`; large ones are sorted in it.
inline std::optional<Index> repeated_vertex(std::span<const Index> face, std::vector<Index>& scratch) {
    const std::size_t n = face.size();
    if (n <= 8) {
        for (std::size_t i = 1; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j)
                if (face[i] == face[j]) return face[i];
        return std::nullopt;
    }
    scratch.assign(face.begin(), face.end());
    std::sort(scratch.begin(), scratch.end());
    auto dup = std::adjacent_find(scratch.begin(), scratch.end());
    if (dup != scratch.end()) return *dup;
    return std::nullopt;
}

//! Appends a double: number_text.h's shortest round-trip text when precision >= 17 (so 0.1 stays "0.1" and round
//! trips stay exact), otherwise %.{precision}g; -0 prints as "0" either way.
inline void append_double(std::string& out, double value, int precision) {
    if (precision >= 17) return append_number_text(out, value);
    if (value == 0) value = 0;
    char buffer[64];
    const std::to_chars_result r =
        std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, std::max(precision, 1));
    out.append(buffer, r.ptr);
}

inline void append_uint(std::string& out, std::uint64_t value) {
    char buffer[24];
    auto r = std::to_chars(buffer, buffer + sizeof(buffer), value);
    out.append(buffer, r.ptr);
}

//! Largest count a reserve() may be given: the caller's estimate from bytes actually present, capped by the
//! configured limit. Header counts never reach reserve() directly.
inline std::size_t bounded_reserve(std::size_t estimate, std::size_t limit) { return std::min(estimate, limit); }

inline constexpr std::size_t kMaxIndexCount = std::numeric_limits<Index>::max();

}  // namespace surfaced::io_detail
