#include "core/geom/mesh_pieces.h"

#include "core/util/release.h"

#include <algorithm>
#include <limits>

namespace pushpin::geom {

namespace {

constexpr uint32_t kNotLocal = 0xffffffffu;

}  // namespace

bool inWindow(const MeshPiece& piece, uint32_t point) {
    return point >= piece.windowPointFirst && point < piece.windowPointEnd;
}

MeshPieces MeshPieces::split(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                             const std::vector<bool>& degenerate, uint32_t maxSlots) {
    MeshPieces out;
    maxSlots = std::max<uint32_t>(maxSlots, 1);
    const size_t faces = mesh.faceCount();
    out.m_strideSlots.reserve(faces / kSlotStride + 1);
    MeshPiece current;
    bool kept = false;
    uint64_t slot = 0;
    auto close = [&](uint32_t end) {
        current.endFace = end;
        if (kept) out.m_pieces.push_back(current);
        current = MeshPiece{};
        current.firstFace = end;
        current.firstSlot = uint32_t(slot);
        kept = false;
    };
    for (size_t f = 0; f < faces; ++f) {
        if (f % kSlotStride == 0) out.m_strideSlots.push_back(uint32_t(slot));
        const uint32_t n = faceTriangleBound(mesh, faceMaterial, degenerate, f);
        if (n == 0) continue;
        if (current.slotCount > 0 && uint64_t(current.slotCount) + n > maxSlots) close(uint32_t(f));
        if (!kept) {
            // A piece starts at its first kept face.
            current.firstFace = uint32_t(f);
            current.firstSlot = uint32_t(slot);
        }
        kept = true;
        current.slotCount += n;
        slot += n;
        for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c)
            current.bounds.extend(glm::dvec3(mesh.points[mesh.faceVertices[c]]));
    }
    close(uint32_t(faces));
    out.m_slots = slot;

    // The faces and edges around each piece: per point the first and last face (then edge) that
    // uses it, gathered over the points of the piece's kept faces.
    std::vector<uint32_t> first(mesh.points.size()), last(mesh.points.size());
    auto overPiecePoints = [&](const MeshPiece& p, auto&& visit) {
        for (uint32_t f = p.firstFace; f < p.endFace; ++f)
            if (faceTriangleBound(mesh, faceMaterial, degenerate, f) > 0)
                for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c) visit(mesh.faceVertices[c]);
    };
    std::fill(first.begin(), first.end(), kNotLocal);
    std::fill(last.begin(), last.end(), 0u);
    for (size_t f = 0; f < faces; ++f)
        for (uint32_t c = mesh.faceVertexBegin(f); c < mesh.faceVertexEnd(f); ++c) {
            const uint32_t p = mesh.faceVertices[c];
            first[p] = std::min(first[p], uint32_t(f));
            last[p] = uint32_t(f);
        }
    for (MeshPiece& p : out.m_pieces) {
        p.aroundFirst = p.firstFace;
        p.aroundEnd = p.endFace;
        overPiecePoints(p, [&](uint32_t q) {
            p.aroundFirst = std::min(p.aroundFirst, first[q]);
            p.aroundEnd = std::max(p.aroundEnd, last[q] + 1);
        });
        p.aroundFaceVertices = mesh.faceVertexBegin(p.aroundEnd) - mesh.faceVertexBegin(p.aroundFirst);
        // n + 2h − 2 a face: face-vertices, twice the loops, less four times the faces.
        const uint64_t loops = mesh.faceLoopStarts[p.aroundEnd] - mesh.faceLoopStarts[p.aroundFirst];
        p.aroundTriangles = p.aroundFaceVertices + 2 * loops - std::min<uint64_t>(p.aroundFaceVertices + 2 * loops,
                                                                                  4 * uint64_t(p.aroundEnd - p.aroundFirst));
    }
    // The points of each piece's surrounding faces, counted with a stamp per point.
    std::fill(first.begin(), first.end(), kNotLocal);
    for (size_t k = 0; k < out.m_pieces.size(); ++k) {
        MeshPiece& p = out.m_pieces[k];
        for (uint32_t c = mesh.faceVertexBegin(p.aroundFirst); c < mesh.faceVertexBegin(p.aroundEnd); ++c) {
            uint32_t& stamp = first[mesh.faceVertices[c]];
            if (stamp != uint32_t(k)) {
                stamp = uint32_t(k);
                ++p.aroundPoints;
            }
        }
    }
    // Each piece's window: its faces from a stride start, their first face-vertex, and the range
    // of the points and current-set uv ids they use.
    const UvSet* uvSet = currentFaceUvSet(mesh);
    out.m_mapsUvs = uvSet != nullptr;
    for (MeshPiece& p : out.m_pieces) {
        p.windowFirst = p.aroundFirst - p.aroundFirst % kSlotStride;
        p.windowFirstFaceVertex = mesh.faceVertexBegin(p.windowFirst);
        p.windowFaceVertices = mesh.faceVertexBegin(p.aroundEnd) - p.windowFirstFaceVertex;
        uint32_t lo = kNotLocal, hi = 0, uvLo = kNotLocal, uvHi = 0;
        for (uint32_t c = mesh.faceVertexBegin(p.windowFirst); c < mesh.faceVertexBegin(p.aroundEnd); ++c) {
            lo = std::min(lo, mesh.faceVertices[c]);
            hi = std::max(hi, mesh.faceVertices[c] + 1);
            if (uvSet && uvSet->faceVertexUvs[c] >= 0) {
                uvLo = std::min(uvLo, uint32_t(uvSet->faceVertexUvs[c]));
                uvHi = std::max(uvHi, uint32_t(uvSet->faceVertexUvs[c]) + 1);
            }
        }
        p.windowPointFirst = lo < hi ? lo : 0;
        p.windowPointEnd = hi;
        p.windowUvFirst = uvLo < uvHi ? uvLo : 0;
        p.windowUvEnd = uvHi;
    }

    std::fill(first.begin(), first.end(), kNotLocal);
    std::fill(last.begin(), last.end(), 0u);
    const size_t points = mesh.points.size();
    for (size_t e = 0; e < mesh.edges.size(); ++e)
        for (uint32_t q : {mesh.edges[e].v0, mesh.edges[e].v1})
            if (q < points) {
                first[q] = std::min(first[q], uint32_t(e));
                last[q] = uint32_t(e) + 1;
            }
    for (MeshPiece& p : out.m_pieces) {
        p.edgeFirst = uint32_t(mesh.edges.size());
        p.edgeEnd = 0;
        overPiecePoints(p, [&](uint32_t q) {
            if (first[q] == kNotLocal) return;
            p.edgeFirst = std::min(p.edgeFirst, first[q]);
            p.edgeEnd = std::max(p.edgeEnd, last[q]);
        });
        if (p.edgeEnd < p.edgeFirst) p.edgeFirst = p.edgeEnd = 0;
        for (uint32_t e = p.edgeFirst; e < p.edgeEnd; ++e)
            p.windowEdges += inWindow(p, mesh.edges[e].v0) && inWindow(p, mesh.edges[e].v1);
    }
    return out;
}

