#include "core/geom/tessellation.h"

#include "core/geom/finite.h"
#include "core/geom/triangulate.h"
#include "core/util/counting_sort.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>

namespace pushpin::geom {

namespace {

template <class T>
uint64_t capacityBytes(const std::vector<T>& v) {
    return uint64_t(v.capacity()) * sizeof(T);
}

// Fills t.neighbors from the identity of the point each corner sits on (`cornerPoint`, 3 per
// triangle): two triangles whose edges join the same two points are neighbours, flagged with
// kHardNeighborBit when `hard(t0, t1, p0, p1)` says so (p0 < p1); edges used by one triangle or
// by more than two get kNoNeighbor.
// Each edge use (slot 3·t + k) is filed under its lower point by a counting sort, in slot order;
// a point's uses are few, so the uses of one edge are found in its own short list (4 bytes a use,
// not a sort of 16-byte records over the whole mesh).
template <class HardFn>
void buildNeighbors(Tessellation& t, const std::vector<uint32_t>& cornerPoint, HardFn&& hard) {
    const size_t triangles = t.triangleCount();
    t.neighbors.assign(3 * triangles, kNoNeighbor);
    auto ends = [&](uint32_t slot) {
        const uint32_t a = cornerPoint[slot], b = cornerPoint[slot - slot % 3 + (slot % 3 + 1) % 3];
        return std::pair<uint32_t, uint32_t>(std::min(a, b), std::max(a, b));
    };
    uint32_t points = 0;
    for (size_t c = 0; c < 3 * triangles; ++c) points = std::max(points, cornerPoint[c] + 1);
    std::vector<uint32_t> start, uses;  // each edge use (corner slot) filed under its lower point
    util::fileByKey(
        points,
        [&](auto&& visit) {
            for (uint32_t slot = 0; slot < 3 * triangles; ++slot) {
                const auto [lo, hi] = ends(slot);
                if (lo != hi) visit(lo, slot);
            }
        },
        start, uses);

    std::vector<std::pair<uint32_t, uint32_t>> sorted;  // (upper point, slot) of a busy point
    auto pair = [&](uint32_t lo, uint32_t hi, uint32_t s0, uint32_t s1) {
        const uint32_t t0 = s0 / 3, t1 = s1 / 3;
        if (t0 == t1) return;
        const uint32_t bit = hard(t0, t1, lo, hi) ? kHardNeighborBit : 0u;
        t.neighbors[s0] = t1 | bit;
        t.neighbors[s1] = t0 | bit;
    };
    for (uint32_t p = 0; p < points; ++p) {
        const uint32_t begin = start[p], end = start[p + 1];
        if (end - begin <= 32) {
            for (uint32_t i = begin; i < end; ++i) {
                const uint32_t hi = ends(uses[i]).second;
                uint32_t count = 0, second = 0;
                bool first = true;
                for (uint32_t j = begin; j < end; ++j) {
                    if (ends(uses[j]).second != hi) continue;
                    if (j < i) first = false;
                    if (++count == 2) second = j;
                }
                if (first && count == 2) pair(p, hi, uses[i], uses[second]);
            }
            continue;
        }
        sorted.clear();
        for (uint32_t i = begin; i < end; ++i) sorted.emplace_back(ends(uses[i]).second, uses[i]);
        std::sort(sorted.begin(), sorted.end());
        for (size_t i = 0; i < sorted.size();) {
            size_t j = i + 1;
            while (j < sorted.size() && sorted[j].first == sorted[i].first) ++j;
            if (j - i == 2) pair(p, sorted[i].first, sorted[i].second, sorted[i + 1].second);
            i = j;
        }
    }
}

bool sameBits(const glm::vec3& a, const glm::vec3& b) {
    return std::bit_cast<uint32_t>(a.x) == std::bit_cast<uint32_t>(b.x) &&
           std::bit_cast<uint32_t>(a.y) == std::bit_cast<uint32_t>(b.y) &&
           std::bit_cast<uint32_t>(a.z) == std::bit_cast<uint32_t>(b.z);
}

bool sameBits(const glm::vec2& a, const glm::vec2& b) {
    return std::bit_cast<uint32_t>(a.x) == std::bit_cast<uint32_t>(b.x) &&
           std::bit_cast<uint32_t>(a.y) == std::bit_cast<uint32_t>(b.y);
}

}  // namespace

uint64_t Tessellation::bytes() const {
    return capacityBytes(positions) + capacityBytes(normals) + capacityBytes(uvs) + capacityBytes(corners) +
           capacityBytes(face) + capacityBytes(material) + capacityBytes(neighbors) + capacityBytes(clusterBounds);
}

std::vector<uint32_t> triangleVertices(const Tessellation& t, std::span<const uint32_t> triangles) {
    std::vector<uint32_t> vertices(3 * triangles.size());
    for (size_t i = 0; i < triangles.size(); ++i)
        for (size_t k = 0; k < 3; ++k) vertices[3 * i + k] = t.corners[3 * size_t(triangles[i]) + k];
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    return vertices;
}

uint64_t copiedTrianglesBytes(const Tessellation& t, size_t triangles, size_t vertices) {
    const uint64_t perVertex = sizeof(glm::vec3) + (t.normals.empty() ? 0 : sizeof(glm::vec3)) +
                               (t.uvs.empty() ? 0 : sizeof(glm::vec2));
    const uint64_t perTriangle = 7 * sizeof(uint32_t) + (t.material.empty() ? 0 : sizeof(uint16_t));
    return uint64_t(vertices) * perVertex + uint64_t(triangles) * perTriangle;
}

Tessellation copyTriangles(const Tessellation& t, std::span<const uint32_t> triangles,
                           std::span<const uint32_t> vertices) {
    Tessellation c;
    c.positions.resize(vertices.size());
    if (!t.normals.empty()) c.normals.resize(vertices.size());
    if (!t.uvs.empty()) c.uvs.resize(vertices.size());
    for (size_t i = 0; i < vertices.size(); ++i) {
        c.positions[i] = t.positions[vertices[i]];
        if (!t.normals.empty()) c.normals[i] = t.normals[vertices[i]];
        if (!t.uvs.empty()) c.uvs[i] = t.uvs[vertices[i]];
    }
    const size_t n = triangles.size();
    c.corners.resize(3 * n);
    c.neighbors.resize(3 * n);
    c.face.resize(n);
    if (!t.material.empty()) c.material.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const size_t from = triangles[i];
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = t.corners[3 * from + k];
            c.corners[3 * i + k] = uint32_t(std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin());
            c.neighbors[3 * i + k] = t.neighbors[3 * from + k];
        }
        c.face[i] = t.face[from];
        if (!t.material.empty()) c.material[i] = from < t.material.size() ? t.material[from] : uint16_t(0);
    }
    return c;
}

