// The malformed-file corpus (tests/data/malformed): every file must fail with the right error code and a message
// that names where (line or byte offset) and what. Also: format detection, and that no file is left untested.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <utility>
#include <string>
#include <vector>

#include "geometry/io/mesh_io.h"
#include "tests/io/format_test_helpers.h"

namespace surfaced {
namespace {

using format_test::fails_with;

struct Case {
    const char* file;
    ErrorCode code;
    const char* needle;  //!< must appear in the message; "line N:" / "offset N:" prefixes are also checked as fields
};

const Case kCases[] = {
    // ---- OBJ
    {"obj_empty.obj", ErrorCode::ParseError, "empty file"},
    {"obj_no_faces.obj", ErrorCode::ParseError, "no faces"},
    {"obj_whitespace_only.obj", ErrorCode::ParseError, "no faces"},
    {"obj_nan.obj", ErrorCode::NonFinite, "line 3: vertex 3 has a non-finite coordinate"},
    {"obj_inf.obj", ErrorCode::NonFinite, "line 2: vertex 2 has a non-finite coordinate"},
    {"obj_overflow.obj", ErrorCode::NonFinite, "line 1: vertex 1 has a non-finite coordinate"},
    {"obj_index_zero.obj", ErrorCode::IndexOutOfRange, "line 4: face index 0 is invalid (OBJ indices start at 1)"},
    {"obj_index_out_of_range.obj", ErrorCode::IndexOutOfRange, "line 12: face index 9 out of range (8 vertices)"},
    {"obj_negative_beyond_start.obj", ErrorCode::IndexOutOfRange, "line 4: face index -4 out of range (3 vertices)"},
    {"obj_two_vertex_face.obj", ErrorCode::DegenerateFace, "line 4: face has 2 vertices (at least 3 needed)"},
    {"obj_empty_face.obj", ErrorCode::DegenerateFace, "line 4: face has 0 vertices"},
    {"obj_repeated_vertex.obj", ErrorCode::DegenerateFace, "line 4: face uses vertex 1 more than once"},
    {"obj_bad_number.obj", ErrorCode::ParseError, "line 2: vertex coordinate is not a number: 'abc'"},
    {"obj_truncated.obj", ErrorCode::ParseError, "line 3: vertex has 2 coordinates (3 needed)"},
    {"obj_truncated_face.obj", ErrorCode::DegenerateFace, "line 4: face has 2 vertices"},
    {"obj_uv_out_of_range.obj", ErrorCode::IndexOutOfRange,
     "line 6: texture coordinate index 3 out of range (2 texture coordinates)"},
    {"obj_mixed_uv_corners.obj", ErrorCode::ParseError,
     "line 5: face mixes corners with and without texture coordinates"},
    {"obj_normal_out_of_range.obj", ErrorCode::IndexOutOfRange, "line 5: normal index 2 out of range (1 normals)"},
    {"obj_index_not_integer.obj", ErrorCode::ParseError, "line 4: face index '3.5' is not an integer"},
    {"obj_huge_index.obj", ErrorCode::IndexOutOfRange, "line 4: face index '99999999999999999999999' out of range"},
    {"obj_crease_out_of_range.obj", ErrorCode::IndexOutOfRange,
     "line 5: crease refers to vertex 7 but there are 3 vertices"},
    {"obj_hole_out_of_range.obj", ErrorCode::IndexOutOfRange, "line 5: hole refers to face 3 but there are 1 faces"},
    {"obj_corner_negative.obj", ErrorCode::IndexOutOfRange, "line 5: corner vertex index -1 out of range"},
    {"obj_tag_too_few_args.obj", ErrorCode::ParseError, "line 5: tag 'crease' declares 2/1/0 arguments but has only 2"},
    {"obj_tag_bad_counts.obj", ErrorCode::ParseError, "line 5: tag 'crease' has malformed argument counts '2/1'"},
    {"obj_tag_absurd_counts.obj", ErrorCode::ParseError,
     "line 5: tag 'vertexedit' declares 4000000000/0/0 arguments but has only 2"},
    {"obj_crease_odd_ints.obj", ErrorCode::ParseError, "line 5: crease tag needs vertex pairs"},
    {"obj_crease_nan.obj", ErrorCode::NonFinite, "line 5: sharpness is not finite"},
    {"obj_boundary_bad.obj", ErrorCode::ParseError, "line 5: interpolateboundary value 7 is not 0, 1 or 2"},
    {"obj_crlf_error.obj", ErrorCode::IndexOutOfRange, "line 4: face index 4 out of range (3 vertices)"},
    {"obj_continuation_error.obj", ErrorCode::IndexOutOfRange, "line 7: face index 0 is invalid"},
    {"obj_utf16le_nobom.obj", ErrorCode::ParseError, "line 1: UTF-16 is not supported (NUL byte at offset 1)"},
    {"obj_utf16le_odd.obj", ErrorCode::ParseError, "offset 64: UTF-16 text (it starts with a byte order mark) ends in"},
    {"obj_binary_garbage.obj", ErrorCode::ParseError, "binary data in a text file"},
    {"obj_high_bytes.obj", ErrorCode::ParseError, "line 1: unexpected '\\x8f\\xe3\\x01\\x7f' (not an OBJ statement)"},

    // ---- OFF
    {"off_empty.off", ErrorCode::ParseError, "empty file"},
    {"off_comments_only.off", ErrorCode::ParseError, "empty file"},
    {"off_bad_header.off", ErrorCode::ParseError, "line 1: expected an OFF header, found 'OFX'"},
    {"off_missing_counts.off", ErrorCode::ParseError, "line 1: unexpected end of file: no vertex count"},
    {"off_negative_count.off", ErrorCode::ParseError, "line 2: vertex count '-3' is not a non-negative integer"},
    {"off_absurd_counts.off", ErrorCode::ParseError,
     "line 2: header declares 4000000000 vertices and 4000000000 faces, but only 6 bytes follow"},
    {"off_truncated_vertices.off", ErrorCode::ParseError, "line 4: unexpected end of file: read 2 of 4 vertices"},
    {"off_truncated_faces.off", ErrorCode::ParseError, "line 6: unexpected end of file: read 1 of 2 faces"},
    {"off_nan.off", ErrorCode::NonFinite, "line 4: vertex 1 has a non-finite coordinate"},
    {"off_index_out_of_range.off", ErrorCode::IndexOutOfRange, "line 6: face index 3 out of range (3 vertices)"},
    {"off_negative_index.off", ErrorCode::IndexOutOfRange, "line 6: face index -1 out of range (3 vertices)"},
    {"off_two_vertex_face.off", ErrorCode::DegenerateFace, "line 6: face has 2 vertices (at least 3 needed)"},
    {"off_repeated_vertex.off", ErrorCode::DegenerateFace, "line 6: face uses vertex 1 more than once"},
    {"off_face_short.off", ErrorCode::ParseError, "line 7: face declares 4 vertices but lists 3"},
    {"off_no_faces.off", ErrorCode::ParseError, "line 2: no faces"},
    {"off_bad_coordinate.off", ErrorCode::ParseError, "line 4: vertex coordinate 'x' is not a number"},
    {"off_garbage.off", ErrorCode::ParseError, "binary data in a text file"},

    // ---- PLY
    {"ply_empty.ply", ErrorCode::ParseError, "empty file"},
    {"ply_no_magic.ply", ErrorCode::ParseError, "line 1: not a PLY file"},
    {"ply_no_end_header.ply", ErrorCode::ParseError, "line 4: header has no end_header line"},
    {"ply_unknown_type.ply", ErrorCode::ParseError, "line 4: unknown property type 'float3'"},
    {"ply_no_format.ply", ErrorCode::ParseError, "line 4: header has no format line"},
    {"ply_bad_format.ply", ErrorCode::ParseError, "line 2: unknown PLY format 'binary_middle_endian'"},
    {"ply_property_before_element.ply", ErrorCode::ParseError, "line 3: property before any element"},
    {"ply_missing_z.ply", ErrorCode::ParseError, "line 3: vertex element has no 'z' property"},
    {"ply_no_faces.ply", ErrorCode::ParseError, "line 9: no faces"},
    // found by fuzz_ply: a property-less element with a huge count made the ascii reader loop 10^15 times
    {"ply_element_without_properties.ply", ErrorCode::ParseError,
     "line 3: element 'junk' declares 666666666666666 items but no properties"},
    {"ply_float_list_count.ply", ErrorCode::ParseError, "line 8: list count type 'float' is not an integer type"},
    {"ply_ascii_truncated.ply", ErrorCode::ParseError, "line 13: unexpected end of file in 'face' element 1 of 2"},
    {"ply_ascii_nan.ply", ErrorCode::NonFinite, "line 11: vertex 1 has a non-finite coordinate"},
    {"ply_ascii_index_out_of_range.ply", ErrorCode::IndexOutOfRange, "line 13: face index 5 out of range (3 vertices)"},
    {"ply_ascii_negative_index.ply", ErrorCode::IndexOutOfRange, "line 13: face index -1 out of range (3 vertices)"},
    {"ply_ascii_two_vertex_face.ply", ErrorCode::DegenerateFace, "line 13: face 0 has 2 vertices (at least 3 needed)"},
    {"ply_ascii_repeated.ply", ErrorCode::DegenerateFace, "line 13: face 0 uses vertex 2 more than once"},
    {"ply_ascii_absurd_count.ply", ErrorCode::ParseError, "line 3: header declares 4000000000 'vertex' elements"},
    {"ply_binary_truncated.ply", ErrorCode::ParseError, "offset 207: unexpected end of file in 'face' element 0 of 1"},
    {"ply_binary_absurd_faces.ply", ErrorCode::ParseError, "line 7: header declares 4000000000 'face' elements"},
    {"ply_binary_nan.ply", ErrorCode::NonFinite, "offset 182: vertex 1 has a non-finite coordinate"},
    {"ply_binary_index_out_of_range.ply", ErrorCode::IndexOutOfRange,
     "offset 211: face 0 index 7 out of range (3 vertices)"},
    {"ply_binary_negative_count.ply", ErrorCode::ParseError, "offset 204: negative list length -1"},
    {"ply_binary_huge_list.ply", ErrorCode::BudgetExceeded,
     "offset 205: face 0 has 1000000 vertices, more than max_face_size (65536)"},
    {"ply_binary_list_past_end.ply", ErrorCode::ParseError,
     "offset 209: unexpected end of file in 'face' element 0 of 1"},
    {"ply_be_inf.ply", ErrorCode::NonFinite, "offset 218: vertex 2 has a non-finite coordinate"},
    {"ply_binary_repeated.ply", ErrorCode::DegenerateFace, "offset 206: face 0 uses vertex 0 more than once"},
    // UTF-16 is read as the text it spells (here a header without elements), with its own line numbers
    {"ply_utf16le_bom.ply", ErrorCode::ParseError, "line 3: no vertex element in the header"},
    {"ply_utf16le_binary.ply", ErrorCode::ParseError, "line 2: binary PLY with a UTF-16 header"},
    {"ply_garbage.ply", ErrorCode::ParseError, "line 1: not a PLY file"},

    // ---- STL
    {"stl_empty.stl", ErrorCode::ParseError, "empty file"},
    {"stl_ascii_truncated.stl", ErrorCode::ParseError, "line 5: unexpected end of file inside a facet"},
    {"stl_ascii_nan.stl", ErrorCode::NonFinite, "line 5: vertex has a non-finite coordinate"},
    {"stl_ascii_bad_keyword.stl", ErrorCode::ParseError, "line 3: expected 'loop', found 'lop'"},
    {"stl_ascii_two_vertices.stl", ErrorCode::DegenerateFace, "line 2: facet has 2 vertices (3 needed)"},
    {"stl_ascii_four_vertices.stl", ErrorCode::ParseError, "line 7: facet has more than 3 vertices"},
    {"stl_ascii_no_endsolid.stl", ErrorCode::ParseError, "line 8: unexpected end of file (no 'endsolid')"},
    {"stl_ascii_bad_number.stl", ErrorCode::ParseError, "line 5: vertex value '1,5' is not a number"},
    {"stl_ascii_all_degenerate.stl", ErrorCode::DegenerateFace, "all 1 triangles are degenerate"},
    {"stl_ascii_empty_solid.stl", ErrorCode::ParseError, "no faces"},
    {"stl_binary_truncated.stl", ErrorCode::ParseError,
     "offset 80: binary STL declares 12 triangles (684 bytes) but the file has 334 bytes"},
    {"stl_binary_absurd_count.stl", ErrorCode::ParseError, "offset 80: binary STL declares 4000000000 triangles"},
    {"stl_binary_nan.stl", ErrorCode::NonFinite, "offset 170: triangle 1 has a non-finite coordinate"},
    {"stl_binary_inf.stl", ErrorCode::NonFinite, "offset 96: triangle 0 has a non-finite coordinate"},
    {"stl_binary_all_degenerate.stl", ErrorCode::DegenerateFace, "all 2 triangles are degenerate"},
    {"stl_binary_zero_triangles.stl", ErrorCode::ParseError, "no faces"},
    {"stl_binary_solid_truncated.stl", ErrorCode::ParseError, "offset 80: binary STL declares 3 triangles"},
    {"stl_utf16le_bom.stl", ErrorCode::ParseError, "no faces"},
    {"stl_short_garbage.stl", ErrorCode::ParseError,
     "offset 0: not an ascii STL (no 'solid') and too short for a binary STL (30 bytes"},
};

//! Files of the corpus that were refused until UTF-16 with a byte order mark was read: each holds one triangle.
const char* const kAccepted[] = {"obj_utf16le_bom.obj", "obj_utf16be_bom.obj", "off_utf16le_bom.off"};

Result<PolygonMesh> read_any(const std::string& name, std::string_view bytes) {
    switch (*format_from_extension(name)) {
        case MeshFormat::Obj: return read_obj(bytes);
        case MeshFormat::Off: return read_off(bytes);
        case MeshFormat::Ply: return read_ply(bytes);
        case MeshFormat::Stl: return read_stl(bytes);
        case MeshFormat::Glb:
        case MeshFormat::Gltf: break;
    }
    return make_error(ErrorCode::Internal, "not a format of this test");
}

//! "line 12: ..." -> 12 (and the same for "offset"), or -1.
std::int64_t location(const std::string& needle, const std::string& prefix) {
    if (needle.rfind(prefix, 0) != 0) return -1;
    return std::strtoll(needle.c_str() + prefix.size(), nullptr, 10);
}

class MalformedFile : public ::testing::TestWithParam<Case> {};

TEST_P(MalformedFile, FailsWithLocatedError) {
    const Case& c = GetParam();
    const std::string bytes = format_test::slurp(format_test::malformed_dir() + "/" + c.file);
    auto result = read_any(c.file, bytes);
    ASSERT_TRUE(fails_with(result, c.code, c.needle));
    const std::string needle = c.needle;
    if (const auto line = location(needle, "line "); line >= 0) {
        EXPECT_EQ(result.error().line, line);
    }
    if (const auto offset = location(needle, "offset "); offset >= 0) {
        EXPECT_EQ(result.error().offset, offset);
    }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string name = info.param.file;
    for (char& ch : name)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Malformed, MalformedFile, ::testing::ValuesIn(kCases), case_name);

TEST(MalformedCorpus, EveryFileHasACase) {
    std::set<std::string> listed;
    for (const Case& c : kCases) EXPECT_TRUE(listed.insert(c.file).second) << "listed twice: " << c.file;
    for (const char* file : kAccepted) EXPECT_TRUE(listed.insert(file).second) << "listed twice: " << file;
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(format_test::malformed_dir())) {
        const std::string name = entry.path().filename().string();
        if (name == "make_binary_cases.py") continue;
        ++files;
        EXPECT_TRUE(listed.count(name)) << "no expectation for " << name;
    }
    EXPECT_EQ(files, listed.size());
}

TEST(MalformedCorpus, Utf16WithByteOrderMarkIsRead) {
    for (const char* file : kAccepted) {
        auto mesh = read_any(file, format_test::slurp(format_test::malformed_dir() + "/" + file));
        ASSERT_TRUE(mesh.ok()) << file << ": " << mesh.error().message;
        EXPECT_EQ(mesh->vertex_count(), 3u) << file;
        EXPECT_EQ(mesh->face_count(), 1u) << file;
    }
}

TEST(MalformedCorpus, AbsurdCountsAreRejectedQuickly) {
    // The header promises ~4e9 items; the readers must neither reserve for them nor loop over them.
    std::string stl(80, ' ');
    stl += std::string("\xff\xff\xff\xff", 4);
    stl += std::string(116, '\x01');
    EXPECT_TRUE(fails_with(read_stl(stl), ErrorCode::ParseError, "declares 4294967295 triangles"));
    const std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4294967295\nproperty float x\n"
        "property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n" +
        std::string(100, '\0');
    EXPECT_TRUE(
        fails_with(read_ply(ply), ErrorCode::ParseError, "line 3: header declares 4294967295 'vertex' elements"));
    // Within the bytes but over the configured limit: BudgetExceeded naming the limit.
    ReadOptions small;
    small.max_vertices = 2;
    EXPECT_TRUE(fails_with(read_ply(format_test::slurp(format_test::malformed_dir() + "/ply_binary_nan.ply"), small),
                           ErrorCode::BudgetExceeded, "more than max_vertices (2)"));
}

TEST(MalformedCorpus, TruncatedPrefixesNeverCrash) {
    // Every prefix of valid files (all formats) either parses or fails with an error; never crashes or hangs.
    PolygonMesh mesh = format_test::cube();
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (std::size_t i = 0; i < mesh.face_indices.size(); ++i) mesh.uv_indices.push_back(static_cast<Index>(i % 4));
    mesh.tags.creases = {{0, 1, 2}};
    const std::string files[] = {write_obj(mesh), write_ply(mesh, PlyEncoding::Ascii),
                                 write_ply(mesh, PlyEncoding::BinaryLittleEndian)};
    for (const std::string& file : files)
        for (std::size_t n = 0; n < file.size(); ++n) {
            const std::string_view prefix(file.data(), n);
            auto a = read_obj(prefix);
            auto b = read_ply(prefix);
            auto c = read_off(prefix);
            auto d = read_stl(prefix);
            for (const auto* r : {&a, &b, &c, &d}) {
                if (!r->ok()) {
                    EXPECT_FALSE(r->error().message.empty());
                }
            }
        }
}

TEST(MalformedCorpus, MutatedFilesFailCleanlyOrValidate) {
    // Random byte edits of valid files in every format: each read either fails with a message, or gives a mesh
    // that passes validate() (the readers' own checks must be complete). Fixed seed, so failures reproduce.
    PolygonMesh mesh = format_test::cube();
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (std::size_t i = 0; i < mesh.face_indices.size(); ++i) mesh.uv_indices.push_back(static_cast<Index>(i % 4));
    mesh.normals.assign(8, Vec3{0, 0, 1});
    mesh.tags.creases = {{0, 1, 2}};
    mesh.tags.corners = {{3, 1.5}};
    mesh.tags.holes = {5};
    std::string off = "OFF\n8 6 0\n";
    for (const Vec3& p : mesh.positions)
        off += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        off += "4";
        for (Index v : mesh.face(f)) off += " " + std::to_string(v);
        off += "\n";
    }
    std::string stl_ascii = "solid s\n";
    std::string stl_binary(80, ' ');
    stl_binary += std::string("\x0c\0\0\0", 4);
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
        auto q = mesh.face(f);
        for (int t = 0; t < 2; ++t) {
            const Index tri[3] = {q[0], q[t + 1], q[t + 2]};
            stl_ascii += "facet normal 0 0 0\nouter loop\n";
            stl_binary += std::string(12, '\0');
            for (Index v : tri) {
                const Vec3& p = mesh.positions[v];
                stl_ascii +=
                    "vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
                for (int k = 0; k < 3; ++k) {
                    const float value = static_cast<float>(p[k]);
                    stl_binary.append(reinterpret_cast<const char*>(&value), 4);  // little-endian host assumed here
                }
            }
            stl_ascii += "endloop\nendfacet\n";
            stl_binary += std::string(2, '\0');
        }
    }
    stl_ascii += "endsolid s\n";
    const std::pair<MeshFormat, std::string> seeds[] = {
        {MeshFormat::Obj, write_obj(mesh)},
        {MeshFormat::Off, off},
        {MeshFormat::Ply, write_ply(mesh, PlyEncoding::Ascii)},
        {MeshFormat::Ply, write_ply(mesh, PlyEncoding::BinaryLittleEndian)},
        {MeshFormat::Stl, stl_ascii},
        {MeshFormat::Stl, stl_binary},
    };
    std::uint64_t state = 0x9e3779b97f4a7c15ULL;
    auto next = [&state](std::uint64_t bound) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<std::size_t>((state >> 33) % bound);
    };
    const char interesting[] = {'0', '9', '-', '/', ' ', '\n', '.', 'e', '#', '\\', '\0', '\xff', 'n', 'f', 'v', 't'};
    std::size_t parsed = 0, failed = 0;
    for (const auto& [format, seed] : seeds) {
        for (int iteration = 0; iteration < 1500; ++iteration) {
            std::string bytes = seed;
            const int edits = 1 + static_cast<int>(next(4));
            for (int e = 0; e < edits && !bytes.empty(); ++e) {
                const std::size_t at = next(bytes.size());
                switch (next(5)) {
                    case 0: bytes[at] = static_cast<char>(next(256)); break;
                    case 1: bytes[at] = interesting[next(sizeof(interesting))]; break;
                    case 2: bytes.insert(at, 1, interesting[next(sizeof(interesting))]); break;
                    case 3: bytes.erase(at, 1 + next(8)); break;
                    case 4: bytes.resize(at); break;
                }
            }
            Result<PolygonMesh> result = format == MeshFormat::Obj   ? read_obj(bytes)
                                         : format == MeshFormat::Off ? read_off(bytes)
                                         : format == MeshFormat::Ply ? read_ply(bytes)
                                                                     : read_stl(bytes);
            if (result.ok()) {
                ++parsed;
                const Status valid = validate(*result);
                ASSERT_TRUE(valid.ok()) << valid.error().message << "\n--- input:\n" << bytes;
            } else {
                ++failed;
                ASSERT_FALSE(result.error().message.empty());
                ASSERT_TRUE(result.error().line >= 0 || result.error().offset >= 0 ||
                            result.error().message.find("no faces") != std::string::npos ||
                            result.error().message.find("empty file") != std::string::npos ||
                            result.error().message.find("UTF-16") != std::string::npos)
                    << "error without a location: " << result.error().message;
            }
        }
    }
    EXPECT_GT(parsed, 100u);
    EXPECT_GT(failed, 100u);
}

