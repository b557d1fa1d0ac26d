#include "tests/support/osd_reference.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <memory>
#include <vector>

namespace surfaced::testing {

namespace {
using namespace OpenSubdiv;

struct Point {
    double p[3];
    void Clear() { p[0] = p[1] = p[2] = 0; }
    void AddWithWeight(const Point& src, double w) {
        p[0] += w * src.p[0];
        p[1] += w * src.p[1];
        p[2] += w * src.p[2];
    }
};

Sdc::Options::VtxBoundaryInterpolation to_osd(BoundaryInterpolation b) {
    switch (b) {
        case BoundaryInterpolation::None: return Sdc::Options::VTX_BOUNDARY_NONE;
        case BoundaryInterpolation::EdgeOnly: return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
        case BoundaryInterpolation::EdgeAndCorner: return Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
    }
    return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
}
}  // namespace

std::unique_ptr<Far::TopologyRefiner> make_refiner(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::vector<int> verts_per_face(mesh.face_count());
    for (std::size_t f = 0; f < mesh.face_count(); ++f) verts_per_face[f] = static_cast<int>(mesh.face_size(f));
    std::vector<int> indices(mesh.face_indices.begin(), mesh.face_indices.end());

    Far::TopologyDescriptor desc;
    desc.numVertices = static_cast<int>(mesh.vertex_count());
    desc.numFaces = static_cast<int>(mesh.face_count());
    desc.numVertsPerFace = verts_per_face.data();
    desc.vertIndicesPerFace = indices.data();

    std::vector<int> crease_pairs, corner_vertices, holes;
    std::vector<float> crease_weights, corner_weights;
    if (options.use_mesh_tags) {
        for (const Crease& c : mesh.tags.creases) {
            crease_pairs.push_back(static_cast<int>(c.v0));
            crease_pairs.push_back(static_cast<int>(c.v1));
            crease_weights.push_back(static_cast<float>(c.sharpness));
        }
        for (const Corner& c : mesh.tags.corners) {
            corner_vertices.push_back(static_cast<int>(c.vertex));
            corner_weights.push_back(static_cast<float>(c.sharpness));
        }
        for (Index h : mesh.tags.holes) holes.push_back(static_cast<int>(h));
    }
    desc.numCreases = static_cast<int>(crease_weights.size());
    desc.creaseVertexIndexPairs = crease_pairs.data();
    desc.creaseWeights = crease_weights.data();
    desc.numCorners = static_cast<int>(corner_weights.size());
    desc.cornerVertexIndices = corner_vertices.data();
    desc.cornerWeights = corner_weights.data();
    desc.numHoles = static_cast<int>(holes.size());
    desc.holeIndices = holes.data();
    // UVs as face-varying channel 0 (the descriptor keeps pointers: the storage is static per thread, valid until
    // the next call, which is enough because the factory copies everything in Create)
    thread_local std::vector<int> uv_indices;
    thread_local Far::TopologyDescriptor::FVarChannel channel;
    if (mesh.has_uvs()) {
        uv_indices.assign(mesh.uv_indices.begin(), mesh.uv_indices.end());
        channel.numValues = static_cast<int>(mesh.uvs.size());
        channel.valueIndices = uv_indices.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    Sdc::Options sdc;
    sdc.SetFVarLinearInterpolation(static_cast<Sdc::Options::FVarLinearInterpolation>(options.uv_interpolation));
    sdc.SetCreasingMethod(options.crease_method == CreaseMethod::Chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                         : Sdc::Options::CREASE_UNIFORM);
    sdc.SetTriangleSubdivision(options.triangle_rule == TriangleRule::Smooth ? Sdc::Options::TRI_SUB_SMOOTH
                                                                             : Sdc::Options::TRI_SUB_CATMARK);
    BoundaryInterpolation boundary =
        options.use_mesh_boundary_tag && mesh.tags.boundary ? *mesh.tags.boundary : options.boundary;
    sdc.SetVtxBoundaryInterpolation(to_osd(boundary));
    const Sdc::SchemeType scheme = options.scheme == SubdivisionScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    return std::unique_ptr<Far::TopologyRefiner>(Factory::Create(desc, Factory::Options(scheme, sdc)));
}

PolygonMesh osd_subdivide(const PolygonMesh& mesh, const SubdivisionOptions& options) {
    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(mesh, options);
    if (!refiner) return {};
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(options.levels));

    std::vector<Point> src(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        src[v] = Point{{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z}};
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    std::vector<Point> dst;
    for (int level = 1; level <= options.levels; ++level) {
        dst.resize(refiner->GetLevel(level).GetNumVertices());
        Point* out = dst.data();
        primvar.Interpolate(level, src.data(), out);
        src.swap(dst);
    }

    std::vector<Point> uv_src, uv_dst;
    if (mesh.has_uvs()) {
        for (const Vec2& uv : mesh.uvs) uv_src.push_back(Point{{uv.x, uv.y, 0.0}});
        for (int level = 1; level <= options.levels; ++level) {
            uv_dst.resize(refiner->GetLevel(level).GetNumFVarValues(0));
            Point* o = uv_dst.data();
            primvar.InterpolateFaceVarying(level, uv_src.data(), o, 0);
            uv_src.swap(uv_dst);
        }
    }

    PolygonMesh out;
    for (const Point& p : src) out.positions.push_back({p.p[0], p.p[1], p.p[2]});
    for (const Point& p : uv_src) out.uvs.push_back({p.p[0], p.p[1]});
    const Far::TopologyLevel& last = refiner->GetLevel(options.levels);
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        if (last.IsFaceHole(f)) continue;
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        std::vector<Index> face(fv.begin(), fv.end());
        out.add_face(face);
        if (mesh.has_uvs()) {
            Far::ConstIndexArray values = last.GetFaceFVarValues(f, 0);
            out.uv_indices.insert(out.uv_indices.end(), values.begin(), values.end());
        }
    }
    return out;
}

OsdLimit osd_limit(const PolygonMesh& mesh, const SubdivisionOptions& options, int at_level, std::size_t count) {
    std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(mesh, options);
    OsdLimit out;
    if (!refiner) return out;
    Far::TopologyRefiner::UniformOptions uniform(at_level);
    uniform.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uniform);
    std::vector<Point> src(mesh.vertex_count()), dst;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        src[v] = Point{{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z}};
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int level = 1; level <= at_level; ++level) {
        dst.resize(refiner->GetLevel(level).GetNumVertices());
        Point* o = dst.data();
        primvar.Interpolate(level, src.data(), o);
        src.swap(dst);
    }
    std::vector<Point> pos(src.size()), t1(src.size()), t2(src.size());
    Point* pp = pos.data();
    Point* p1 = t1.data();
    Point* p2 = t2.data();
    primvar.Limit(src.data(), pp, p1, p2);
    for (std::size_t v = 0; v < count && v < src.size(); ++v) {
        out.positions.push_back({pos[v].p[0], pos[v].p[1], pos[v].p[2]});
        const Vec3 a{t1[v].p[0], t1[v].p[1], t1[v].p[2]}, b{t2[v].p[0], t2[v].p[1], t2[v].p[2]};
        const Vec3 n = cross(a, b);
        const double len = norm(n);
        out.normals.push_back(len > 0 ? n * (1.0 / len) : Vec3{});
    }
    return out;
}

}  // namespace surfaced::testing
