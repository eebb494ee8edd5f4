#include "core/geom/geometry_handle.h"

#include "core/geom/nurbs_pieces.h"

#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <mutex>

namespace pushpin::geom {

// A surface's grid (its parameters at once; its welds, which evaluate the boundary, when it is
// first tessellated, so that a surface never made costs no evaluation) and its pieces.
struct NurbsGridPieces {
    mutable NurbsGrid grid;
    std::optional<NurbsPieces> pieces;
    mutable std::once_flag weldOnce;
    mutable bool welded = false;
    mutable std::string problem;
    // The grid with its welds, or null with `why` set when the boundary evaluates to NaN/Inf.
    const NurbsGrid* withWelds(const NurbsSurface& s, std::string& why) const {
        std::call_once(weldOnce, [&] { welded = weldNurbsGrid(s, grid, problem); });
        if (!welded) why = problem;
        return welded ? &grid : nullptr;
    }
};

namespace {

// Bytes of one tessellation vertex (position, normal, uv) and of one triangle's own arrays
// (three corners, face, material, three neighbours).
constexpr uint64_t kVertexBytes = 2 * sizeof(glm::vec3) + sizeof(glm::vec2);
constexpr uint64_t kTriangleBytes = 3 * sizeof(uint32_t) + sizeof(uint32_t) + sizeof(uint16_t) + 3 * sizeof(uint32_t) +
                                    sizeof(Bounds3) / Tessellation::kClusterTriangles;

// A mesh kept in memory.
class KeptMesh final : public MeshSource {
public:
    explicit KeptMesh(std::shared_ptr<const Mesh> mesh) : m_mesh(std::move(mesh)) {}
    std::shared_ptr<const Mesh> mesh() const override { return m_mesh; }
    bool keepsMesh() const override { return true; }

private:
    std::shared_ptr<const Mesh> m_mesh;
};

// Bytes of a mesh's arrays from their lengths: points, face-vertices, loop and face starts, edges,
// uvs and uv ids.
uint64_t meshArrayBytes(uint64_t points, uint64_t faceVertices, uint64_t starts, uint64_t edges, uint64_t uvs,
                        uint64_t uvIds) {
    return points * sizeof(glm::vec3) + faceVertices * sizeof(uint32_t) + starts * sizeof(uint32_t) +
           edges * sizeof(MeshEdge) + uvs * sizeof(glm::vec2) + uvIds * sizeof(int32_t);
}

uint64_t meshArraysBytes(const Mesh& m) {
    uint64_t uvs = 0, uvIds = 0;
    for (const UvSet& s : m.uvSets) {
        uvs += s.uvs.capacity();
        uvIds += s.faceVertexUvs.capacity();
    }
    return meshArrayBytes(m.points.capacity(), m.faceVertices.capacity(),
                          m.loopStarts.capacity() + m.faceLoopStarts.capacity(), m.edges.capacity(), uvs, uvIds);
}

}  // namespace

void GeometryHandle::measureMesh(const Mesh& mesh) {
    static const std::vector<bool> kNone;
    const std::vector<bool>& drop = m_degenerate ? *m_degenerate : kNone;
    m_triangles = meshTriangleCount(mesh, m_faceMaterial, drop);
    uint32_t materials = 0;
    uint64_t usedPoints = 0;
    auto measurePoints = [&] {
        std::vector<uint8_t> used(mesh.points.size(), 0);
        for (size_t f = 0; f < mesh.faceCount(); ++f) {
            const uint16_t material = f < m_faceMaterial.size() ? m_faceMaterial[f] : uint16_t(0);
            if (material == kNoFaceMaterial || (f < drop.size() && drop[f])) continue;
            materials = std::max<uint32_t>(materials, uint32_t(material) + 1);
            for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c) {
                const uint32_t p = mesh.faceVertices[c];
                if (used[p]) continue;
                used[p] = 1;
                ++usedPoints;
                m_bounds.extend(glm::dvec3(mesh.points[p]));
            }
        }
    };
    m_meshPoints = mesh.points.size();
    m_meshFaces = mesh.faceCount();
    m_meshFaceVertices = mesh.faceVertexCount();
    m_meshNormals = mesh.normals.size() == mesh.faceVertexCount();
    if (m_pieceTriangles > 0 && m_triangles > m_pieceTriangles && m_triangles < uint64_t(kHardNeighborBit) - 1) {
        // The piece table and the points used read the mesh side by side (isolated: a thread
        // waiting here takes no other work of its caller's).
        tbb::this_task_arena::isolate([&] {
            tbb::parallel_invoke(measurePoints, [&] {
                m_pieces = std::make_shared<const MeshPieces>(
                    MeshPieces::split(mesh, m_faceMaterial, drop, m_pieceTriangles));
            });
        });
    } else {
        measurePoints();
    }
    m_materials = std::max<uint32_t>(materials, 1);
    m_sourceBytes = meshArraysBytes(mesh) + m_faceMaterial.capacity() * sizeof(uint16_t) + (m_pieces ? m_pieces->bytes() : 0);
    estimateMeshBytes(mesh.faceVertexCount(), mesh.faceCount(), mesh.points.size(), mesh.edges.size(), usedPoints);
}

