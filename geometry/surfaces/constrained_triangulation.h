// A constrained Delaunay triangulation of points in a rectangle, built incrementally: the rectangle starts as two
// triangles; each point is located by a visibility walk and inserted by splitting its triangle (or the edge it lies
// on), then Lawson flips restore the Delaunay property (never flipping a constrained edge); a constraint segment is
// recovered by flipping the edges it crosses (Sloan's method). Used by the trimmed-surface tessellator
// (trimmed_surface.h) in each Bézier patch's scaled parameter plane. Internal to geometry/surfaces.
//
// Robustness. Orientation and in-circle tests are plain double-precision determinants; a flip is only made when both
// new triangles are positively oriented, so the triangulation stays valid whatever the rounding (it may then be only
// nearly Delaunay). Points exactly on an edge (orientation exactly 0, as for points on the rectangle's sides or on a
// shared grid line) split that edge.
//
// References: C. L. Lawson, "Software for C1 surface interpolation" (1977) (flips); S. W. Sloan, "A fast algorithm for
// generating constrained Delaunay triangulations", Computers & Structures 47 (1993) (constraint recovery).
#pragma once

#include <array>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "geometry/core/types.h"

namespace surfaced::detail {

struct CdtTriangle {
    std::array<int, 3> v{};            //!< vertices, counter-clockwise
    std::array<int, 3> n{-1, -1, -1};  //!< n[i]: the triangle across the edge opposite v[i] (-1 on the rectangle)
};

class ConstrainedTriangulation {
public:
    //! The rectangle [lo, hi] as two triangles (its four corners are vertices 0..3: lo, (hi.x, lo.y), hi, (lo.x, hi.y)).
    ConstrainedTriangulation(Vec2 lo, Vec2 hi);

    //! Inserts p, which must lie in the closed rectangle. Returns its vertex index, or the index of the vertex already
    //! at p (exactly equal coordinates).
    int insert(Vec2 p);

    //! Makes the segment a-b a chain of edges that later flips keep (split at vertices lying exactly on it). False when
    //! it crosses an earlier constraint or the flips do not converge (inputs that cross).
    bool constrain(int a, int b);

    //! Inserts p when it lies strictly inside the rectangle, can be reached from triangle `from` by a walk that crosses
    //! no constrained edge, lies on no edge or vertex, and is outside the diametral circle of every constrained edge of
    //! the triangle holding it (Ruppert's encroachment; only when check_encroachment). Returns the vertex index, or -1
    //! when refused.
    int insert_free(Vec2 p, int from, bool check_encroachment = true);
    //! When insert_free refused p because it lies beyond or encroaches on a side of the rectangle: that side's edge
    //! (its two vertices), else (-1, -1). Splitting that edge is the caller's decision (Ruppert's boundary split).
    std::pair<int, int> refused_side() const { return refused_side_; }

    //! Lawson flips over every edge that is not constrained until all are locally Delaunay (after constrain()).
    void restore_delaunay();

    //! Component label of each triangle (triangles joined across edges that are not constrained); returns the count.
    int components(std::vector<int>& label) const;

    bool constrained(int a, int b) const { return constraints_.count(key(a, b)) != 0; }
    const std::vector<Vec2>& points() const { return points_; }
    const std::vector<CdtTriangle>& triangles() const { return triangles_; }

private:
    static std::uint64_t key(int a, int b) {
        const auto lo = static_cast<std::uint64_t>(a < b ? a : b), hi = static_cast<std::uint64_t>(a < b ? b : a);
        return lo << 32 | hi;
    }
    struct Location {
        int triangle = -1;
        int edge = -1;    //!< p lies on the edge opposite v[edge]
        int vertex = -1;  //!< p equals this vertex
        bool blocked = false;
    };
    Location locate(Vec2 p, int start, bool stop_at_constraints) const;
    int add_point(Vec2 p, const Location& at);
    void split_triangle(int t, int p);
    void split_edge(int t, int i, int p);
    void legalize(std::vector<std::pair<int, int>>& stack);
    bool flip(int t, int i);
    void set_neighbor(int t, int old_neighbor, int new_neighbor);
    bool find_edge(int a, int b, int& t, int& i) const;
    int opposite_index(int t, int neighbor) const;

    Vec2 lo_, hi_;
    std::vector<Vec2> points_;
    std::vector<CdtTriangle> triangles_;
    std::vector<int> vertex_triangle_;  //!< one triangle holding each vertex
    std::unordered_set<std::uint64_t> constraints_;
    int last_ = 0;  //!< where the next walk starts
    std::pair<int, int> refused_side_{-1, -1};
};

double orient(Vec2 a, Vec2 b, Vec2 c);

}  // namespace surfaced::detail
