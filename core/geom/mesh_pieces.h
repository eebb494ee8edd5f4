// core/geom/mesh_pieces.h: a large mesh tessellated piece by piece (DESIGN.md steps 2 and 6a), so
// that no tile needs the triangles of the whole shape at once and threads make different pieces
// at the same time. A piece is a run of consecutive faces holding at most a given number of
// triangle ids. Triangle ids ("slots") are those of the whole shape: face f's triangles take
// slots faceSlot(f) + 0, 1, …, one per triangle its corner count promises (n + 2h − 2,
// faceTriangleBound), in face order, so ids grow with the face and with the triangle within it
// exactly as in triangulateValidMesh's numbering and every piece knows the ids of its
// neighbours' triangles without making them. A face whose ear clipping gives fewer triangles
// leaves its last slots as zero-area triangles that rasterize to nothing.
// A piece's tessellation is the whole shape's, cut to its triangles: the same corner positions,
// normals and uvs bit for bit, and neighbours (by slot) across piece borders too, because the
// piece is made with every face around its points.
// Thread safety: MeshPieces is immutable after split(); triangulateMeshPiece is pure.
// Memory: MeshPieces holds 96 bytes a piece and 4 bytes per kSlotStride faces; split() works with
// 8 bytes a point besides.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"
#include "core/geom/tessellation.h"

#include <cstdint>
#include <vector>

namespace pushpin::geom {

struct MeshPiece {
    uint32_t firstFace = 0, endFace = 0;   // faces [firstFace, endFace)
    uint32_t firstSlot = 0, slotCount = 0;  // triangle ids [firstSlot, firstSlot + slotCount)
    // Every face with a corner at a point of the piece's kept faces lies in [aroundFirst,
    // aroundEnd), every edge with an end there in [edgeFirst, edgeEnd).
    uint32_t aroundFirst = 0, aroundEnd = 0;
    uint32_t edgeFirst = 0, edgeEnd = 0;
    uint64_t aroundFaceVertices = 0;  // face-vertices of the faces [aroundFirst, aroundEnd)
    uint64_t aroundTriangles = 0;     // the triangle ids those faces promise (kept or not)
    uint64_t aroundPoints = 0;        // the points those faces use
    // What a MeshWindow for the piece holds: the faces [windowFirst, aroundEnd) (windowFirst is
    // aroundFirst rounded down to a multiple of kSlotStride, so that the slots of every face in it
    // can be counted), whose face-vertices start at windowFirstFaceVertex and whose points and
    // current-uv-set uv ids lie in [windowPointFirst, windowPointEnd) and [windowUvFirst,
    // windowUvEnd), and the edges [edgeFirst, edgeEnd).
    uint32_t windowFirst = 0;
    uint64_t windowFirstFaceVertex = 0, windowFaceVertices = 0;
    uint32_t windowPointFirst = 0, windowPointEnd = 0;
    uint32_t windowUvFirst = 0, windowUvEnd = 0;
    uint32_t windowEdges = 0;  // edges of [edgeFirst, edgeEnd) with both ends in the window's points
    Bounds3 bounds;  // of the points of its kept faces
};

// Part of a mesh, enough to make one of its pieces without the rest: `mesh` holds the whole
// mesh's faces from faceBase, its points from pointBase and the uvs of its current uv set (as its
// only set, current) from uvBase, each numbered from its base, and of the piece's edges
// [edgeFirst, edgeEnd) those with both ends among its points, in their order. Stored normals and
// the current set's uv ids are kept per face-vertex as the whole mesh has them (no uv set when the
// whole mesh's current set maps no face).
struct MeshWindow {
    Mesh mesh;
    uint32_t faceBase = 0, pointBase = 0, uvBase = 0;
    bool window = false;  // false: `mesh` is a whole mesh (every base 0, every edge listed)
};

class MeshPieces {
public:
    // Faces between two stored slot offsets (faceSlot reads at most this many faces).
    static constexpr uint32_t kSlotStride = 64;

    // Splits `mesh` (valid; `faceMaterial` and `degenerate` as triangulateValidMesh takes them)
    // into runs of faces of at most `maxSlots` triangle ids each (a single face with more takes a
    // piece of its own). Pieces without kept faces are left out. The mesh must have fewer than
    // 2^31 − 1 triangle ids.
    static MeshPieces split(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                            const std::vector<bool>& degenerate, uint32_t maxSlots);

    const std::vector<MeshPiece>& pieces() const { return m_pieces; }
    uint64_t slotCount() const { return m_slots; }
    // Whether the split mesh's current uv set maps faces (its windows then carry uv ids).
    bool mapsUvs() const { return m_mapsUvs; }
    // The first triangle id of face `f` (`mesh` may hold the faces from `faceBase` on only, as
    // faceTriangleBound takes them, when that is a multiple of kSlotStride at or before f).
    uint32_t faceSlot(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, const std::vector<bool>& degenerate,
                      size_t f, size_t faceBase = 0) const;
    uint64_t bytes() const {
        return uint64_t(m_pieces.capacity()) * sizeof(MeshPiece) + uint64_t(m_strideSlots.capacity()) * sizeof(uint32_t);
    }

private:
    std::vector<MeshPiece> m_pieces;
    std::vector<uint32_t> m_strideSlots;  // faceSlot(k · kSlotStride)
    uint64_t m_slots = 0;
    bool m_mapsUvs = false;
};

// The tessellation of piece `piece`: triangle i is the one of slot pieces[piece].firstSlot + i
// (zero-area where its face made fewer triangles than it promised); `face` holds mesh face
// indices and `neighbors` slots, with kHardNeighborBit and kNoNeighbor as in a whole tessellation.
// Arguments as MeshPieces::split took them, and `smoothShading` as triangulateValidMesh takes it.
Tessellation triangulateMeshPiece(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate, const MeshPieces& pieces, size_t piece);

// Whether `point` of the whole mesh is among the points of the piece's window.
bool inWindow(const MeshPiece& piece, uint32_t point);

// The window of `piece` cut from the whole mesh (what a source that makes windows alone must give).
MeshWindow cutMeshWindow(const Mesh& mesh, const MeshPiece& piece);

// The same from a window holding the piece's MeshPiece window (faces, edges, points and uvs); the
// tessellation is the same bit for bit.
Tessellation triangulateMeshPiece(const MeshWindow& window, const std::vector<uint16_t>& faceMaterial,
                                  bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                  size_t piece);

// Bytes triangulateMeshPiece holds while it runs besides the mesh and its result, for `piece` of
// a mesh of `meshPoints` points: the point map over the whole mesh, and the piece's own mesh (its
// faces and those around its points: at most aroundFaceVertices face-vertices, aroundPoints points
// and aroundTriangles triangles) with its whole tessellation and that tessellation's working memory.
// `normals` and `uvs`: whether the mesh has stored normals and a current uv set that maps faces.
uint64_t meshPieceWorkBytes(const MeshPiece& piece, uint64_t meshPoints, bool smoothShading, bool normals = true,
                            bool uvs = true);

}  // namespace pushpin::geom