Tessellation triangulateMesh(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading) {
    const MeshValidation validation = mesh.validate();
    if (!validation.ok()) return {};
    std::vector<bool> degenerate(mesh.faceCount(), false);
    for (uint32_t f : validation.degenerateFaces) degenerate[f] = true;
    return triangulateValidMesh(mesh, faceMaterial, smoothShading, degenerate);
}

uint32_t faceTriangleBound(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate, size_t f) {
    return faceTriangleBound(mesh, f, faceMaterial, degenerate, f);
}

uint32_t faceTriangleBound(const Mesh& mesh, size_t meshFace, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate, size_t f) {
    const uint16_t material = f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0);
    if (material == kNoFaceMaterial || (f < degenerate.size() && degenerate[f])) return 0;
    const uint64_t corners = mesh.faceVertexEnd(meshFace) - mesh.faceVertexBegin(meshFace);
    const uint64_t holes = mesh.holeCount(meshFace);
    return corners + 2 * holes >= 3 ? uint32_t(corners + 2 * holes - 2) : 0u;
}

uint64_t meshTriangleCount(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                           const std::vector<bool>& degenerate) {
    uint64_t count = 0;
    for (size_t f = 0; f < mesh.faceCount(); ++f) count += faceTriangleBound(mesh, faceMaterial, degenerate, f);
    return count;
}

void buildTriangleNeighbors(Tessellation& t, const std::vector<uint32_t>& cornerPoint) {
    buildNeighbors(t, cornerPoint, [](uint32_t, uint32_t, uint32_t, uint32_t) { return false; });
}

void computeTessellationBounds(Tessellation& t) {
    t.bounds = Bounds3();
    for (const glm::vec3& p : t.positions) t.bounds.extend(glm::dvec3(p));
    const size_t triangles = t.triangleCount();
    const size_t clusters = (triangles + Tessellation::kClusterTriangles - 1) / Tessellation::kClusterTriangles;
    t.clusterBounds.assign(clusters, Bounds3());
    for (size_t c = 0; c < 3 * triangles; ++c)
        t.clusterBounds[c / (3 * Tessellation::kClusterTriangles)].extend(glm::dvec3(t.positions[t.corners[c]]));
}

