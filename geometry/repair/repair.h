// Mesh repair: turns a polygon soup or a broken mesh into one that manifold-only algorithms (simplification,
// subdivision, remeshing) accept, and says what it changed.
//
// repair_mesh runs these steps, in this order; each counts what it did in RepairReport, and no face is dropped
// without being counted:
//  1. weld: vertices with identical positions (or, with weld_tolerance > 0, within that distance of a kept vertex:
//     a grid hash) merge into the lowest index among them; the kept vertex keeps its position.        -> welded
//  2. degenerate faces: a face that uses a vertex more than once (after welding), or whose vector area (Newell) is
//     exactly zero (collinear or coincident corners), is dropped.                                    -> degenerate
//  3. duplicate faces: a face with the same vertex set as an earlier face is dropped, whatever its winding (a
//     back-to-back pair is a duplicate); the first one stays.                                         -> duplicate
//  4. joining and orientation: faces are joined across their edges, at most two per edge. An edge of two faces is
//     joined (in either direction: one of them will be reversed), unless the faces are tied together already with
//     the other relative winding (a non-orientable surface is cut there). On an edge of more than two faces (a fin,
//     two solids sharing an edge) faces are paired where they can agree and the rest are cut off. Each connected set
//     of joined faces is then oriented by its lowest face (faces that disagree are reversed), and a closed set
//     (every edge joined) whose signed volume is negative is reversed whole, so that it faces outward. -> flipped
//  5. non-manifold vertices: the faces around a vertex that are not connected through joined edges around it (a
//     bow-tie, two solids touching at a vertex, the faces cut off a fin) get their own copy of the vertex, one per
//     fan; the first fan (in face order) keeps the original. Where two faces would still share an edge without being
//     joined, more of the vertex's joins are cut first.                                         -> nonmanifold_split
//  6. small components: connected components with fewer than min_component_faces faces are dropped.
//                                                                              -> small_components, removed_faces
//  7. unreferenced vertices (no kept face uses them) are dropped; vertices keep their relative order, copies made
//     by step 5 come after them.                                                                     -> unreferenced
//  8. holes (optional): boundary loops of at most max_hole_edges edges are closed with triangles (ear clipping of
//     the loop projected on its best-fit plane), only when that projection is a simple polygon and the triangles add
//     no edge the mesh has already; other holes stay open and are not counted. A component closed this way is
//     reversed if its volume is negative.                                               -> holes_filled, fill_faces
//
// Guaranteed on the output: every edge is used by one face, or by two faces in opposite directions; the faces
// around every vertex form one fan (a disk or a half-disk); no face has a repeated vertex or zero area; no two faces
// have the same vertex set; with `orient`, every closed component has a signed volume >= 0 (> 0 unless it is flat).
// Faces keep their input order (their corners start at the same vertex; a reversed face runs backwards from it),
// filled holes come last. Counts: output vertices = input - welded - unreferenced + nonmanifold_split, output faces =
// input - degenerate - duplicate - removed_faces + fill_faces. A mesh that needs nothing is returned unchanged, bit
// for bit, with every count 0 (and `components` set).
//
// Attributes: face-varying uvs travel with their corners (uv_indices follow the faces kept and reversed; filled
// triangles reuse the uvs of the boundary corners; the uvs array is kept whole). Vertex normals are carried to the
// kept vertices and their copies, and dropped when any face was reversed (they would no longer agree with the
// winding). Tags: creases and corners whose vertices survive are remapped (to the vertex a welded one merged into,
// and to the first fan's copy), others are dropped, as are creases whose ends were welded together; hole tags follow
// their faces; the boundary rule is kept.
#pragma once

#include <cstddef>

#include "geometry/core/cancel.h"
#include "geometry/core/result.h"
#include "geometry/mesh/polygon_mesh.h"

