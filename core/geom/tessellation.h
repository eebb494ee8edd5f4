// core/geom/tessellation.h: the triangles one shape renders with (DESIGN.md steps 2 and 6a), and
// the two ways they are made: triangulation of a polygon mesh and the uniform per-span grid of a
// NURBS surface.
// A Tessellation is indexed: vertices (position, unit normal, uv) are shared by the corners that
// have the same values, so a closed smooth mesh holds about half a vertex per triangle. Corner k
// of triangle t is vertex corners[3·t + k].
// Thread safety: the functions are pure; a finished Tessellation is read by any number of threads.
// Memory: a Tessellation owns its arrays; bytes() is what it holds on the heap, the figure the
// render's memory budget is charged with.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"
#include "core/geom/nurbs.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pushpin::geom {

// In `Tessellation::neighbors`: no triangle across this edge (a boundary, or an edge shared by
// more than two triangles).
constexpr uint32_t kNoNeighbor = 0xffffffffu;
// In `Tessellation::neighbors`: the shared edge is hard (fragments across it never merge).
constexpr uint32_t kHardNeighborBit = 0x80000000u;
// A `faceMaterial` entry for a face that is not rendered (it belongs to no shading group).
constexpr uint16_t kNoFaceMaterial = 0xffff;

struct Tessellation {
    std::vector<glm::vec3> positions;  // per vertex, object space
    std::vector<glm::vec3> normals;    // per vertex, unit, object space (smooth or faceted per hard edges)
    std::vector<glm::vec2> uvs;        // per vertex (current UV set); empty when the shape has none
    std::vector<uint32_t> corners;     // 3 per triangle: the vertex of each corner
    std::vector<uint32_t> face;        // per triangle: the Maya face (or NURBS patch) it came from
    std::vector<uint16_t> material;    // per triangle: the face's material slot
    // 3 per triangle: neighbors[3·t + k] is the triangle across edge k (corner k to corner
    // (k+1)%3), with kHardNeighborBit when the edge is hard or the materials differ; kNoNeighbor
    // on a boundary.
    std::vector<uint32_t> neighbors;
    Bounds3 bounds;                    // object space, of the vertices
    // Object-space bounds of each run of kClusterTriangles consecutive triangles (the last run may
    // be shorter), so that a tile finds the triangles it needs without testing every one.
    std::vector<Bounds3> clusterBounds;
    static constexpr size_t kClusterTriangles = 64;

    size_t triangleCount() const { return face.size(); }
    size_t vertexCount() const { return positions.size(); }
    // Corner c (= 3·t + k) of the triangle list.
    const glm::vec3& position(size_t c) const { return positions[corners[c]]; }
    const glm::vec3& normal(size_t c) const { return normals[corners[c]]; }
    glm::vec2 uv(size_t c) const { return uvs.empty() ? glm::vec2(0.0f) : uvs[corners[c]]; }
    // Heap bytes held by the arrays (their capacities).
    uint64_t bytes() const;
};

// Triangulates one mesh: ear clipping of each face's outer loop with its holes bridged in, in the
// face's best-fit plane. Normals are Mesh::shadingNormals, or face normals when `smoothShading`
// is off; uvs come from the current UV set; neighbours are triangles across an edge of the same
// face or across a soft mesh edge, flagged hard across hard edges and where `faceMaterial`
// differs. `faceMaterial` has one entry per face (empty = all 0; missing entries are 0); faces
// marked kNoFaceMaterial and degenerate faces give no triangles. With `smoothShading` off every
// edge between two faces is hard (each face has its own flat normal). Triangles wind like their
// face: counter-clockwise seen from the side the face normal points to. A mesh that fails
// Mesh::validate() (indices out of range, NaN/Inf points) gives an empty tessellation.
Tessellation triangulateMesh(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading);

// The same for a mesh that already passed Mesh::validate(); `degenerate` marks the faces to drop
// (MeshValidation::degenerateFaces), one entry per face or empty.
Tessellation triangulateValidMesh(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate);

// The number of triangles triangulateValidMesh makes of the faces kept (a face of n corners and h
// holes gives n + 2h − 2), without triangulating: exact unless ear clipping gives up on a face,
// an upper bound always.
uint64_t meshTriangleCount(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate);
// The same for face `f` alone: 0 for a face not kept.
uint32_t faceTriangleBound(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate, size_t f);
// The same when `mesh` holds face f of a whole mesh as its face `meshFace` (a MeshWindow); `f`,
// `faceMaterial` and `degenerate` count from the whole mesh's first face.
uint32_t faceTriangleBound(const Mesh& mesh, size_t meshFace, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate, size_t f);

// Fills t.neighbors of t.triangleCount() triangles from the point each corner sits on
// (`cornerPoint`, 3 per triangle): two triangles whose edges join the same two points are
// neighbours (no edge hard); edges used by one triangle or by more than two get kNoNeighbor.
void buildTriangleNeighbors(Tessellation& t, const std::vector<uint32_t>& cornerPoint);

// Fills t.bounds and t.clusterBounds from the vertices and corners.
void computeTessellationBounds(Tessellation& t);

// The vertices the triangles `triangles` of `t` use, ascending, each once.
std::vector<uint32_t> triangleVertices(const Tessellation& t, std::span<const uint32_t> triangles);
// Bytes copyTriangles gives for `triangles` triangles using `vertices` vertices of `t`.
uint64_t copiedTrianglesBytes(const Tessellation& t, size_t triangles, size_t vertices);
// Triangles `triangles` of `t` (each once, ascending) on their own: triangle i is t's triangle
// triangles[i], with its face, material and neighbours (t's triangle ids) as t has them, and its
// corners renumbered onto `vertices` (triangleVertices of them), whose positions, normals and uvs
// are t's. No bounds or clusters.
Tessellation copyTriangles(const Tessellation& t, std::span<const uint32_t> triangles,
                           std::span<const uint32_t> vertices);

// Uniform per-span grid tessellation of a NURBS surface (reference/algorithms.md §8, primary
// pass) with `divU` × `divV` steps per span (nurbs_pieces.h): positions and normals evaluated
// exactly, uvs the normalised parameters, poles given a neighbouring normal, every grid edge soft,
// seams and poles welded for adjacency, two triangles a grid cell (one of zero area keeps its id
// with its three corners on one vertex); material 0 throughout and face = the patch
// (spanU · spansV + spanV). Returns nullopt with `problem` set when the surface evaluates to
// non-finite values or has an empty parameter domain.
std::optional<Tessellation> tessellateNurbs(const NurbsSurface& surface, int divU, int divV, std::string& problem);

// The number of grid triangles tessellateNurbs makes at most: 2 per grid cell.
uint64_t nurbsTriangleCount(const NurbsSurface& surface, int divU, int divV);

}  // namespace pushpin::geom
