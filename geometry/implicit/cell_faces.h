// The cell-local numbering and face topology shared by the marching-cubes style meshers (the dual mesher of
// mesh_field.cpp and the reconstruction's sparse extraction): corners, edges, and the segments the zero level cuts
// across one face of a cell, with the asymptotic decider on faces with four crossings.
//
// Corner c has offsets (c & 1, c >> 1 & 1, c >> 2 & 1). Edge e along axis a = e / 4 starts at the corner with offset
// o_b = e & 1 on axis b = (a+1)%3 and o_c = (e >> 1) & 1 on axis c = (a+2)%3, and 0 on axis a.
#pragma once

namespace surfaced::cell_faces {

inline int bit(int corner, int axis) { return (corner >> axis) & 1; }

//! The edge along `axis` that starts at `corner`'s offsets on the two other axes.
inline int local_edge(int axis, int corner) {
    return 4 * axis + bit(corner, (axis + 1) % 3) + 2 * bit(corner, (axis + 2) % 3);
}

inline int edge_start_corner(int e) {
    const int a = e / 4, ob = e & 1, oc = (e >> 1) & 1;
    return (ob << ((a + 1) % 3)) | (oc << ((a + 2) % 3));
}

struct Segment {
    int e0, e1;
};

//! The segments joining the crossings on face (normal axis `a`, side `s`) of a cell with corner values v (inside:
//! v < 0). A face with four crossings is decided by the asymptotic decider: the bilinear interpolant's saddle value
//! (a00 a11 - a10 a01) / (a00 + a11 - a10 - a01), computed in double from the face's four values in the face's own
//! (u, w) order, so both cells sharing the face agree. Returns how many (0, 1 or 2).
template <class Value>
int face_segments(const Value v[8], int a, int s, Segment out[2]) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    auto corner = [&](int u, int w) { return (s << a) | (u << b) | (w << c); };
    const int c00 = corner(0, 0), c10 = corner(1, 0), c01 = corner(0, 1), c11 = corner(1, 1);
    const int e[4] = {local_edge(b, c00), local_edge(c, c10), local_edge(b, c01), local_edge(c, c00)};
    const bool in00 = v[c00] < 0, in10 = v[c10] < 0, in01 = v[c01] < 0, in11 = v[c11] < 0;
    const bool x[4] = {in00 != in10, in10 != in11, in01 != in11, in00 != in01};
    const int crossings = x[0] + x[1] + x[2] + x[3];
    if (crossings == 0) return 0;
    if (crossings == 2) {
        int found[2], n = 0;
        for (int i = 0; i < 4; ++i)
            if (x[i]) found[n++] = e[i];
        out[0] = {found[0], found[1]};
        return 1;
    }
    const double a00 = v[c00], a10 = v[c10], a01 = v[c01], a11 = v[c11];
    const double numerator = a00 * a11 - a10 * a01;
    const double denominator = a00 + a11 - a10 - a01;
    const bool centre_inside = numerator * denominator < 0;
    if (centre_inside == in00) {  // 00 and 11 joined through the centre: cut off corners 10 and 01
        out[0] = {e[0], e[1]};
        out[1] = {e[2], e[3]};
    } else {  // cut off corners 00 and 11
        out[0] = {e[3], e[0]};
        out[1] = {e[1], e[2]};
    }
    return 2;
}

}  // namespace surfaced::cell_faces