// ---- format detection

TEST(ObjOffPlyStlFormatDetect, FromExtension) {
    EXPECT_EQ(format_from_extension("a/b/model.OBJ"), MeshFormat::Obj);
    EXPECT_EQ(format_from_extension("x.off"), MeshFormat::Off);
    EXPECT_EQ(format_from_extension("C:\\dir.d\\bunny.Ply"), MeshFormat::Ply);
    EXPECT_EQ(format_from_extension("part.stl"), MeshFormat::Stl);
    EXPECT_EQ(format_from_extension("scene.glb"), MeshFormat::Glb);
    EXPECT_EQ(format_from_extension("scene.gltf"), MeshFormat::Gltf);
    EXPECT_EQ(format_from_extension("dir.obj/noext"), std::nullopt);
    EXPECT_EQ(format_from_extension("trailingdot."), std::nullopt);
    EXPECT_EQ(format_from_extension(""), std::nullopt);
}

TEST(ObjOffPlyStlFormatDetect, FromMediaType) {
    EXPECT_EQ(format_from_media_type("model/obj"), MeshFormat::Obj);
    EXPECT_EQ(format_from_media_type("Model/STL; charset=binary"), MeshFormat::Stl);
    EXPECT_EQ(format_from_media_type("application/sla"), MeshFormat::Stl);
    EXPECT_EQ(format_from_media_type("application/ply"), MeshFormat::Ply);
    EXPECT_EQ(format_from_media_type(" model/gltf-binary "), MeshFormat::Glb);
    EXPECT_EQ(format_from_media_type("model/gltf+json"), MeshFormat::Gltf);
    EXPECT_EQ(format_from_media_type("application/json"), std::nullopt);
}