void GeometryHandle::estimateMeshBytes(uint64_t fv, uint64_t faces, uint64_t points, uint64_t edges, uint64_t usedPoints) {
    // Hard edges and uv seams split some points into several vertices.
    m_vertices = usedPoints + usedPoints / 8;
    // The peak of triangulateValidMesh's working memory, phase by phase (bytes per face-vertex fv,
    // face F, point P, edge E, triangle T): smooth shading normals (corner faces, face areas and
    // corner sets throughout; first the edge smoothness table and the half-edges by point, then
    // the corners by point and the normals); the corner loop (normals, corner points, vertex
    // chains); the adjacency (corner points, edge uses by point, the smoothness table again).
    const uint64_t t = m_triangles;
    const uint64_t normalsPhase =
        m_smooth ? std::max(16 * fv + 24 * faces + 8 * points + 5 * edges, 24 * fv + 24 * faces + 4 * points) : 0;
    const uint64_t cornerPhase = (m_smooth ? 12 * fv : 0) + 24 * t + 4 * points;
    const uint64_t adjacencyPhase = 24 * t + 4 * points + (m_smooth ? 4 * points + 5 * edges : 0);
    m_workBytes = std::max({normalsPhase, cornerPhase, adjacencyPhase});
}

std::shared_ptr<GeometryHandle> GeometryHandle::fromMesh(std::shared_ptr<const Mesh> mesh,
                                                         std::vector<uint16_t> faceMaterial,
                                                         std::shared_ptr<const std::vector<bool>> degenerate,
                                                         bool smoothShading) {
    const Mesh& m = *mesh;
    return fromMeshSource(std::make_shared<KeptMesh>(std::move(mesh)), m, std::move(faceMaterial),
                          std::move(degenerate), smoothShading);
}

std::shared_ptr<GeometryHandle> GeometryHandle::fromMeshSource(std::shared_ptr<const MeshSource> source,
                                                               const Mesh& mesh, std::vector<uint16_t> faceMaterial,
                                                               std::shared_ptr<const std::vector<bool>> degenerate,
                                                               bool smoothShading, uint32_t pieceTriangles) {
    std::shared_ptr<GeometryHandle> h(new GeometryHandle());
    h->m_faceMaterial = std::move(faceMaterial);
    h->m_degenerate = std::move(degenerate);
    h->m_smooth = smoothShading;
    h->m_pieceTriangles = pieceTriangles;
    h->measureMesh(mesh);
    h->m_source = std::move(source);
    return h;
}

