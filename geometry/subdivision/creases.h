// Sharpness and OpenSubdiv's crease rules (Sdc::Crease): the sharpness state of a level, which rule a vertex follows
// (smooth, dart, crease, corner), how semi-sharp sharpness decays from one level to the next (uniform or Chaikin), the
// fractional weight where a feature turns smooth between two levels, and the base level's sharpness from the mesh tags
// and the topology. Internal to geometry/subdivision; interpolate.cpp applies these rules to points. Sharpness
// arithmetic is done in float, as OpenSubdiv does, so that results agree to the last bits.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/core/result.h"
#include "geometry/core/types.h"
#include "geometry/mesh/polygon_mesh.h"
#include "geometry/subdivision/subdivide.h"
#include "geometry/subdivision/topology.h"

namespace surfaced::subdivision {

//! Sharpness classes: > 0 is sharp, >= kInfiniteSharpness infinitely so; semi-sharp features decay to smooth.
inline bool is_sharp(float s) { return s > 0.0f; }
inline bool is_infinite(float s) { return s >= kInfiniteSharpness; }
inline bool is_semi_sharp(float s) { return s > 0.0f && s < kInfiniteSharpness; }
//! Uniform decay of one level: sharpness - 1, down to 0; infinite stays infinite.
inline float decrement(float s) {
    if (is_infinite(s)) return kInfiniteSharpness;
    return s > 1.0f ? s - 1.0f : 0.0f;
}

//! A vertex's rule: from its own sharpness and the number of sharp edges at it.
enum class Rule { Smooth, Dart, Crease, Corner };
inline Rule vertex_rule(float vertex_sharpness, int sharp_edges) {
    if (is_sharp(vertex_sharpness)) return Rule::Corner;
    switch (sharp_edges) {
        case 0: return Rule::Smooth;
        case 1: return Rule::Dart;
        case 2: return Rule::Crease;
        default: return Rule::Corner;
    }
}

//! Sharpness state of one level.
struct Sharpness {
    std::vector<float> edge;         // per edge; boundary and non-manifold edges are infinite
    std::vector<float> vertex;       // per vertex
    std::vector<std::uint8_t> hole;  // per face; empty when there are no holes
};

//! What the rules need to know about a level's vertices.
struct Neighbourhood {
    std::vector<std::uint32_t> vertex_faces, vertex_edges;
    std::vector<Index> sharp_offsets;  // per vertex, into sharp_edges: incident edges with sharpness > 0
    std::vector<Index> sharp_edges;
    std::vector<float> semi_sum;  // Chaikin: sum of incident semi-sharp sharpness
    std::vector<std::uint16_t> semi_count;
    bool any_sharp_vertex = false;
};

//! The neighbourhood of every vertex of `level` (the Chaikin sums only with CreaseMethod::Chaikin).
Neighbourhood neighbourhood(const Level& level, const Sharpness& sharp, CreaseMethod method);

//! Sharpness of the child of an edge (sharpness s) at its end vertex v (OpenSubdiv's Crease::
//! SubdivideEdgeSharpnessAtVertex): uniform decay, or Chaikin's 3/4 own + 1/4 the other semi-sharp edges' average.
inline float child_edge_sharpness(float s, Index v, const Neighbourhood& n, CreaseMethod method) {
    if (method == CreaseMethod::Uniform || n.vertex_edges[v] < 2) return decrement(s);
    if (!is_sharp(s)) return 0.0f;
    if (is_infinite(s)) return kInfiniteSharpness;
    if (n.semi_count[v] > 1) {
        const float others = (n.semi_sum[v] - s) / static_cast<float>(n.semi_count[v] - 1);
        s = 0.75f * s + 0.25f * others;
    }
    s -= 1.0f;
    return is_sharp(s) ? s : 0.0f;
}

//! Fraction of the parent rule in a vertex whose rule changes between levels (Crease::ComputeFractionalWeightAtVertex).
//! `parent_edges`/`child_edges`: the sharpness of the vertex's `count` sharp edges before and after the decay.
float fractional_weight(float parent_vertex, float child_vertex, const float* parent_edges, const float* child_edges,
                        Index count);

//! Sharpness of the child level (vertices: children of vertices first; edges: face-interior edges first, then two
//! per parent edge), and holes carried to child faces. `holes_only`: the last level, where nothing refines the
//! sharpness further; only the holes are needed (for the output), and the rest would be written for nothing.
Sharpness refine_sharpness(const Level& p, const Level& child, const Sharpness& sharp, const Neighbourhood& n,
                           CreaseMethod method, bool loop, bool holes_only = false);

//! Base-level sharpness from the mesh tags and the topology, as OpenSubdiv's factory assigns it: boundary and
//! non-manifold edges are infinitely sharp; corners of one face are with edge-and-corner; non-manifold vertices are,
//! except on a simple non-manifold crease. With "boundary none", faces at an open boundary become holes. Fails
//! (InvalidArgument) on a crease between vertices that share no edge.
Result<Sharpness> base_sharpness(const PolygonMesh& mesh, const Level& level, BoundaryInterpolation boundary,
                                 bool use_tags);

}  // namespace surfaced::subdivision