Tessellation triangulateValidMesh(const Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading,
                                  const std::vector<bool>& degenerate) {
    Tessellation out;
    const size_t faces = mesh.faceCount();
    std::vector<glm::vec3> shading;
    if (smoothShading) shading = mesh.shadingNormals();
    const UvSet* uvSet = currentFaceUvSet(mesh);

    const uint64_t triangles = meshTriangleCount(mesh, faceMaterial, degenerate);
    std::vector<uint32_t> cornerPoint;
    cornerPoint.reserve(3 * triangles);
    out.corners.reserve(3 * triangles);
    out.face.reserve(triangles);
    out.material.reserve(triangles);
    // Vertices by point: the first vertex made at each point, then a chain through the others
    // (points where normals or uvs split: hard edges, uv seams).
    std::vector<uint32_t> firstVertex(mesh.points.size(), kNoNeighbor);
    std::vector<uint32_t> nextVertex;
    const size_t expectedVertices = std::min<size_t>(mesh.faceVertexCount(), mesh.points.size() + triangles / 4);
    out.positions.reserve(expectedVertices);
    out.normals.reserve(expectedVertices);
    if (uvSet) out.uvs.reserve(expectedVertices);
    nextVertex.reserve(expectedVertices);
    auto vertexFor = [&](uint32_t point, const glm::vec3& n, const glm::vec2& uv) {
        for (uint32_t v = firstVertex[point]; v != kNoNeighbor; v = nextVertex[v])
            if (sameBits(out.normals[v], n) && (!uvSet || sameBits(out.uvs[v], uv))) return v;
        const uint32_t v = uint32_t(out.positions.size());
        out.positions.push_back(mesh.points[point]);
        out.normals.push_back(n);
        if (uvSet) out.uvs.push_back(uv);
        nextVertex.push_back(firstVertex[point]);
        firstVertex[point] = v;
        return v;
    };

    PolygonTriangulator triangulator;
    std::vector<glm::dvec3> points;
    std::vector<uint32_t> loops, local;
    for (size_t f = 0; f < faces; ++f) {
        const uint16_t material = f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0);
        if (material == kNoFaceMaterial || (f < degenerate.size() && degenerate[f])) continue;
        const uint32_t begin = mesh.faceVertexBegin(f), end = mesh.faceVertexEnd(f);
        const glm::dvec3 areaVector = mesh.faceAreaVector(f);
        local.clear();
        if (mesh.holeCount(f) == 0 && end - begin == 3) {
            local = {0, 1, 2};
        } else {
            points.clear();
            for (uint32_t c = begin; c < end; ++c) points.push_back(glm::dvec3(mesh.points[mesh.faceVertices[c]]));
            loops.clear();
            for (uint32_t l = mesh.faceLoopStarts[f]; l <= mesh.faceLoopStarts[f + 1]; ++l)
                loops.push_back(mesh.loopStarts[l] - begin);
            triangulator.triangulate(points, loops, areaVector, local);
        }
        if (local.empty()) continue;
        const double areaLength = glm::length(areaVector);
        const glm::vec3 faceNormal = areaLength > 0.0 ? glm::vec3(areaVector / areaLength) : glm::vec3(0, 0, 1);
        for (size_t i = 0; i < local.size(); ++i) {
            const uint32_t fv = begin + local[i];
            const uint32_t point = mesh.faceVertices[fv];
            glm::vec3 n = faceNormal;
            if (smoothShading) {
                const glm::vec3 s = shading[fv];
                const float length = glm::length(s);
                if (std::isfinite(length) && length > 1e-20f) n = s / length;
            }
            glm::vec2 uv(0.0f);
            if (uvSet) {
                const int32_t id = uvSet->faceVertexUvs[fv];
                if (id >= 0) uv = uvSet->uvs[size_t(id)];
            }
            out.corners.push_back(vertexFor(point, n, uv));
            cornerPoint.push_back(point);
        }
        for (size_t t = 0; t < local.size() / 3; ++t) {
            out.face.push_back(uint32_t(f));
            out.material.push_back(material);
        }
    }
    // The vertex arrays were reserved by a guess: give back what the guess left over.
    out.positions.shrink_to_fit();
    out.normals.shrink_to_fit();
    out.uvs.shrink_to_fit();
    computeTessellationBounds(out);

    shading = {};  // the adjacency below needs none of the per-corner or per-point tables
    firstVertex = {};
    nextVertex = {};
    std::optional<EdgeSmoothness> smoothness;
    if (smoothShading) smoothness.emplace(mesh);
    buildNeighbors(out, cornerPoint, [&](uint32_t t0, uint32_t t1, uint32_t a, uint32_t b) {
        if (out.face[t0] == out.face[t1]) return false;  // a diagonal inside one face
        if (out.material[t0] != out.material[t1]) return true;
        if (!smoothShading) return true;
        return smoothness->find(a, b) == EdgeSmoothness::Kind::Hard;
    });
    return out;
}

}  // namespace pushpin::geom
