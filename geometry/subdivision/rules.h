// Subdivision weights as pure functions of valence: OpenSubdiv's Sdc rules for Catmull-Clark ("catmark") and Loop.
// Kept apart from topology and data (as OpenSubdiv keeps Sdc apart from Vtr and Far).
#pragma once

#include <cmath>
#include <numbers>

namespace surfaced::subdivision {

//! Smooth interior vertex of valence n (Catmull-Clark): new = v*P + e*sum(edge neighbours) + f*sum(face points).
struct CatmarkVertexWeights {
    double vertex, edge, face;
};
inline CatmarkVertexWeights catmark_smooth_vertex(int n) {
    const double dn = n;
    return {(dn - 2.0) / dn, 1.0 / (dn * dn), 1.0 / (dn * dn)};
}

//! Smooth interior vertex of valence n (Loop's original weights, as OpenSubdiv): new = v*P + e*sum(neighbours).
struct LoopVertexWeights {
    double vertex, edge;
};
inline LoopVertexWeights loop_smooth_vertex(int n) {
    if (n == 6) return {0.625, 0.0625};  // exact for the regular case
    const double dn = n;
    const double beta = 0.375 + 0.25 * std::cos(2.0 * std::numbers::pi / dn);
    const double e = (0.625 - beta * beta) / dn;
    return {1.0 - e * dn, e};
}

//! Warren's simplified Loop weights: beta = 3/(8n) (3/16 at valence 3). Not OpenSubdiv's; cheaper to reason about.
inline LoopVertexWeights loop_warren_vertex(int n) {
    const double beta = n == 3 ? 3.0 / 16.0 : 3.0 / (8.0 * n);
    return {1.0 - n * beta, beta};
}

//! Crease (and boundary) vertex with exactly two sharp edges: 3/4 P + 1/8 each sharp neighbour.
inline constexpr double kCreaseVertexWeight = 0.75;
inline constexpr double kCreaseNeighbourWeight = 0.125;

//! Smooth Loop edge: 3/8 each end, 1/8 each opposite vertex. Smooth Catmull-Clark edge: 1/4 each end and face point.
inline constexpr double kLoopEdgeEndWeight = 0.375;
inline constexpr double kLoopEdgeOppositeWeight = 0.125;
inline constexpr double kCatmarkEdgeWeight = 0.25;

}  // namespace surfaced::subdivision