uint32_t MeshPieces::faceSlot(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                              const std::vector<bool>& degenerate, size_t f, size_t faceBase) const {
    uint32_t slot = m_strideSlots[f / kSlotStride];
    for (size_t g = f - f % kSlotStride; g < f; ++g) slot += faceTriangleBound(mesh, faceMaterial, degenerate, g, faceBase);
    return slot;
}

uint64_t meshPieceWorkBytes(const MeshPiece& piece, uint64_t meshPoints, bool smoothShading, bool normals, bool uvs) {
    const uint64_t fv = piece.aroundFaceVertices, points = piece.aroundPoints, t = piece.aroundTriangles;
    const uint64_t faces = piece.aroundEnd - piece.aroundFirst;
    // The point map; the piece's mesh (points, face-vertices with their normals and uv ids, loop
    // and face starts, edges, uvs, and the uv map as large as the uvs); its tessellation (vertices
    // of position, normal and uv; corners, face, material, neighbours, cluster bounds); the
    // slot and vertex maps.
    const uint64_t pointMap = meshPoints * sizeof(uint32_t);
    const uint64_t uvBytes = uvs ? 2 * sizeof(glm::vec2) + sizeof(int32_t) : 0;
    const uint64_t mesh = points * (sizeof(glm::vec3) + 3 * sizeof(MeshEdge) + uvBytes) +
                          fv * (sizeof(uint32_t) + (uvs ? sizeof(int32_t) : 0) + (normals ? sizeof(glm::vec3) : 0)) +
                          2 * (faces + 1) * sizeof(uint32_t);
    const uint64_t vertices = points + points / 8;
    const uint64_t tessellation = vertices * (uvs ? 32 : 24) + t * (7 * sizeof(uint32_t) + sizeof(uint16_t) + 1);
    // triangulateValidMesh's working memory, phase by phase (GeometryHandle's estimate).
    const uint64_t edges = 3 * points;
    const uint64_t normalsPhase =
        smoothShading ? std::max(16 * fv + 24 * faces + 8 * points + 5 * edges, 24 * fv + 24 * faces + 4 * points) : 0;
    const uint64_t cornerPhase = (smoothShading ? 12 * fv : 0) + 24 * t + 4 * points;
    const uint64_t adjacencyPhase = 24 * t + 4 * points + (smoothShading ? 4 * points + 5 * edges : 0);
    const uint64_t maps = vertices * sizeof(uint32_t) + 2 * faces * sizeof(uint32_t);
    return pointMap + mesh + tessellation + std::max({normalsPhase, cornerPhase, adjacencyPhase}) + maps;
}

