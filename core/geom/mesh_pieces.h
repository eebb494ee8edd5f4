// core/geom/mesh_pieces.h: a large mesh tessellated piece by piece (DESIGN.md steps 2 and 6a), so
// that no tile needs the triangles of the whole shape at once and threads make different pieces
// at the same time. A piece is a set of faces holding at most a given number of triangle ids,
// close together in space: the kept faces in the order of a Morton curve through their centres,
// cut into consecutive groups. On the mesh's face list a piece is a few runs of faces (on a grid
// stored row by row, one run per row it crosses). A mesh whose faces would give too many runs
// that way (faces stored in no spatial order) is cut in face order instead, one run a piece.
// Triangle ids ("slots") are those of the whole shape: face f's triangles take slots faceSlot(f)
// + 0, 1, …, one per triangle its corner count promises (n + 2h − 2, faceTriangleBound), in face
// order, so ids grow with the face and with the triangle within it exactly as in
// triangulateValidMesh's numbering, and every piece knows the ids of its neighbours' triangles
// without making them. A face whose ear clipping gives fewer triangles leaves its last slots as
// zero-area triangles that rasterize to nothing. A piece's tessellation holds its triangles in
// id order; slotRuns() says which piece and place an id has.
// A piece's tessellation is the whole shape's, cut to its triangles: the same corner positions,
// normals and uvs bit for bit, and neighbours (by slot) across piece borders too, because the
// piece is made with every face around its points.
// Thread safety: MeshPieces is immutable after split(); triangulateMeshPiece is pure.
// Memory: MeshPieces holds about 130 bytes a piece and 8 to 48 bytes a run; split() works with 12
// bytes a face and 4 bytes a point besides.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"
#include "core/geom/slot_run.h"
#include "core/geom/tessellation.h"

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace pushpin::geom {

// Consecutive faces [first, end); face `first` has the triangle ids from firstSlot on and its
// face-vertices from firstFaceVertex on.
struct FaceRun {
    uint32_t first = 0, end = 0;
    uint32_t firstSlot = 0;
    uint64_t firstFaceVertex = 0;
};

// Consecutive edges [first, end).
struct EdgeRun {
    uint32_t first = 0, end = 0;
};

struct MeshPiece {
    uint32_t slotCount = 0;  // triangle ids of its faces: its tessellation's triangles
    // Its faces: MeshPieces::faceRuns (faces in them that are not its own give no triangle ids).
    uint32_t faceRunBegin = 0, faceRunEnd = 0;
    // Runs holding every face with a corner at a point of its kept faces (and maybe others):
    // MeshPieces::aroundRuns; and runs holding every edge with an end at such a point:
    // MeshPieces::edgeRuns.
    uint32_t aroundRunBegin = 0, aroundRunEnd = 0;
    uint32_t edgeRunBegin = 0, edgeRunEnd = 0;
    // What its window (cutMeshWindow) holds: the faces of its around runs, their face-vertices,
    // the triangle ids they promise, the points and current-uv-set uvs they use, and the edges of
    // its edge runs with both ends at those points.
    uint64_t windowFaces = 0, windowFaceVertices = 0, windowTriangles = 0;
    uint64_t windowPoints = 0, windowUvs = 0, windowEdges = 0;
    Bounds3 bounds;  // of the points of its kept faces
};

// Part of a mesh, enough to make one of its pieces without the rest (cutMeshWindow): `mesh` holds
// the faces of the piece's around runs in their order, the points they use and the uvs of the
// whole mesh's current uv set they use (as its only set, current), each in ascending order of
// their index in the whole mesh, and of the edges of the piece's edge runs those with both ends
// among its points, in their order. Stored normals are kept per face-vertex as the whole mesh has
// them (no uv set when the whole mesh's current set maps no face).
struct MeshWindow {
    Mesh mesh;
    bool window = false;  // false: `mesh` is a whole mesh
};

// The points (or uvs) of a whole mesh that a window uses: their ids ascending, each once, and the
// place of each among them, which is its index in the window.
class WindowIds {
public:
    // From ids in any order, repeats allowed.
    explicit WindowIds(std::vector<uint32_t> ids) : m_ids(std::move(ids)) {
        std::sort(m_ids.begin(), m_ids.end());
        m_ids.erase(std::unique(m_ids.begin(), m_ids.end()), m_ids.end());
    }
    size_t size() const { return m_ids.size(); }
    uint32_t operator[](size_t place) const { return m_ids[place]; }
    bool contains(uint32_t id) const { return std::binary_search(m_ids.begin(), m_ids.end(), id); }
    // The place of `id`, which must be among them.
    uint32_t place(uint32_t id) const {
        return uint32_t(std::lower_bound(m_ids.begin(), m_ids.end(), id) - m_ids.begin());
    }
    // visit(first place, first id, end id) for each run of consecutive ids, in order.
    template <class Visit>
    void forEachRun(Visit&& visit) const {
        for (size_t i = 0; i < m_ids.size();) {
            size_t j = i + 1;
            while (j < m_ids.size() && m_ids[j] == m_ids[j - 1] + 1) ++j;
            visit(i, m_ids[i], uint64_t(m_ids[j - 1]) + 1);
            i = j;
        }
    }

private:
    std::vector<uint32_t> m_ids;
};

class MeshPieces {
public:
    enum class Layout {
        Spatial,    // pieces along a Morton curve, unless the faces' order makes that too many runs
        FaceOrder,  // consecutive faces
    };

    // Splits `mesh` (valid; `faceMaterial` and `degenerate` as triangulateValidMesh takes them)
    // into pieces of at most `maxSlots` triangle ids each (a single face with more takes a piece of
    // its own). Faces giving no triangles belong to no piece, and no piece is empty. The mesh must
    // have fewer than 2^31 − 1 triangle ids.
    static MeshPieces split(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                            const std::vector<bool>& degenerate, uint32_t maxSlots, Layout layout = Layout::Spatial);

    const std::vector<MeshPiece>& pieces() const { return m_pieces; }
    uint64_t slotCount() const { return m_slots; }
    // Whether the pieces follow the Morton curve (false: consecutive faces).
    bool spatial() const { return m_spatial; }
    // Whether the split mesh's current uv set maps faces (its windows then carry uv ids).
    bool mapsUvs() const { return m_mapsUvs; }
    std::span<const FaceRun> faceRuns(size_t piece) const {
        const MeshPiece& p = m_pieces[piece];
        return {m_faceRuns.data() + p.faceRunBegin, size_t(p.faceRunEnd - p.faceRunBegin)};
    }
    std::span<const FaceRun> aroundRuns(size_t piece) const {
        const MeshPiece& p = m_pieces[piece];
        return {m_aroundRuns.data() + p.aroundRunBegin, size_t(p.aroundRunEnd - p.aroundRunBegin)};
    }
    std::span<const EdgeRun> edgeRuns(size_t piece) const {
        const MeshPiece& p = m_pieces[piece];
        return {m_edgeRuns.data() + p.edgeRunBegin, size_t(p.edgeRunEnd - p.edgeRunBegin)};
    }
    // Every run of triangle ids, sorted by firstSlot (they cover [0, slotCount()) without gaps).
    const std::vector<SlotRun>& slotRuns() const { return m_slotRuns; }
    // The runs of piece `piece` in the order of its tessellation (local ascending), one per face
    // run.
    std::span<const SlotRun> pieceSlotRuns(size_t piece) const {
        const MeshPiece& p = m_pieces[piece];
        return {m_pieceSlotRuns.data() + p.faceRunBegin, size_t(p.faceRunEnd - p.faceRunBegin)};
    }
    uint64_t bytes() const;

private:
    std::vector<MeshPiece> m_pieces;
    std::vector<FaceRun> m_faceRuns, m_aroundRuns;
    std::vector<EdgeRun> m_edgeRuns;
    std::vector<SlotRun> m_slotRuns, m_pieceSlotRuns;  // the latter parallel to m_faceRuns
    uint64_t m_slots = 0;
    bool m_spatial = false;
    bool m_mapsUvs = false;
};

// The window of piece `piece` cut from the whole mesh (what a source that makes windows alone must
// give).
MeshWindow cutMeshWindow(const Mesh& mesh, const MeshPieces& pieces, size_t piece);

// The tessellation of piece `piece`: triangle i is the one of the piece's i-th triangle id
// (pieceSlotRuns; zero-area where its face made fewer triangles than it promised); `face` holds
// mesh face indices and `neighbors` slots, with kHardNeighborBit and kNoNeighbor as in a whole
// tessellation. `source` is the whole mesh, or the piece's window (the same tessellation bit for
// bit). Other arguments as MeshPieces::split took them, and `smoothShading` as
// triangulateValidMesh takes it.
Tessellation triangulateMeshPiece(const MeshWindow& source, const std::vector<uint16_t>& faceMaterial,
                                  bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                  size_t piece);
Tessellation triangulateMeshPiece(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate, const MeshPieces& pieces, size_t piece);

// Bytes triangulateMeshPiece holds while it runs besides its source and its result, for `piece`
// when the source has `sourcePoints` points (the whole mesh's, or the window's): the point map
// over the source, and the piece's own mesh (its faces and those around its points: at most the
// window's face-vertices, points and triangles) with its whole tessellation and that
// tessellation's working memory. `normals` and `uvs`: whether the mesh has stored normals and a
// current uv set that maps faces.
uint64_t meshPieceWorkBytes(const MeshPiece& piece, uint64_t sourcePoints, bool smoothShading, bool normals = true,
                            bool uvs = true);

}  // namespace pushpin::geom