uint32_t GeometryHandle::pieceTrianglesFor(uint64_t capBytes) {
    uint32_t n = kPieceTriangles;
    if (capBytes == 0) return n;
    while (n > (1u << 14) && uint64_t(n) * kPieceMakingBytes > capBytes / 64) n /= 2;
    return n;
}

std::shared_ptr<GeometryHandle> GeometryHandle::fromMeshCounts(std::shared_ptr<const MeshSource> source,
                                                               const PrimitiveCounts& counts, bool smoothShading) {
    std::shared_ptr<GeometryHandle> h(new GeometryHandle());
    h->m_smooth = smoothShading;
    h->m_validate = true;
    h->m_bounds = counts.bounds;
    h->m_triangles = counts.triangles;
    h->m_materials = 1;
    // What the made mesh will hold (one loop per face).
    h->m_sourceBytes = meshArrayBytes(counts.points, counts.faceVertices, 2 * (counts.faces + 1), counts.edges,
                                      counts.uvs, counts.uvs > 0 ? counts.faceVertices : 0);
    h->estimateMeshBytes(counts.faceVertices, counts.faces, counts.points, counts.edges, counts.points);
    h->m_meshPoints = counts.points;
    h->m_meshFaces = counts.faces;
    h->m_meshFaceVertices = counts.faceVertices;
    h->m_source = std::move(source);
    return h;
}

std::shared_ptr<GeometryHandle> GeometryHandle::fromNurbs(std::shared_ptr<const NurbsSurface> surface, int divU,
                                                          int divV, uint32_t pieceTriangles) {
    std::shared_ptr<GeometryHandle> h(new GeometryHandle());
    h->m_divU = std::max(divU, 1);
    h->m_divV = std::max(divV, 1);
    h->m_bounds = surface->bounds();
    h->m_triangles = nurbsTriangleCount(*surface, h->m_divU, h->m_divV);
    h->m_vertices = h->m_triangles / 2 + 1;
    h->m_pieceTriangles = pieceTriangles;
    h->m_surface = std::move(surface);
    h->splitNurbs();
    return h;
}

namespace {

// What tessellateNurbsCells holds while it makes `cells` besides its result: the positions of the
// points it evaluates; the normals, shading normals and vertex map of its own; and for each
// triangle it looks at for adjacency its slot, corner points (twice, one copy sorted) and
// neighbours, and the edge uses buildTriangleNeighbors files.
uint64_t nurbsCellsWorkBytes(const NurbsGrid& g, const NurbsCells& cells) {
    const NurbsCellsWork w = nurbsCellsWork(g, cells);
    return w.points * (3 * sizeof(glm::dvec3) + sizeof(uint32_t)) + w.triangles * (4 + 3 * 4 * 2 + 3 * 4 + 3 * 8);
}

}  // namespace

void GeometryHandle::splitNurbs() {
    m_nurbs.reset();
    m_sourceBytes = uint64_t(m_surface->cvs().capacity()) * sizeof(glm::dvec4);
    std::optional<NurbsGrid> grid = nurbsGridParameters(*m_surface, m_divU, m_divV, m_nurbsProblem);
    if (!grid) {
        m_workBytes = 0;
        return;
    }
    auto made = std::make_shared<NurbsGridPieces>();
    made->grid = std::move(*grid);
    const NurbsGrid& g = made->grid;
    if (m_pieceTriangles >= 2 && m_triangles > m_pieceTriangles && m_triangles < uint64_t(kHardNeighborBit) - 1)
        made->pieces = NurbsPieces::split(*m_surface, g, m_pieceTriangles);
    m_sourceBytes += uint64_t(g.us.capacity() + g.vs.capacity()) * sizeof(double) +
                     uint64_t(g.spanOfU.capacity() + g.spanOfV.capacity()) * sizeof(uint32_t) +
                     uint64_t(2 * (g.us.size() + g.vs.size())) * 2 * sizeof(uint32_t) +  // the welds, at most
                     (made->pieces ? made->pieces->bytes() : 0);
    m_workBytes = nurbsCellsWorkBytes(g, g.allCells());
    m_nurbs = std::move(made);
}

