// core/geom/geometry_handle.h: one shape's renderable geometry before it has triangles (DESIGN.md
// step 2): its source (an evaluated polygon mesh with the material of each face, or a NURBS surface
// with its per-span divisions), its object-space bounds, how many triangles it will make and how
// many of them a scanline crosses at a given screen size — all known without tessellating — and
// tessellate(), which the renderer calls when a tile first needs the shape (its tessellation cache
// keeps one per handle, shared by every instance that uses the handle).
// Thread safety: immutable after creation; every method may be called from any thread at once.
// Memory: a handle shares its source (std::shared_ptr) with the other handles of the same shape
// and keeps no triangles; a MeshSource that evaluates on demand keeps no mesh either. A shape in
// pieces keeps its piece table (MeshPieces, or NurbsPieces with the surface's grid), counted in
// sourceBytes().
// sourceBytes() and tessellationBytesEstimate() are what it costs while it tessellates.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"
#include "core/geom/mesh_pieces.h"
#include "core/geom/nurbs.h"
#include "core/geom/poly_primitives.h"
#include "core/geom/tessellation.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pushpin::geom {

struct NurbsGridPieces;

// Where a handle gets its mesh when it tessellates: a mesh kept in memory, or one evaluated again
// on demand (a creator or history result, a stored mesh decoded from the scene), so that no
// mesh needs to stay resident between tessellations. Every call returns the same mesh.
// Thread safety: mesh() may be called from any thread at once.
class MeshSource {
public:
    virtual ~MeshSource() = default;
    // The mesh (never null; empty when it can no longer be made).
    virtual std::shared_ptr<const Mesh> mesh() const = 0;
    // Whether the source holds its mesh in memory all along.
    virtual bool keepsMesh() const = 0;
    // Whether window() makes the part of the mesh one piece needs without making the rest.
    virtual bool makesWindows() const { return false; }
    // The window of piece `piece` of `pieces` (MeshPieces::split of this source's mesh, which has
    // `faceVertexCount` face-vertices): cutMeshWindow of the mesh, bit for bit. nullopt when it
    // cannot be made.
    virtual std::optional<MeshWindow> window(const MeshPieces& pieces, size_t piece, uint64_t faceVertexCount) const {
        (void)pieces, (void)piece, (void)faceVertexCount;
        return std::nullopt;
    }
};

class GeometryHandle {
public:
    // A mesh that passed Mesh::validate(), with one material slot per face (kNoFaceMaterial: not
    // rendered; empty: all 0) and the faces to drop (MeshValidation::degenerateFaces, or empty).
    // The handle keeps the mesh.
    static std::shared_ptr<GeometryHandle> fromMesh(std::shared_ptr<const Mesh> mesh, std::vector<uint16_t> faceMaterial,
                                                    std::shared_ptr<const std::vector<bool>> degenerate,
                                                    bool smoothShading);
    // The same for a mesh the handle asks `source` for each time it tessellates; `mesh` is that
    // mesh, made once now for the bounds and counts and not kept. It is tessellated in pieces of
    // at most `pieceTriangles` triangle ids when it has more (pieceTrianglesFor a cap).
    static std::shared_ptr<GeometryHandle> fromMeshSource(std::shared_ptr<const MeshSource> source, const Mesh& mesh,
                                                          std::vector<uint16_t> faceMaterial,
                                                          std::shared_ptr<const std::vector<bool>> degenerate,
                                                          bool smoothShading, uint32_t pieceTriangles = kPieceTriangles);
    // A mesh not made yet: `source` makes it when the handle first tessellates, and `counts` (a
    // primitive's PrimitiveCounts) give the bounds, triangles and byte estimates until then. Every
    // face takes material 0; the mesh is validated when it is made and its degenerate faces dropped.
    static std::shared_ptr<GeometryHandle> fromMeshCounts(std::shared_ptr<const MeshSource> source,
                                                          const PrimitiveCounts& counts, bool smoothShading);
    // A NURBS surface tessellated on a uniform grid of divU × divV steps per span (material 0), in
    // rectangles of at most `pieceTriangles` triangle ids when it has more (nurbs_pieces.h).
    static std::shared_ptr<GeometryHandle> fromNurbs(std::shared_ptr<const NurbsSurface> surface, int divU, int divV,
                                                     uint32_t pieceTriangles = kPieceTriangles);