TEST(ObjOffPlyStlFormatDetect, Sniff) {
    const PolygonMesh mesh = format_test::cube();
    EXPECT_EQ(sniff_format(write_obj(mesh)), MeshFormat::Obj);
    EXPECT_EQ(sniff_format("v 0 0 0\n"), MeshFormat::Obj);
    EXPECT_EQ(sniff_format(write_ply(mesh, PlyEncoding::Ascii)), MeshFormat::Ply);
    EXPECT_EQ(sniff_format(write_ply(mesh, PlyEncoding::BinaryLittleEndian)), MeshFormat::Ply);
    EXPECT_EQ(sniff_format("# comment\nOFF\n3 1 0\n"), MeshFormat::Off);
    EXPECT_EQ(sniff_format("COFF 3 1 0\n"), MeshFormat::Off);
    EXPECT_EQ(sniff_format("solid x\nfacet normal 0 0 1\n"), MeshFormat::Stl);
    EXPECT_EQ(sniff_format(std::string("glTF\x02\0\0\0", 8)), MeshFormat::Glb);
    EXPECT_EQ(sniff_format(format_test::slurp(format_test::malformed_dir() + "/stl_binary_nan.stl")), MeshFormat::Stl);
    EXPECT_EQ(sniff_format(format_test::slurp(format_test::malformed_dir() + "/obj_binary_garbage.obj")), std::nullopt);
    EXPECT_EQ(sniff_format(""), std::nullopt);
    for (const auto& entry : std::filesystem::directory_iterator(format_test::shapes_dir())) {
        if (entry.path().extension() == ".obj") {
            EXPECT_EQ(sniff_format(format_test::slurp(entry.path().string())), MeshFormat::Obj) << entry.path();
        }
    }
}

}  // namespace
}  // namespace surfaced