size_t GeometryHandle::pieceCount() const {
    if (m_pieces) return m_pieces->pieces().size();
    if (m_nurbs && m_nurbs->pieces) return m_nurbs->pieces->pieces().size();
    return 1;
}

const Bounds3& GeometryHandle::pieceBounds(size_t k) const {
    if (m_pieces) return m_pieces->pieces()[k].bounds;
    if (m_nurbs && m_nurbs->pieces) return m_nurbs->pieces->pieces()[k].bounds;
    return m_bounds;
}

uint64_t GeometryHandle::pieceTriangleCount(size_t k) const {
    if (m_pieces) return m_pieces->pieces()[k].slotCount;
    if (m_nurbs && m_nurbs->pieces) return 2 * m_nurbs->pieces->pieces()[k].cells.count();
    return m_triangles;
}

double GeometryHandle::trianglesPerScanline(double screenHeight) const {
    const double triangles = double(m_triangles);
    if (triangles <= 0.0) return 0.0;
    if (!(screenHeight > 1.0)) return triangles;
    // A square grid of T triangles has sqrt(T / 2) rows of cells; a scanline meets the triangles
    // of every row whose height range holds it: T · (cell height + 1 row) / box height.
    const double rows = std::sqrt(triangles * 0.5);
    const double cellHeight = screenHeight / std::max(rows, 1.0);
    return std::min(triangles, triangles * (cellHeight + 1.0) / screenHeight);
}

uint64_t GeometryHandle::tessellationBytesEstimate() const {
    return m_vertices * kVertexBytes + m_triangles * kTriangleBytes;
}

std::shared_ptr<GeometryHandle> GeometryHandle::withPieces(uint32_t pieceTriangles) const {
    std::shared_ptr<GeometryHandle> h(new GeometryHandle(*this));
    h->m_pieceTriangles = pieceTriangles;
    if (m_source && !m_validate) {
        h->m_pieces.reset();
        h->m_bounds = Bounds3();
        h->measureMesh(*m_source->mesh());
    }
    if (m_surface) h->splitNurbs();
    return h;
}

namespace {

const SlotRun kOneRun{};

}  // namespace

std::span<const SlotRun> GeometryHandle::slotRuns() const {
    if (m_pieces) return m_pieces->slotRuns();
    if (m_nurbs && m_nurbs->pieces) return m_nurbs->pieces->slotRuns();
    return {&kOneRun, 1};
}

std::span<const SlotRun> GeometryHandle::pieceSlotRuns(size_t k) const {
    if (m_pieces) return m_pieces->pieceSlotRuns(k);
    if (m_nurbs && m_nurbs->pieces) return m_nurbs->pieces->pieceSlotRuns(k);
    return {&kOneRun, 1};
}

GeometryHandle::PiecePlace GeometryHandle::placeOf(uint32_t triangle) const {
    if (pieceCount() == 1) return {0, triangle};
    const std::span<const SlotRun> runs = slotRuns();
    const SlotRun* r = findSlotRun(runs.data(), runs.size(), triangle);
    if (!r) return {0, 0};
    return {r->piece, r->local + (triangle - r->firstSlot)};
}

uint64_t GeometryHandle::pieceBytesEstimate(size_t k) const {
    if (m_nurbs && m_nurbs->pieces) {
        const NurbsCells& c = m_nurbs->pieces->pieces()[k].cells;
        const uint64_t vertices = uint64_t(c.i1 - c.i0 + 1) * uint64_t(c.j1 - c.j0 + 1);
        return vertices * kVertexBytes + 2 * c.count() * kTriangleBytes;
    }
    if (!m_pieces) return tessellationBytesEstimate();
    // The piece's share of the vertices, and a tenth more for those its borders repeat.
    const uint64_t slots = m_pieces->pieces()[k].slotCount;
    const uint64_t vertices = uint64_t(double(m_vertices) * double(slots) / double(std::max<uint64_t>(m_triangles, 1)) * 1.1) + 64;
    return vertices * kVertexBytes + slots * kTriangleBytes;
}

