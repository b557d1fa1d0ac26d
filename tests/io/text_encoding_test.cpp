// Text encodings every text reader shares (geometry/io/text_encoding.h): UTF-16 with a byte order mark, either
// byte order, reads to the same mesh as its UTF-8 original and reports errors at the original's line numbers.
#include <gtest/gtest.h>

#include <string>
#include <string_view>

#include "geometry/io/mesh_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::expect_same_mesh;
using format_test::fails_with;

//! UTF-8 text as UTF-16 with a byte order mark. Handles what the tests use: ASCII, two-byte UTF-8 characters and one
//! four-byte character (written as a surrogate pair).
std::string to_utf16(std::string_view utf8, bool big_endian) {
    std::string out = big_endian ? "\xfe\xff" : "\xff\xfe";
    auto unit = [&](unsigned u) {
        const char hi = static_cast<char>(u >> 8), lo = static_cast<char>(u & 0xff);
        out += big_endian ? std::string{hi, lo} : std::string{lo, hi};
    };
    for (std::size_t i = 0; i < utf8.size(); ++i) {
        const auto c = static_cast<unsigned char>(utf8[i]);
        if (c < 0x80) {
            unit(c);
        } else if ((c & 0xe0) == 0xc0) {
            unit(((c & 0x1fu) << 6) | (static_cast<unsigned char>(utf8[++i]) & 0x3fu));
        } else {  // four bytes: U+10000 and above
            unsigned cp = c & 0x07u;
            for (int k = 0; k < 3; ++k) cp = (cp << 6) | (static_cast<unsigned char>(utf8[++i]) & 0x3fu);
            cp -= 0x10000;
            unit(0xd800 + (cp >> 10));
            unit(0xdc00 + (cp & 0x3ff));
        }
    }
    return out;
}

struct Sample {
    const char* name;
    Result<PolygonMesh> (*read)(std::string_view, const ReadOptions&);
    std::string text;
};

const Sample kSamples[] = {
    {"obj", read_obj,
     "# W\xc3\xbcrfel \xf0\x9f\x8e\xb2\r\nv 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
     "g caf\xc3\xa9\nf 1/1 2/2 3/3 4/4\n"},
    {"off", read_off, "OFF # \xc3\xa9\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0.5\n4 0 1 2 3\n"},
    {"ply", read_ply,
     "ply\nformat ascii 1.0\ncomment fa\xc3\xa7"
     "ade\nelement vertex 3\nproperty float x\nproperty float y\n"
     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
     "3 0 1 2\n"},
    {"stl", read_stl,
     "solid t\xc3\xa9st\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
     "endfacet\nendsolid t\xc3\xa9st\n"},
};

TEST(TextEncoding, Utf16ReadsLikeUtf8InEveryTextFormat) {
    for (const Sample& s : kSamples) {
        SCOPED_TRACE(s.name);
        auto utf8 = s.read(s.text, {});
        ASSERT_TRUE(utf8.ok()) << utf8.error().message;
        for (bool big_endian : {false, true}) {
            auto utf16 = s.read(to_utf16(s.text, big_endian), {});
            ASSERT_TRUE(utf16.ok()) << (big_endian ? "BE: " : "LE: ") << utf16.error().message;
            expect_same_mesh(*utf8, *utf16);
        }
    }
    for (const Sample& s : kSamples) EXPECT_EQ(sniff_format(to_utf16(s.text, true)), sniff_format(s.text)) << s.name;
    // read_mesh (the API's path) goes through the same readers.
    auto via_dispatch = read_mesh(to_utf16(kSamples[0].text, true), MeshFormat::Obj);
    ASSERT_TRUE(via_dispatch.ok()) << via_dispatch.error().message;
    EXPECT_EQ(via_dispatch->face_count(), 1u);
}

TEST(TextEncoding, Utf16ErrorsNameTheLinesOfTheText) {
    const std::string obj = "# \xc3\xa9\nv 0 0 0\nv 1 x 0\n";
    EXPECT_TRUE(fails_with(read_obj(to_utf16(obj, false)), ErrorCode::ParseError, "line 3:"));
    auto off = read_off(to_utf16("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", true));
    ASSERT_TRUE(fails_with(off, ErrorCode::IndexOutOfRange, "line 6:"));
    EXPECT_EQ(off.error().line, 6);
    // A non-ASCII character inside a number is an error, as in UTF-8.
    EXPECT_TRUE(fails_with(read_obj(to_utf16("v 0 0 0\nv 1 0 0\nv 0 1\xc3\xa9 0\nf 1 2 3\n", false)),
                           ErrorCode::ParseError, "line 3:"));
}

TEST(TextEncoding, WhatStaysRefused) {
    // UTF-16 without a byte order mark: its NUL bytes are refused as before.
    std::string no_bom = to_utf16("v 0 0 0\n", false).substr(2);
    EXPECT_TRUE(fails_with(read_obj(no_bom), ErrorCode::ParseError, "line 1: UTF-16 is not supported"));
    // Cut in the middle of a character.
    const std::string odd = to_utf16("OFF\n", true) + std::string(1, '\0');
    EXPECT_TRUE(fails_with(read_off(odd), ErrorCode::ParseError, "ends in the middle of a character"));
    // A binary PLY's header is ASCII; a UTF-16 one cannot be separated from its body.
    const std::string binary =
        to_utf16("ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nend_header\n", false);
    EXPECT_TRUE(fails_with(read_ply(binary), ErrorCode::ParseError, "line 2: binary PLY with a UTF-16 header"));
    // A U+0000 character is a NUL byte in the text, as in UTF-8.
    EXPECT_TRUE(fails_with(read_obj(to_utf16(std::string("v 0 0 0\n\0", 9), false)), ErrorCode::ParseError,
                           "line 2: NUL byte"));
}

TEST(TextEncoding, BinaryStlWhoseHeaderStartsLikeAByteOrderMark) {
    // The size rule decides first: an 80-byte header may start with any bytes.
    std::string stl = "\xff\xfe" + std::string(78, ' ');
    stl += std::string("\x01\0\0\0", 4);
    const float corners[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0};
    stl.append(reinterpret_cast<const char*>(corners), sizeof corners);  // little-endian host, as in stl_test
    stl += std::string(2, '\0');
    auto mesh = read_stl(stl);
    ASSERT_TRUE(mesh.ok()) << mesh.error().message;
    EXPECT_EQ(mesh->face_count(), 1u);
}

}  // namespace
}  // namespace surfaced