MeshWindow cutMeshWindow(const Mesh& mesh, const MeshPiece& piece) {
    MeshWindow w;
    w.window = true;
    w.faceBase = piece.windowFirst;
    w.pointBase = piece.windowPointFirst;
    w.uvBase = piece.windowUvFirst;
    Mesh& m = w.mesh;
    m.points.assign(mesh.points.begin() + piece.windowPointFirst, mesh.points.begin() + piece.windowPointEnd);
    const uint32_t loop0 = mesh.faceLoopStarts[piece.windowFirst], loopEnd = mesh.faceLoopStarts[piece.aroundEnd];
    const uint32_t fv0 = mesh.loopStarts[loop0], fvEnd = mesh.loopStarts[loopEnd];
    m.faceLoopStarts.clear();
    for (uint32_t f = piece.windowFirst; f <= piece.aroundEnd; ++f) m.faceLoopStarts.push_back(mesh.faceLoopStarts[f] - loop0);
    m.loopStarts.clear();
    for (uint32_t l = loop0; l <= loopEnd; ++l) m.loopStarts.push_back(mesh.loopStarts[l] - fv0);
    m.faceVertices.reserve(fvEnd - fv0);
    for (uint32_t c = fv0; c < fvEnd; ++c) m.faceVertices.push_back(mesh.faceVertices[c] - piece.windowPointFirst);
    if (mesh.normals.size() == mesh.faceVertexCount())
        m.normals.assign(mesh.normals.begin() + fv0, mesh.normals.begin() + fvEnd);
    if (const UvSet* from = currentFaceUvSet(mesh)) {
        UvSet set;
        set.name = from->name;
        set.uvs.assign(from->uvs.begin() + piece.windowUvFirst, from->uvs.begin() + piece.windowUvEnd);
        set.faceVertexUvs.reserve(fvEnd - fv0);
        for (uint32_t c = fv0; c < fvEnd; ++c) {
            const int32_t id = from->faceVertexUvs[c];
            set.faceVertexUvs.push_back(id >= 0 ? id - int32_t(piece.windowUvFirst) : -1);
        }
        m.uvSets.push_back(std::move(set));
        m.currentUvSet = 0;
    }
    m.edges.reserve(piece.windowEdges);
    for (uint32_t e = piece.edgeFirst; e < piece.edgeEnd; ++e) {
        const MeshEdge& edge = mesh.edges[e];
        if (inWindow(piece, edge.v0) && inWindow(piece, edge.v1))
            m.edges.push_back({edge.v0 - piece.windowPointFirst, edge.v1 - piece.windowPointFirst, edge.smooth});
    }
    return w;
}