    GeometryHandle& operator=(const GeometryHandle&) = delete;

    bool isMesh() const { return m_source != nullptr; }
    // Object space, conservative: the points of the faces kept (meshes), the control hull (NURBS
    // surfaces with positive weights, which lie inside it).
    const Bounds3& bounds() const { return m_bounds; }
    // Triangles the tessellation will have at most (meshes: exact unless ear clipping gives up on
    // a face; NURBS: zero-area triangles at poles are dropped).
    uint64_t triangleCount() const { return m_triangles; }
    // Material slots used (one more than the largest faceMaterial entry kept; 1 for NURBS).
    uint32_t materialCount() const { return m_materials; }
    // Triangles one scanline crossing the object is expected to meet when its screen box is
    // `screenHeight` pixels high: the triangles spread over the box's height, each as tall as a
    // cell of a square grid of triangleCount() triangles over it, and at least one pixel row.
    double trianglesPerScanline(double screenHeight) const;
    // Vertices the tessellation is expected to have (an estimate: the points used, and some more
    // where hard edges and uv seams split them; one per grid point for NURBS).
    uint64_t vertexCountEstimate() const { return m_vertices; }
    // Bytes the tessellation will hold (an estimate from the triangle and vertex counts).
    uint64_t tessellationBytesEstimate() const;
    // Bytes tessellate() holds while it runs besides the result and the source: shading normals,
    // the edge table and the adjacency sort of a mesh, the evaluated grid of a surface.
    uint64_t tessellationWorkBytesEstimate() const { return m_workBytes; }
    // Bytes of the source (the mesh or surface), shared by the handles of one shape; for a mesh
    // made on demand, what it holds while the handle tessellates.
    uint64_t sourceBytes() const { return m_sourceBytes; }
    const std::shared_ptr<const NurbsSurface>& surface() const { return m_surface; }
    // Whether the source stays in memory (a kept mesh, a NURBS surface) rather than being made
    // only while the handle tessellates; handles sharing a source give the same sourceId().
    bool keepsSource() const { return m_surface != nullptr || m_source->keepsMesh(); }
    const void* sourceId() const { return m_surface ? static_cast<const void*>(m_surface.get()) : m_source.get(); }

    // Makes the tessellation, without keeping it. For NURBS surfaces that evaluate to
    // NaN/Inf the result is empty and `problem` (when given) says why.
    Tessellation tessellate(std::string* problem = nullptr) const;