uint64_t GeometryHandle::pieceWorkBytesEstimate(size_t k) const {
    if (m_nurbs && m_nurbs->pieces) return nurbsCellsWorkBytes(m_nurbs->grid, m_nurbs->pieces->pieces()[k].cells);
    if (!m_pieces) return m_workBytes;
    const MeshPiece& p = m_pieces->pieces()[k];
    if (!makesPiecesAlone()) return meshPieceWorkBytes(p, m_meshPoints, m_smooth, m_meshNormals, m_pieces->mapsUvs());
    // The window (its points, face-vertices with normals and uv ids, loop and face starts, edges
    // and uvs) with what making it holds at its peak (the point and uv ids it gathers, sorted),
    // and the piece made from it, whose point map covers the window's points.
    const uint64_t faceVertices = p.windowFaceVertices;
    const uint64_t window = meshArrayBytes(p.windowPoints, faceVertices, 2 * (p.windowFaces + 1), p.windowEdges,
                                           p.windowUvs, m_pieces->mapsUvs() ? faceVertices : 0) +
                            (m_meshNormals ? faceVertices * sizeof(glm::vec3) : 0);
    const uint64_t gathering = 2 * faceVertices * sizeof(uint32_t);
    return window + gathering + meshPieceWorkBytes(p, p.windowPoints, m_smooth, m_meshNormals, m_pieces->mapsUvs());
}

Tessellation GeometryHandle::tessellatePiece(size_t k, std::string* problem) const {
    if (m_nurbs && m_nurbs->pieces) return tessellateSurface(k, problem);
    if (!m_pieces) return tessellate(problem);
    if (makesPiecesAlone()) {
        static const std::vector<bool> kNone;
        std::optional<MeshWindow> window = m_source->window(*m_pieces, k, m_meshFaceVertices);
        if (window)
            return triangulateMeshPiece(*window, m_faceMaterial, m_smooth, m_degenerate ? *m_degenerate : kNone,
                                        *m_pieces, k);
    }
    return tessellatePiece(k, *m_source->mesh());
}

Tessellation GeometryHandle::tessellatePiece(size_t k, const Mesh& mesh) const {
    static const std::vector<bool> kNone;
    // A mesh that can no longer be made as it was measured (an empty one) gives no triangles.
    if (!m_pieces || mesh.faceCount() != m_meshFaces || mesh.points.size() != m_meshPoints) return {};
    return triangulateMeshPiece(mesh, m_faceMaterial, m_smooth, m_degenerate ? *m_degenerate : kNone, *m_pieces, k);
}

Tessellation GeometryHandle::tessellate(std::string* problem) const {
    if (m_source) {
        static const std::vector<bool> kNone;
        const std::shared_ptr<const Mesh> mesh = m_source->mesh();
        if (m_validate) return triangulateMesh(*mesh, m_faceMaterial, m_smooth);
        return triangulateValidMesh(*mesh, m_faceMaterial, m_smooth, m_degenerate ? *m_degenerate : kNone);
    }
    if (m_surface) return tessellateSurface(std::nullopt, problem);
    return {};
}

Tessellation GeometryHandle::tessellateSurface(std::optional<size_t> piece, std::string* problem) const {
    std::string why = m_nurbsProblem;
    if (m_nurbs)
        if (const NurbsGrid* g = m_nurbs->withWelds(*m_surface, why)) {
            const NurbsCells cells = piece ? m_nurbs->pieces->pieces()[*piece].cells : g->allCells();
            if (std::optional<Tessellation> t = tessellateNurbsCells(*m_surface, *g, cells, why)) return std::move(*t);
        }
    if (problem) *problem = why;
    return {};
}

}  // namespace pushpin::geom