namespace {

// triangulateMeshPiece on `mesh`: a whole mesh, or the window `base` describes (base.window).
// Faces are named by their whole-mesh index below.
Tessellation triangulatePieceIn(const Mesh& mesh, const MeshWindow& base, const std::vector<uint16_t>& faceMaterial,
                                bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                size_t pieceIndex) {
    const MeshPiece& piece = pieces.pieces()[pieceIndex];
    const uint32_t faceBase = base.faceBase;
    auto bound = [&](size_t f) { return faceTriangleBound(mesh, faceMaterial, degenerate, f, faceBase); };
    auto keptFace = [&](size_t f) { return bound(f) > 0; };
    auto fvBegin = [&](size_t f) { return mesh.faceVertexBegin(f - faceBase); };
    auto fvEnd = [&](size_t f) { return mesh.faceVertexEnd(f - faceBase); };

    // The points of the piece's kept faces, marked; then every face with a corner at a marked point
    // (the piece's faces among them), in face order: the piece's own mesh. Every face around a
    // marked point is in it, so the smoothing groups and sums at those points, and the triangles
    // across the edges of the piece's triangles, are the whole mesh's.
    std::vector<uint32_t> local(mesh.points.size(), kNotLocal);
    constexpr uint32_t kMarked = kNotLocal - 1;
    for (size_t f = piece.firstFace; f < piece.endFace; ++f)
        if (keptFace(f))
            for (uint32_t c = fvBegin(f); c < fvEnd(f); ++c) local[mesh.faceVertices[c]] = kMarked;
    std::vector<uint32_t> subFaces;
    for (size_t f = piece.aroundFirst; f < piece.aroundEnd; ++f) {
        bool touches = f >= piece.firstFace && f < piece.endFace;
        for (uint32_t c = fvBegin(f); c < fvEnd(f) && !touches; ++c)
            touches = local[mesh.faceVertices[c]] == kMarked;
        if (touches) subFaces.push_back(uint32_t(f));
    }
    // Local point ids in ascending global order.
    for (uint32_t f : subFaces)
        for (uint32_t c = fvBegin(f); c < fvEnd(f); ++c)
            if (local[mesh.faceVertices[c]] == kNotLocal) local[mesh.faceVertices[c]] = kMarked;
    Mesh sub;
    std::vector<uint32_t> globalPoint;
    for (size_t p = 0; p < local.size(); ++p)
        if (local[p] == kMarked) {
            local[p] = uint32_t(globalPoint.size());
            globalPoint.push_back(uint32_t(p));
        }
    sub.points.reserve(globalPoint.size());
    for (uint32_t p : globalPoint) sub.points.push_back(mesh.points[p]);

    const UvSet* uvSet = currentFaceUvSet(mesh);
    std::vector<int32_t> localUv;
    if (uvSet) {
        sub.uvSets.resize(1);
        sub.uvSets[0].name = uvSet->name;
        localUv.assign(uvSet->uvs.size(), -1);
    }
    const bool explicitNormals = mesh.normals.size() == mesh.faceVertexCount();
    std::vector<uint16_t> subMaterial;
    std::vector<bool> subDegenerate;
    subMaterial.reserve(subFaces.size());
    subDegenerate.reserve(subFaces.size());
    sub.loopStarts.clear();
    sub.faceLoopStarts.clear();
    for (uint32_t f : subFaces) {
        sub.faceLoopStarts.push_back(uint32_t(sub.loopStarts.size()));
        for (uint32_t l = mesh.faceLoopStarts[f - faceBase]; l < mesh.faceLoopStarts[f - faceBase + 1]; ++l) {
            sub.loopStarts.push_back(uint32_t(sub.faceVertices.size()));
            for (uint32_t c = mesh.loopStarts[l]; c < mesh.loopStarts[l + 1]; ++c) {
                sub.faceVertices.push_back(local[mesh.faceVertices[c]]);
                if (explicitNormals) sub.normals.push_back(mesh.normals[c]);
                if (uvSet) {
                    const int32_t id = uvSet->faceVertexUvs[c];
                    if (id >= 0 && localUv[size_t(id)] < 0) {
                        localUv[size_t(id)] = int32_t(sub.uvSets[0].uvs.size());
                        sub.uvSets[0].uvs.push_back(uvSet->uvs[size_t(id)]);
                    }
                    sub.uvSets[0].faceVertexUvs.push_back(id >= 0 ? localUv[size_t(id)] : -1);
                }
            }
        }
        subMaterial.push_back(f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0));
        subDegenerate.push_back(f < degenerate.size() && degenerate[f]);
    }
    sub.loopStarts.push_back(uint32_t(sub.faceVertices.size()));
    sub.faceLoopStarts.push_back(uint32_t(sub.loopStarts.size() - 1));
    util::release(localUv);
    // The mesh's edges between points of the piece's mesh, in their order (the last listing of an
    // edge decides its smoothness, as in the whole mesh). Those that matter have an end at a point
    // of the piece's kept faces, so they lie in the piece's edge range.
    const uint32_t edgeFirst = base.window ? 0 : piece.edgeFirst;
    const uint32_t edgeEnd = base.window ? uint32_t(mesh.edges.size()) : piece.edgeEnd;
    for (uint32_t k = edgeFirst; k < edgeEnd; ++k) {
        const MeshEdge& e = mesh.edges[k];
        if (e.v0 < local.size() && e.v1 < local.size() && local[e.v0] != kNotLocal && local[e.v1] != kNotLocal)
            sub.edges.push_back({local[e.v0], local[e.v1], e.smooth});
    }
    util::release(local);

    Tessellation whole = triangulateValidMesh(sub, subMaterial, smoothShading, subDegenerate);