namespace surfaced {

struct RepairOptions {
    //! 0: weld only vertices with identical coordinates; > 0: also vertices within this distance (mesh units) of a
    //! lower-indexed kept vertex. Must be finite and >= 0.
    double weld_tolerance = 0;
    //! Orient each connected component consistently, outward for closed ones, reversing faces as needed. false: no
    //! face is reversed; two faces that traverse an edge in the same direction are not joined there (the edge is cut
    //! like a non-manifold one), so the output guarantees hold all the same.
    bool orient = true;
    //! Drop connected components with fewer faces than this (0: keep all).
    std::size_t min_component_faces = 0;
    //! Close holes whose boundary loop has at most this many edges (0: none). Each hole costs O(n^2) to O(n^3) in its
    //! edge count n.
    std::size_t max_hole_edges = 0;
    //! Polled between the steps; when it fires the result is Cancelled.
    Cancel cancel;
};

//! What each step did (see the steps above).
struct RepairReport {
    std::size_t welded = 0;             //!< vertices merged into another
    std::size_t degenerate = 0;         //!< faces dropped: a repeated vertex or zero area
    std::size_t duplicate = 0;          //!< faces dropped: the same vertex set as an earlier face (either winding)
    std::size_t flipped = 0;            //!< output faces reversed relative to the input
    std::size_t nonmanifold_split = 0;  //!< vertex copies made to cut non-manifold edges and vertices apart
    std::size_t small_components = 0;   //!< components dropped by min_component_faces
    std::size_t removed_faces = 0;      //!< faces of those components
    std::size_t holes_filled = 0;       //!< boundary loops closed
    std::size_t fill_faces = 0;         //!< triangles added to close them
    std::size_t unreferenced = 0;       //!< vertices dropped because no kept face uses them
    std::size_t components = 0;         //!< connected components in the output (not a change)

    //! True when the output differs from the input in any way.
    bool changed() const {
        return welded || degenerate || duplicate || flipped || nonmanifold_split || small_components || removed_faces ||
               holes_filled || fill_faces || unreferenced;
    }
};

struct RepairResult {
    PolygonMesh mesh;
    RepairReport report;
};

//! Repairs the mesh as described at the top of this file. Work and memory are linear in the size of the mesh for
//! bounded valence (a radix sort of position hashes, counting sorts of edges, union-find where faces disagree or a
//! vertex has several fans; edges of k faces cost O(k log k)), plus the holes it closes.
//! \pre validate(mesh, {.allow_repeated_vertices = true}) succeeds (checked; its error is returned).
//! \return the repaired mesh and the report, or InvalidArgument (weld_tolerance negative or not finite), or the
//!         validation error, or Cancelled.
Result<RepairResult> repair_mesh(const PolygonMesh& mesh, const RepairOptions& options = {});

//! What audit_mesh finds.
struct MeshDefects {
    std::size_t degenerate_faces = 0;      //!< a repeated vertex or zero area
    std::size_t duplicate_faces = 0;       //!< the same vertex set as an earlier face
    std::size_t nonmanifold_edges = 0;     //!< used by more than two faces
    std::size_t inconsistent_edges = 0;    //!< used by two faces in the same direction
    std::size_t nonmanifold_vertices = 0;  //!< whose faces form more than one fan
    //! Closed, consistently oriented, with a negative signed volume (beyond rounding: below -1e-9 times the sum of
    //! the faces' absolute volumes).
    std::size_t inverted_components = 0;

    //! Anything that breaks algorithms which need a manifold, consistently oriented mesh (inverted components do not).
    bool breaks_manifold() const {
        return degenerate_faces || duplicate_faces || nonmanifold_edges || inconsistent_edges || nonmanifold_vertices;
    }
};

//! Counts the defects repair_mesh removes (without welding: coincident but distinct vertices are no defect). The
//! edge and vertex counts are taken over the faces that are neither degenerate nor duplicates. Linear, like
//! repair_mesh's joining step alone. \return the counts, or validate()'s error (repeated vertices allowed).
Result<MeshDefects> audit_mesh(const PolygonMesh& mesh);

//! Whether the mesh is manifold as it is (no welding, no repair): every edge is used by one face, or by two faces in
//! opposite directions, and the faces around every vertex form one fan. The rule every operation that needs a
//! manifold mesh applies before it runs (api/operations/mesh_repair.h), so that they refuse the same meshes.
//! \pre validate(mesh) succeeds (no face repeats a vertex).
//! \return Ok, or NonManifold naming the defect, with a face at it as the error's element (ElementKind::Face; so that a
//!         caller can point at the face in a file or a JSON body): for an edge of more than two faces, its third face;
//!         for an edge two faces traverse in the same direction, the second; the edge with the lowest such face is
//!         named first, then the lowest non-manifold vertex, with the first face that uses it.
Status check_manifold(const PolygonMesh& mesh);

//! The cheap question an operation asks first: would a manifold-only algorithm trip over this mesh (any defect of
//! MeshDefects::breaks_manifold)? True also when the mesh fails validation (repair_mesh then reports why).
bool needs_repair(const PolygonMesh& mesh);

}  // namespace surfaced