    // A mesh (kept or made on demand, not a primitive's counts) or a NURBS surface of more than
    // kPieceTriangles triangles is tessellated in pieces of at most that many triangle ids
    // (mesh_pieces.h, nurbs_pieces.h), each made when a tile first needs it; every other shape is
    // one piece, its whole tessellation. Triangle ids are the whole shape's either way.
    static constexpr uint32_t kPieceTriangles = 1u << 18;
    // The piece size for a render under a memory cap of `capBytes` (0: none): kPieceTriangles, or
    // smaller, a power of two no smaller than 2^14, so that making one piece (its mesh window,
    // working memory and tessellation: about kPieceMakingBytes a triangle id) takes at most a
    // sixty-fourth of the cap. A tile can then make its pieces beside the scene, the frame's
    // buffers and the pieces it holds under a small cap, and a tile where a distant part of a large
    // mesh shrinks to a few pixels holds whole pieces no larger than it needs. The image does not
    // depend on the piece size.
    static constexpr uint64_t kPieceMakingBytes = 256;
    static uint32_t pieceTrianglesFor(uint64_t capBytes);
    size_t pieceCount() const;
    const Bounds3& pieceBounds(size_t k) const;
    uint64_t pieceTriangleCount(size_t k) const;
    // Where triangle ids live (MeshPieces::slotRuns; one run from 0 for a shape in one piece), and
    // the runs of piece k in the order of its tessellation.
    std::span<const SlotRun> slotRuns() const;
    std::span<const SlotRun> pieceSlotRuns(size_t k) const;
    // The pieces of a mesh (null for a NURBS surface or a shape in one piece).
    const MeshPieces* pieces() const { return m_pieces.get(); }
    // The same shape split into pieces of at most `pieceTriangles` triangle ids (0: one piece), for
    // comparing piece sizes; a primitive's counts stays one piece.
    std::shared_ptr<GeometryHandle> withPieces(uint32_t pieceTriangles) const;
    // The piece that holds triangle id `triangle` (of one of the pieces), and the triangle's index
    // in that piece's tessellation.
    struct PiecePlace {
        size_t piece = 0;
        uint32_t local = 0;
    };
    PiecePlace placeOf(uint32_t triangle) const;
    // tessellationBytesEstimate() and tessellationWorkBytesEstimate() for piece k.
    uint64_t pieceBytesEstimate(size_t k) const;
    uint64_t pieceWorkBytesEstimate(size_t k) const;
    // Makes piece k's tessellation (tessellate() for a shape in one piece): triangle i has id
    // pieceFirstTriangle(k) + i.
    Tessellation tessellatePiece(size_t k, std::string* problem = nullptr) const;
    // The same for a shape in pieces, from its mesh as makeMesh() gives it (so that one mesh serves
    // the pieces made while it is at hand).
    Tessellation tessellatePiece(size_t k, const Mesh& mesh) const;
    // The mesh of a mesh shape (made again when the source does not keep it), and the bytes it
    // holds (sourceBytes() without the piece table).
    std::shared_ptr<const Mesh> makeMesh() const { return m_source ? m_source->mesh() : nullptr; }
    uint64_t meshBytes() const { return m_sourceBytes - (m_pieces ? m_pieces->bytes() : 0); }
    // What making that mesh again holds at its peak: the mesh and the decoder's tables (a few
    // words a face and a face-vertex).
    uint64_t meshMakingBytes() const { return meshBytes() + 8 * m_meshFaces + 4 * m_meshFaceVertices; }
    // Whether each piece is made from its own window of the mesh (MeshSource::makesWindows), so
    // that the whole mesh is never made for it.
    bool makesPiecesAlone() const { return m_pieces && m_source && m_source->makesWindows(); }

private:
    GeometryHandle() = default;
    GeometryHandle(const GeometryHandle&) = default;  // withPieces() only

    void measureMesh(const Mesh& mesh);
    // The byte estimates from a mesh's counts (face-vertices, faces, points, edges) and the
    // triangles and points kept.
    void estimateMeshBytes(uint64_t faceVertices, uint64_t faces, uint64_t points, uint64_t edges, uint64_t usedPoints);

    std::shared_ptr<const MeshSource> m_source;
    std::vector<uint16_t> m_faceMaterial;
    std::shared_ptr<const std::vector<bool>> m_degenerate;
    bool m_smooth = true;
    bool m_validate = false;  // the mesh is made after the handle: validate it when tessellating
    std::shared_ptr<const NurbsSurface> m_surface;
    int m_divU = 1, m_divV = 1;
    Bounds3 m_bounds;
    uint64_t m_triangles = 0;
    uint64_t m_vertices = 0;  // estimate
    uint32_t m_materials = 1;
    uint64_t m_sourceBytes = 0;
    uint64_t m_workBytes = 0;
    uint64_t m_meshPoints = 0, m_meshFaces = 0, m_meshFaceVertices = 0;
    bool m_meshNormals = false;  // the mesh has stored normals (per face-vertex)
    uint32_t m_pieceTriangles = kPieceTriangles;
    std::shared_ptr<const MeshPieces> m_pieces;  // null: one piece
    // A NURBS surface's grid and, when it is in pieces, its piece table (null: no grid could be
    // made, m_nurbsProblem says why).
    std::shared_ptr<const NurbsGridPieces> m_nurbs;
    std::string m_nurbsProblem;
    void splitNurbs();
    // The surface's tessellation: piece `piece`'s cells, or the whole grid.
    Tessellation tessellateSurface(std::optional<size_t> piece, std::string* problem) const;
};

}  // namespace pushpin::geom