    // Triangle ranges per local face (triangles come in face order), and the slot of each face.
    const size_t subFaceCount = subFaces.size();
    std::vector<uint32_t> firstTriangle(subFaceCount + 1, 0);
    for (uint32_t lf : whole.face) ++firstTriangle[lf + 1];
    for (size_t lf = 0; lf < subFaceCount; ++lf) firstTriangle[lf + 1] += firstTriangle[lf];
    std::vector<uint32_t> faceSlot(subFaceCount);
    size_t ownBegin = subFaceCount, ownEnd = 0;  // the piece's faces among the local ones
    {
        uint32_t slot = piece.firstSlot;
        for (size_t lf = 0; lf < subFaceCount; ++lf) {
            const uint32_t f = subFaces[lf];
            if (f >= piece.firstFace && f < piece.endFace) {
                ownBegin = std::min(ownBegin, lf);
                ownEnd = lf + 1;
                faceSlot[lf] = slot;
                slot += bound(f);
            } else {
                faceSlot[lf] = pieces.faceSlot(mesh, faceMaterial, degenerate, f, faceBase);
            }
        }
    }
    auto slotOf = [&](uint32_t t) {
        const uint32_t lf = whole.face[t];
        return faceSlot[lf] + (t - firstTriangle[lf]);
    };

    // The piece's triangles in slot order, their vertices renumbered in order of first use, and
    // a zero-area triangle for each slot its face left unused.
    Tessellation out;
    out.corners.reserve(3 * size_t(piece.slotCount));
    out.face.reserve(piece.slotCount);
    out.material.reserve(piece.slotCount);
    out.neighbors.reserve(3 * size_t(piece.slotCount));
    std::vector<uint32_t> vertexOf(whole.positions.size(), kNotLocal);
    auto vertex = [&](uint32_t v) {
        if (vertexOf[v] == kNotLocal) {
            vertexOf[v] = uint32_t(out.positions.size());
            out.positions.push_back(whole.positions[v]);
            out.normals.push_back(whole.normals[v]);
            if (!whole.uvs.empty()) out.uvs.push_back(whole.uvs[v]);
        }
        return vertexOf[v];
    };
    for (size_t lf = ownBegin; lf < ownEnd; ++lf) {
        const uint32_t f = subFaces[lf];
        const uint32_t promised = bound(f);
        const uint32_t made = firstTriangle[lf + 1] - firstTriangle[lf];
        for (uint32_t t = firstTriangle[lf]; t < firstTriangle[lf + 1]; ++t) {
            for (int k = 0; k < 3; ++k) {
                out.corners.push_back(vertex(whole.corners[3 * size_t(t) + k]));
                const uint32_t nb = whole.neighbors[3 * size_t(t) + k];
                out.neighbors.push_back(nb == kNoNeighbor ? kNoNeighbor
                                                          : slotOf(nb & ~kHardNeighborBit) | (nb & kHardNeighborBit));
            }
            out.face.push_back(f);
            out.material.push_back(whole.material[t]);
        }
        uint32_t spare = made > 0 ? out.corners.back() : kNotLocal;
        for (uint32_t k = made; k < promised; ++k) {
            // A slot the face left unused: a point-sized triangle at one of the face's corners.
            if (spare == kNotLocal) {
                spare = uint32_t(out.positions.size());
                out.positions.push_back(mesh.points[mesh.faceOuterLoop(f - faceBase)[0]]);
                out.normals.push_back(glm::vec3(0.0f, 0.0f, 1.0f));
                if (!whole.uvs.empty()) out.uvs.push_back(glm::vec2(0.0f));
            }
            out.corners.insert(out.corners.end(), {spare, spare, spare});
            out.neighbors.insert(out.neighbors.end(), {kNoNeighbor, kNoNeighbor, kNoNeighbor});
            out.face.push_back(f);
            out.material.push_back(f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0));
        }
    }
    out.positions.shrink_to_fit();
    out.normals.shrink_to_fit();
    out.uvs.shrink_to_fit();
    computeTessellationBounds(out);
    return out;
}

}  // namespace

Tessellation triangulateMeshPiece(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate, const MeshPieces& pieces, size_t piece) {
    return triangulatePieceIn(mesh, MeshWindow{}, faceMaterial, smoothShading, degenerate, pieces, piece);
}

Tessellation triangulateMeshPiece(const MeshWindow& window, const std::vector<uint16_t>& faceMaterial,
                                  bool smoothShading, const std::vector<bool>& degenerate, const MeshPieces& pieces,
                                  size_t piece) {
    return triangulatePieceIn(window.mesh, window, faceMaterial, smoothShading, degenerate, pieces, piece);
}

}  // namespace pushpin::geom
