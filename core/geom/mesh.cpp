// core/geom/mesh.cpp: queries and edits on geom::Mesh.
#include "core/geom/mesh.h"

#include "core/geom/union_find.h"
#include "core/util/counting_sort.h"
#include "core/util/parallel_runs.h"
#include "core/util/release.h"


#include <array>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <optional>
#include <unordered_map>

namespace pushpin::geom {

namespace {

glm::dvec3 toD(const glm::vec3& v) { return glm::dvec3(v); }

// Whether bad(i) holds for some i < n, looked for on all threads in runs when n is large (isolated:
// a thread waiting for the runs takes no other work of its caller's).
template <class Bad>
bool anyOf(size_t n, Bad&& bad) {
    constexpr size_t kRun = 65536;
    auto scan = [&](size_t lo, size_t hi) {
        bool found = false;
        for (size_t i = lo; i < hi; ++i) found |= bad(i);
        return found;
    };
    if (n <= 2 * kRun) return scan(0, n);
    std::atomic<bool> found{false};
    util::forEachRun(n, kRun, [&](size_t, size_t lo, size_t hi) {
        if (!found.load(std::memory_order_relaxed) && scan(lo, hi)) found.store(true, std::memory_order_relaxed);
    });
    return found.load();
}

// Newell's method over one loop: twice the signed area vector of the polygon.
glm::dvec3 newell(const Mesh& mesh, std::span<const uint32_t> loop) {
    glm::dvec3 n(0.0);
    const size_t count = loop.size();
    if (count < 3) return n;
    // Relative to the first point, which keeps precision for meshes far from the origin.
    const glm::dvec3 origin = toD(mesh.points[loop[0]]);
    glm::dvec3 a(0.0);  // the first point, relative to itself
    for (size_t i = 1; i <= count; ++i) {
        const glm::dvec3 b = i < count ? toD(mesh.points[loop[i]]) - origin : glm::dvec3(0.0);
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
        a = b;
    }
    return n;
}

}  // namespace

uint32_t Mesh::addFace(std::span<const uint32_t> loopPoints) {
    if (loopStarts.empty()) loopStarts.push_back(0);
    if (faceLoopStarts.empty()) faceLoopStarts.push_back(0);
    faceVertices.insert(faceVertices.end(), loopPoints.begin(), loopPoints.end());
    loopStarts.push_back(static_cast<uint32_t>(faceVertices.size()));
    faceLoopStarts.push_back(static_cast<uint32_t>(loopCount()));
    const size_t fvCount = faceVertices.size();
    if (!normals.empty()) normals.resize(fvCount, glm::vec3(0.0f));
    for (UvSet& set : uvSets)
        if (!set.faceVertexUvs.empty()) set.faceVertexUvs.resize(fvCount, -1);
    for (ColorSet& set : colorSets)
        if (!set.faceVertexColors.empty()) set.faceVertexColors.resize(fvCount, -1);
    return static_cast<uint32_t>(faceCount() - 1);
}

void Mesh::addHole(std::span<const uint32_t> loopPoints) {
    faceVertices.insert(faceVertices.end(), loopPoints.begin(), loopPoints.end());
    loopStarts.push_back(static_cast<uint32_t>(faceVertices.size()));
    faceLoopStarts.back() = static_cast<uint32_t>(loopCount());
    const size_t fvCount = faceVertices.size();
    if (!normals.empty()) normals.resize(fvCount, glm::vec3(0.0f));
    for (UvSet& set : uvSets)
        if (!set.faceVertexUvs.empty()) set.faceVertexUvs.resize(fvCount, -1);
    for (ColorSet& set : colorSets)
        if (!set.faceVertexColors.empty()) set.faceVertexColors.resize(fvCount, -1);
}

const UvSet* currentFaceUvSet(const Mesh& mesh) {
    if (mesh.currentUvSet < 0 || size_t(mesh.currentUvSet) >= mesh.uvSets.size()) return nullptr;
    const UvSet& set = mesh.uvSets[size_t(mesh.currentUvSet)];
    return set.faceVertexUvs.size() == mesh.faceVertexCount() ? &set : nullptr;
}

Bounds3 Mesh::bounds() const {
    Bounds3 b;
    for (const glm::vec3& p : points) b.extend(toD(p));
    return b;
}

glm::dvec3 Mesh::faceAreaVector(size_t f) const {
    glm::dvec3 sum(0.0);
    for (uint32_t l = faceLoopStarts[f]; l < faceLoopStarts[f + 1]; ++l) sum += newell(*this, loop(l));
    return sum * 0.5;
}

glm::dvec3 Mesh::faceNormal(size_t f) const {
    const glm::dvec3 a = faceAreaVector(f);
    const double len = glm::length(a);
    if (!(len > 0.0) || !std::isfinite(len)) return glm::dvec3(0.0);
    return a / len;
}

std::vector<glm::vec3> Mesh::faceNormals() const {
    std::vector<glm::vec3> out(faceCount());
    for (size_t f = 0; f < out.size(); ++f) out[f] = glm::vec3(faceNormal(f));
    return out;
}

double Mesh::signedVolume() const {
    // Sum of the signed tetrahedra (reference point, triangle) over a fan triangulation of every
    // loop; the reference is the bounds centre to limit cancellation.
    const glm::dvec3 ref = points.empty() ? glm::dvec3(0.0) : bounds().center();
    double sixVolume = 0.0;
    for (size_t l = 0; l < loopCount(); ++l) {
        const std::span<const uint32_t> lp = loop(l);
        if (lp.size() < 3) continue;
        const glm::dvec3 p0 = toD(points[lp[0]]) - ref;
        for (size_t i = 1; i + 1 < lp.size(); ++i) {
            const glm::dvec3 p1 = toD(points[lp[i]]) - ref;
            const glm::dvec3 p2 = toD(points[lp[i + 1]]) - ref;
            sixVolume += glm::dot(p0, glm::cross(p1, p2));
        }
    }
    return sixVolume / 6.0;
}

MeshValidation Mesh::validate() const {
    MeshValidation v;
    auto error = [&](std::string message) {
        // A corrupt mesh can produce one message per element; a handful is enough to diagnose it.
        if (v.errors.size() < 32) v.errors.push_back(std::move(message));
    };
    if (loopStarts.empty() || loopStarts.front() != 0) error("loopStarts must start with 0");
    if (faceLoopStarts.empty() || faceLoopStarts.front() != 0) error("faceLoopStarts must start with 0");
    if (!v.errors.empty()) return v;
    if (loopStarts.back() != faceVertices.size())
        error("loopStarts ends at " + std::to_string(loopStarts.back()) + " but there are " +
              std::to_string(faceVertices.size()) + " face-vertices");
    // Each check below looks for a fault on all threads first, and lists the faults in order only
    // when there is one.
    if (anyOf(loopStarts.size() - 1, [&](size_t i) { return loopStarts[i + 1] < loopStarts[i]; }))
        for (size_t i = 1; i < loopStarts.size(); ++i)
            if (loopStarts[i] < loopStarts[i - 1]) error("loopStarts decreases at loop " + std::to_string(i - 1));
    if (faceLoopStarts.back() != loopCount())
        error("faceLoopStarts ends at " + std::to_string(faceLoopStarts.back()) + " but there are " +
              std::to_string(loopCount()) + " loops");
    if (anyOf(faceLoopStarts.size() - 1, [&](size_t i) { return faceLoopStarts[i + 1] <= faceLoopStarts[i]; }))
        for (size_t i = 1; i < faceLoopStarts.size(); ++i)
            if (faceLoopStarts[i] <= faceLoopStarts[i - 1]) error("face " + std::to_string(i - 1) + " has no loop");
    if (!v.errors.empty()) return v;

    const size_t nPoints = points.size();
    if (nPoints >= kMaxMeshPoints)
        error(std::to_string(nPoints) + " points: a mesh holds fewer than " + std::to_string(kMaxMeshPoints));
    auto notFinite = [&](size_t i) {
        const glm::vec3& p = points[i];
        return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
    };
    if (anyOf(nPoints, notFinite))
        for (size_t i = 0; i < nPoints; ++i)
            if (notFinite(i)) error("point " + std::to_string(i) + " is not finite");
    if (anyOf(faceVertices.size(), [&](size_t i) { return faceVertices[i] >= nPoints; }))
        for (size_t i = 0; i < faceVertices.size(); ++i)
            if (faceVertices[i] >= nPoints)
                error("face-vertex " + std::to_string(i) + " uses point " + std::to_string(faceVertices[i]) +
                      " of " + std::to_string(nPoints));
    const size_t fvCount = faceVertices.size();
    if (!normals.empty() && normals.size() != fvCount)
        error(std::to_string(normals.size()) + " normals for " + std::to_string(fvCount) + " face-vertices");
    for (size_t s = 0; s < uvSets.size(); ++s) {
        const UvSet& set = uvSets[s];
        if (!set.faceVertexUvs.empty() && set.faceVertexUvs.size() != fvCount) {
            error("uv set '" + set.name + "' has " + std::to_string(set.faceVertexUvs.size()) + " ids for " +
                  std::to_string(fvCount) + " face-vertices");
            continue;
        }
        auto badUv = [&](size_t i) {
            const int32_t id = set.faceVertexUvs[i];
            return id < -1 || (id >= 0 && size_t(id) >= set.uvs.size());
        };
        if (!anyOf(set.faceVertexUvs.size(), badUv)) continue;
        for (size_t i = 0; i < set.faceVertexUvs.size(); ++i) {
            const int32_t id = set.faceVertexUvs[i];
            if (badUv(i))
                error("uv set '" + set.name + "' face-vertex " + std::to_string(i) + " uses uv " +
                      std::to_string(id) + " of " + std::to_string(set.uvs.size()));
        }
    }
    if (!uvSets.empty() && (currentUvSet < 0 || size_t(currentUvSet) >= uvSets.size()))
        error("current uv set " + std::to_string(currentUvSet) + " of " + std::to_string(uvSets.size()));
    for (const ColorSet& set : colorSets) {
        if (!set.faceVertexColors.empty() && set.faceVertexColors.size() != fvCount) {
            error("colour set '" + set.name + "' has " + std::to_string(set.faceVertexColors.size()) +
                  " ids for " + std::to_string(fvCount) + " face-vertices");
            continue;
        }
        auto badColor = [&](size_t i) {
            const int32_t id = set.faceVertexColors[i];
            return id < -1 || (id >= 0 && size_t(id) >= set.colors.size());
        };
        if (!anyOf(set.faceVertexColors.size(), badColor)) continue;
        for (size_t i = 0; i < set.faceVertexColors.size(); ++i) {
            const int32_t id = set.faceVertexColors[i];
            if (badColor(i))
                error("colour set '" + set.name + "' face-vertex " + std::to_string(i) + " uses colour " +
                      std::to_string(id) + " of " + std::to_string(set.colors.size()));
        }
    }
    auto badEdge = [&](size_t e) { return edges[e].v0 >= nPoints || edges[e].v1 >= nPoints; };
    if (anyOf(edges.size(), badEdge))
        for (size_t e = 0; e < edges.size(); ++e)
            if (badEdge(e)) error("edge " + std::to_string(e) + " uses a point out of range");
    if (!v.errors.empty()) return v;

    // Degenerate faces: a loop with fewer than three distinct points, or (nearly) zero area
    // relative to the face's longest edge. Large meshes are checked in fixed runs of faces on
    // all threads, each run listing its own, joined in face order.
    auto isDegenerate = [&](size_t f, std::vector<uint32_t>& distinct) {
        bool degenerate = false;
        for (uint32_t l = faceLoopStarts[f]; l < faceLoopStarts[f + 1] && !degenerate; ++l) {
            const std::span<const uint32_t> lp = loop(l);
            if (lp.size() < 3) {
                degenerate = true;
            } else if (lp.size() <= 4) {  // the common faces: at least three distinct points, pairwise
                const uint32_t a = lp[0], b = lp[1], c = lp[2], d = lp.size() == 4 ? lp[3] : lp[2];
                const int distinctCount = 1 + (b != a) + (c != a && c != b) + (d != a && d != b && d != c);
                degenerate = distinctCount < 3;
            } else {
                distinct.assign(lp.begin(), lp.end());
                std::sort(distinct.begin(), distinct.end());
                distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
                degenerate = distinct.size() < 3;
            }
        }
        if (!degenerate) {
            const std::span<const uint32_t> outer = faceOuterLoop(f);
            double longest2 = 0.0;
            glm::dvec3 prev = toD(points[outer.back()]);
            for (const uint32_t p : outer) {
                const glm::dvec3 at = toD(points[p]), d = at - prev;
                longest2 = std::max(longest2, glm::dot(d, d));
                prev = at;
            }
            const double area = glm::length(faceAreaVector(f));
            if (!(area > 1e-10 * longest2)) degenerate = true;
        }
        return degenerate;
    };
    constexpr size_t kRun = 16384;
    const size_t faces = faceCount();
    if (faces <= 4 * kRun) {
        std::vector<uint32_t> distinct;
        for (size_t f = 0; f < faces; ++f)
            if (isDegenerate(f, distinct)) v.degenerateFaces.push_back(static_cast<uint32_t>(f));
        return v;
    }
    std::vector<std::vector<uint32_t>> found(util::runCount(faces, kRun));
    util::forEachRun(faces, kRun, [&](size_t r, size_t lo, size_t hi) {
        std::vector<uint32_t> distinct;
        for (size_t f = lo; f < hi; ++f)
            if (isDegenerate(f, distinct)) found[r].push_back(static_cast<uint32_t>(f));
    });
    for (const std::vector<uint32_t>& run : found)
        v.degenerateFaces.insert(v.degenerateFaces.end(), run.begin(), run.end());
    return v;
}

EdgeSmoothness::EdgeSmoothness(const Mesh& mesh) : m_start(mesh.points.size() + 1, 0) {
    const size_t points = mesh.points.size();
    auto inRange = [&](const MeshEdge& e) { return e.v0 < points && e.v1 < points && e.v0 != e.v1; };
    for (const MeshEdge& e : mesh.edges)
        if (inRange(e)) ++m_start[std::min(e.v0, e.v1) + size_t(1)];
    for (size_t p = 0; p < points; ++p) m_start[p + 1] += m_start[p];
    m_upper.resize(m_start[points]);
    m_smooth.resize(m_start[points]);
    for (const MeshEdge& e : mesh.edges) {
        if (!inRange(e)) continue;
        const uint32_t at = m_start[std::min(e.v0, e.v1)]++;
        m_upper[at] = std::max(e.v0, e.v1);
        m_smooth[at] = e.smooth ? 1 : 0;
    }
    for (size_t p = points; p > 0; --p) m_start[p] = m_start[p - 1];
    m_start[0] = 0;
}

EdgeSmoothness::Kind EdgeSmoothness::find(uint32_t a, uint32_t b) const {
    const uint32_t lo = std::min(a, b), hi = std::max(a, b);
    if (size_t(lo) + 1 >= m_start.size()) return Kind::Unlisted;
    for (uint32_t i = m_start[lo + 1]; i-- > m_start[lo];)
        if (m_upper[i] == hi) return m_smooth[i] ? Kind::Smooth : Kind::Hard;
    return Kind::Unlisted;
}

std::vector<glm::vec3> Mesh::shadingNormals() const {
    const size_t fvCount = faceVertices.size();
    std::vector<uint32_t> cornerFace(fvCount);
    std::vector<glm::dvec3> faceArea(faceCount());
    for (size_t f = 0; f < faceCount(); ++f) {
        faceArea[f] = faceAreaVector(f);
        for (uint32_t i = faceVertexBegin(f); i < faceVertexEnd(f); ++i) cornerFace[i] = static_cast<uint32_t>(f);
    }

    std::optional<EdgeSmoothness> smoothness(std::in_place, *this);

    // Union-find over face-vertices: corners at the same point of two faces sharing a soft edge
    // belong to one smoothing group. The half-edges (start and end corner, 8 bytes each) are filed
    // under their lower point by a counting sort; the half-edges of one edge are then found in
    // that point's short list.
    LowestRootSets groups(fvCount);
    struct HalfEdge {
        uint32_t startCorner, endCorner;
    };
    uint32_t pointCount = 0;
    for (uint32_t p : faceVertices) pointCount = std::max(pointCount, p + 1);
    std::vector<uint32_t> start;
    std::vector<HalfEdge> halfEdges;
    util::fileByKey(
        pointCount,
        [&](auto&& visit) {
            for (size_t l = 0; l < loopCount(); ++l) {
                const uint32_t begin = loopStarts[l], end = loopStarts[l + 1];
                for (uint32_t i = begin; i < end; ++i) {
                    const uint32_t j = (i + 1 < end) ? i + 1 : begin;
                    if (faceVertices[i] != faceVertices[j])
                        visit(std::min(faceVertices[i], faceVertices[j]), HalfEdge{i, j});
                }
            }
        },
        start, halfEdges);
    auto upper = [&](const HalfEdge& h) { return std::max(faceVertices[h.startCorner], faceVertices[h.endCorner]); };
    auto joinAcross = [&](const HalfEdge& first, const HalfEdge& other) {
        for (uint32_t c : {other.startCorner, other.endCorner}) {
            if (faceVertices[c] == faceVertices[first.startCorner]) groups.join(c, first.startCorner);
            if (faceVertices[c] == faceVertices[first.endCorner]) groups.join(c, first.endCorner);
        }
    };
    std::vector<std::pair<uint32_t, uint32_t>> busy;  // (upper point, half-edge) of a point with many
    for (uint32_t p = 0; p < pointCount; ++p) {
        const uint32_t begin = start[p], end = start[p + 1];
        if (end - begin <= 32) {
            for (uint32_t i = begin; i < end; ++i) {
                const uint32_t hi = upper(halfEdges[i]);
                bool first = true;
                for (uint32_t k = begin; k < i && first; ++k) first = upper(halfEdges[k]) != hi;
                if (!first || smoothness->find(p, hi) == EdgeSmoothness::Kind::Hard) continue;
                for (uint32_t k = i + 1; k < end; ++k)
                    if (upper(halfEdges[k]) == hi) joinAcross(halfEdges[i], halfEdges[k]);
            }
            continue;
        }
        busy.clear();
        for (uint32_t i = begin; i < end; ++i) busy.emplace_back(upper(halfEdges[i]), i);
        std::sort(busy.begin(), busy.end());
        for (size_t i = 0; i < busy.size();) {
            size_t j = i + 1;
            while (j < busy.size() && busy[j].first == busy[i].first) ++j;
            if (smoothness->find(p, busy[i].first) != EdgeSmoothness::Kind::Hard)
                for (size_t k = i + 1; k < j; ++k) joinAcross(halfEdges[busy[i].second], halfEdges[busy[k].second]);
            i = j;
        }
    }

    util::release(halfEdges);  // what follows needs neither the half-edges nor the smoothness table
    smoothness.reset();
    // A smoothing group's corners all sit on one point: point by point, each group's area-weighted
    // sum adds its corners' faces in corner order (a group is known by its root, its first corner).
    std::vector<uint32_t> byPoint;
    util::fileByKey(
        pointCount,
        [&](auto&& visit) {
            for (uint32_t c = 0; c < fvCount; ++c) visit(faceVertices[c], c);
        },
        start, byPoint);
    std::vector<glm::vec3> out(fvCount);
    std::vector<uint32_t> roots;     // of the point's groups, ascending
    std::vector<glm::dvec3> sums;   // parallel to roots
    for (uint32_t p = 0; p < pointCount; ++p) {
        roots.clear();
        sums.clear();
        auto slotOf = [&](uint32_t root) {
            return size_t(std::lower_bound(roots.begin(), roots.end(), root) - roots.begin());
        };
        for (uint32_t k = start[p]; k < start[p + 1]; ++k) {
            const uint32_t c = byPoint[k], root = groups.find(c);
            if (root == c) {
                roots.push_back(c);
                sums.emplace_back(0.0);
            }
            sums[slotOf(root)] += faceArea[cornerFace[c]];
        }
        for (uint32_t k = start[p]; k < start[p + 1]; ++k) {
            const uint32_t c = byPoint[k];
            if (!normals.empty()) {
                const glm::vec3& n = normals[c];
                if (n.x != 0.0f || n.y != 0.0f || n.z != 0.0f) {
                    out[c] = n;
                    continue;
                }
            }
            glm::dvec3 s = sums[slotOf(groups.find(c))];
            double len = glm::length(s);
            if (!(len > 0.0)) {
                s = faceArea[cornerFace[c]];
                len = glm::length(s);
            }
            out[c] = len > 0.0 ? glm::vec3(s / len) : glm::vec3(0.0f);
        }
    }
    return out;
}

std::vector<MeshEdge> deriveEdges(const Mesh& mesh, bool smooth) {
    std::vector<MeshEdge> out;
    EdgeIndex seen(mesh.faceVertices.size() / 2 + 1);
    for (size_t l = 0; l < mesh.loopCount(); ++l) {
        const std::span<const uint32_t> lp = mesh.loop(l);
        for (size_t i = 0; i < lp.size(); ++i) {
            const uint32_t a = lp[i], b = i + 1 < lp.size() ? lp[i + 1] : lp[0];
            if (a == b) continue;
            bool inserted = false;
            seen.emplace(edgeKey(a, b), static_cast<uint32_t>(out.size()), &inserted);
            if (inserted) out.push_back({a, b, smooth});
        }
    }
    return out;
}

void completeEdges(Mesh& mesh, bool smoothForNew) {
    EdgeIndex seen(mesh.faceVertices.size() / 2 + mesh.edges.size() + 1);
    for (size_t e = 0; e < mesh.edges.size(); ++e) seen.emplace(edgeKey(mesh.edges[e].v0, mesh.edges[e].v1), uint32_t(e));
    for (size_t l = 0; l < mesh.loopCount(); ++l) {
        const std::span<const uint32_t> lp = mesh.loop(l);
        for (size_t i = 0; i < lp.size(); ++i) {
            const uint32_t a = lp[i], b = lp[(i + 1) % lp.size()];
            if (a == b) continue;
            bool inserted = false;
            seen.emplace(edgeKey(a, b), static_cast<uint32_t>(mesh.edges.size()), &inserted);
            if (inserted) mesh.edges.push_back({a, b, smoothForNew});
        }
    }
}

int64_t findEdge(const Mesh& mesh, uint32_t a, uint32_t b) {
    const uint64_t key = edgeKey(a, b);
    for (size_t e = 0; e < mesh.edges.size(); ++e)
        if (edgeKey(mesh.edges[e].v0, mesh.edges[e].v1) == key) return static_cast<int64_t>(e);
    return -1;
}

void transformMesh(Mesh& mesh, const glm::dmat4& m) {
    for (glm::vec3& p : mesh.points) p = glm::vec3(glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0)));
    if (!mesh.normals.empty()) {
        const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
        for (glm::vec3& n : mesh.normals) {
            if (n.x == 0.0f && n.y == 0.0f && n.z == 0.0f) continue;  // "compute" stays "compute"
            const glm::dvec3 t = normalMatrix * glm::dvec3(n);
            const double len = glm::length(t);
            n = len > 0.0 && std::isfinite(len) ? glm::vec3(t / len) : glm::vec3(0.0f);
        }
    }
}

namespace {

// Corners (0..n-1) of one outer loop in triangles, by ear clipping in the plane whose normal is
// `normal`. Past kMaxEarClip corners the quadratic search gives way to a fan.
constexpr size_t kMaxEarClip = 512;

void earClip(const std::vector<glm::dvec2>& p, std::vector<std::array<uint32_t, 3>>& out) {
    const size_t n = p.size();
    std::vector<uint32_t> left(n);
    for (size_t i = 0; i < n; ++i) left[i] = uint32_t(i);
    auto cross = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
        return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    };
    auto inside = [&](glm::dvec2 q, glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
        return cross(a, b, q) >= 0 && cross(b, c, q) >= 0 && cross(c, a, q) >= 0;
    };
    while (left.size() > 3) {
        bool clipped = false;
        for (size_t i = 0; i < left.size() && !clipped; ++i) {
            const uint32_t a = left[(i + left.size() - 1) % left.size()], b = left[i], c = left[(i + 1) % left.size()];
            if (cross(p[a], p[b], p[c]) <= 0) continue;  // reflex or flat: not an ear
            bool empty = true;
            for (uint32_t q : left)
                if (q != a && q != b && q != c && p[q] != p[a] && p[q] != p[b] && p[q] != p[c] &&
                    inside(p[q], p[a], p[b], p[c])) {
                    empty = false;
                    break;
                }
            if (!empty) continue;
            out.push_back({a, b, c});
            left.erase(left.begin() + ptrdiff_t(i));
            clipped = true;
        }
        if (!clipped) break;  // degenerate or self-intersecting: the rest as a fan
    }
    for (size_t i = 1; i + 1 < left.size(); ++i) out.push_back({left[0], left[i], left[i + 1]});
}

}  // namespace

Mesh facelessCopy(const Mesh& source, std::vector<glm::vec3> points) {
    Mesh out;
    out.points = std::move(points);
    out.currentUvSet = source.currentUvSet;
    for (const UvSet& set : source.uvSets) out.uvSets.push_back({set.name, set.uvs, {}});
    for (const ColorSet& set : source.colorSets) out.colorSets.push_back({set.name, set.colors, {}});
    return out;
}

void copyFaceVertex(Mesh& out, const Mesh& source, uint32_t fv, uint32_t point) {
    out.faceVertices.push_back(point);
    if (!source.normals.empty()) out.normals.push_back(source.normals[fv]);
    for (size_t s = 0; s < source.uvSets.size(); ++s)
        if (!source.uvSets[s].faceVertexUvs.empty()) out.uvSets[s].faceVertexUvs.push_back(source.uvSets[s].faceVertexUvs[fv]);
    for (size_t s = 0; s < source.colorSets.size(); ++s)
        if (!source.colorSets[s].faceVertexColors.empty())
            out.colorSets[s].faceVertexColors.push_back(source.colorSets[s].faceVertexColors[fv]);
}

size_t triangulateFaces(Mesh& mesh, const std::vector<bool>* only) {
    Mesh out = facelessCopy(mesh, mesh.points);
    out.edges = mesh.edges;
    auto corner = [&](uint32_t fv) { copyFaceVertex(out, mesh, fv); };
    auto endLoop = [&](bool endFace) {
        out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        if (endFace) out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    };
    size_t withHoles = 0;
    std::vector<glm::dvec2> projected;
    std::vector<std::array<uint32_t, 3>> triangles;
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        const uint32_t begin = mesh.faceVertexBegin(f);
        const size_t n = mesh.faceOuterLoop(f).size();
        const bool selected = !only || (f < only->size() && (*only)[f]);
        if (!selected || mesh.holeCount(f) > 0 || n <= 3) {
            withHoles += selected && mesh.holeCount(f) > 0;
            for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
                for (uint32_t fv = mesh.loopStarts[l]; fv < mesh.loopStarts[l + 1]; ++fv) corner(fv);
                endLoop(l + 1 == mesh.faceLoopStarts[f + 1]);
            }
            continue;
        }
        // The face's plane: two axes perpendicular to its Newell normal.
        glm::dvec3 normal = mesh.faceNormal(f);
        triangles.clear();
        if (n > kMaxEarClip || glm::dot(normal, normal) == 0.0) {
            for (uint32_t i = 1; i + 1 < n; ++i) triangles.push_back({0, i, i + 1});
        } else {
            const glm::dvec3 helper = std::abs(normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
            const glm::dvec3 u = glm::normalize(glm::cross(helper, normal)), v = glm::cross(normal, u);
            projected.clear();
            for (uint32_t i = 0; i < n; ++i) {
                const glm::dvec3 q(mesh.points[mesh.faceVertices[begin + i]]);
                projected.push_back({glm::dot(q, u), glm::dot(q, v)});
            }
            earClip(projected, triangles);
        }
        for (const auto& t : triangles) {
            for (uint32_t k : t) corner(begin + k);
            endLoop(true);
        }
    }
    completeEdges(out, true);
    mesh = std::move(out);
    return withHoles;
}

void deleteFaces(Mesh& mesh, const std::vector<bool>& removeFace) {
    Mesh out = facelessCopy(mesh, std::move(mesh.points));
    const bool hasNormals = !mesh.normals.empty();
    out.faceVertices.reserve(mesh.faceVertices.size());
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        if (f < removeFace.size() && removeFace[f]) continue;
        for (uint32_t l = mesh.faceLoopStarts[f]; l < mesh.faceLoopStarts[f + 1]; ++l) {
            const uint32_t begin = mesh.loopStarts[l], end = mesh.loopStarts[l + 1];
            out.faceVertices.insert(out.faceVertices.end(), mesh.faceVertices.begin() + begin,
                                    mesh.faceVertices.begin() + end);
            out.loopStarts.push_back(static_cast<uint32_t>(out.faceVertices.size()));
            if (hasNormals) out.normals.insert(out.normals.end(), mesh.normals.begin() + begin, mesh.normals.begin() + end);
            for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
                const std::vector<int32_t>& ids = mesh.uvSets[s].faceVertexUvs;
                if (!ids.empty())
                    out.uvSets[s].faceVertexUvs.insert(out.uvSets[s].faceVertexUvs.end(), ids.begin() + begin,
                                                       ids.begin() + end);
            }
            for (size_t s = 0; s < mesh.colorSets.size(); ++s) {
                const std::vector<int32_t>& ids = mesh.colorSets[s].faceVertexColors;
                if (!ids.empty())
                    out.colorSets[s].faceVertexColors.insert(out.colorSets[s].faceVertexColors.end(),
                                                             ids.begin() + begin, ids.begin() + end);
            }
        }
        out.faceLoopStarts.push_back(static_cast<uint32_t>(out.loopCount()));
    }
    // Keep the edges some remaining loop still uses, with their flags and in their order.
    std::unordered_map<uint64_t, bool> used;
    for (const MeshEdge& e : deriveEdges(out, true)) used.emplace(edgeKey(e.v0, e.v1), true);
    for (const MeshEdge& e : mesh.edges)
        if (used.count(edgeKey(e.v0, e.v1))) out.edges.push_back(e);
    // A set that mapped faces but lost all of them keeps an empty (consistent) id array.
    mesh = std::move(out);
    removeUnusedPoints(mesh);
}

size_t removeUnusedPoints(Mesh& mesh) {
    constexpr uint32_t kUnused = ~uint32_t(0);
    std::vector<uint32_t> remap(mesh.points.size(), kUnused);
    for (uint32_t v : mesh.faceVertices)
        if (v < remap.size()) remap[v] = 0;
    uint32_t next = 0;
    for (size_t i = 0; i < remap.size(); ++i) {
        if (remap[i] == kUnused) continue;
        remap[i] = next;
        mesh.points[next++] = mesh.points[i];
    }
    const size_t dropped = mesh.points.size() - next;
    mesh.points.resize(next);
    for (uint32_t& v : mesh.faceVertices)
        if (v < remap.size()) v = remap[v];
    std::vector<MeshEdge> edges;
    edges.reserve(mesh.edges.size());
    for (const MeshEdge& e : mesh.edges) {
        if (e.v0 >= remap.size() || e.v1 >= remap.size() || remap[e.v0] == kUnused || remap[e.v1] == kUnused) continue;
        edges.push_back({remap[e.v0], remap[e.v1], e.smooth});
    }
    mesh.edges = std::move(edges);
    return dropped;
}

size_t faceShells(const Mesh& mesh, std::vector<uint32_t>& shellOfFace) {
    // Points joined through faces, then faces take the shell of their first point.
    LowestRootSets points(mesh.points.size());
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        const uint32_t first = mesh.faceVertices[mesh.faceVertexBegin(f)];
        for (uint32_t fv = mesh.faceVertexBegin(f); fv < mesh.faceVertexEnd(f); ++fv) points.join(first, mesh.faceVertices[fv]);
    }
    shellOfFace.assign(mesh.faceCount(), 0);
    std::vector<uint32_t> number(mesh.points.size(), ~uint32_t(0));
    uint32_t shells = 0;
    for (size_t f = 0; f < mesh.faceCount(); ++f) {
        const uint32_t root = points.find(mesh.faceVertices[mesh.faceVertexBegin(f)]);
        if (number[root] == ~uint32_t(0)) number[root] = shells++;
        shellOfFace[f] = number[root];
    }
    return shells;
}

bool appendMesh(Mesh& into, const Mesh& part, const glm::dmat4& m) {
    if (into.faceVertices.size() + part.faceVertices.size() >= size_t(UINT32_MAX) ||
        into.points.size() + part.points.size() >= size_t(UINT32_MAX))
        return false;
    // Edge lists stay complete on both sides or absent on both (absent: every edge soft).
    const bool withEdges = !into.edges.empty() || !part.edges.empty();
    if (withEdges && into.edges.empty()) completeEdges(into, true);
    const uint32_t pointBase = uint32_t(into.points.size());
    const size_t fvBefore = into.faceVertices.size();
    const uint32_t loopBase = uint32_t(into.loopCount());
    const bool intoNormals = !into.normals.empty() || !part.normals.empty();
    if (intoNormals && into.normals.empty()) into.normals.assign(fvBefore, glm::vec3(0.0f));
    for (const glm::vec3& p : part.points) into.points.emplace_back(glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0)));
    for (uint32_t v : part.faceVertices) into.faceVertices.push_back(pointBase + v);
    for (size_t l = 1; l < part.loopStarts.size(); ++l) into.loopStarts.push_back(uint32_t(fvBefore) + part.loopStarts[l]);
    for (size_t f = 1; f < part.faceLoopStarts.size(); ++f) into.faceLoopStarts.push_back(loopBase + part.faceLoopStarts[f]);
    if (intoNormals) {
        if (part.normals.empty()) {
            into.normals.resize(into.faceVertices.size(), glm::vec3(0.0f));
        } else {
            const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(m)));
            for (const glm::vec3& n : part.normals) {
                if (n == glm::vec3(0.0f)) {
                    into.normals.push_back(n);
                    continue;
                }
                const glm::dvec3 t = normalMatrix * glm::dvec3(n);
                const double len = glm::length(t);
                into.normals.push_back(len > 0.0 ? glm::vec3(t / len) : glm::vec3(0.0f));
            }
        }
    }
    if (withEdges) {
        for (const MeshEdge& e : part.edges) into.edges.push_back({pointBase + e.v0, pointBase + e.v1, e.smooth});
        if (part.edges.empty()) completeEdges(into, true);
    }
    // UV sets by name.
    const size_t fvAfter = into.faceVertices.size();
    for (UvSet& set : into.uvSets)
        if (!set.faceVertexUvs.empty() || fvBefore == 0) set.faceVertexUvs.resize(fvBefore, -1);
    std::vector<bool> filled(into.uvSets.size(), false);
    for (const UvSet& src : part.uvSets) {
        size_t s = 0;
        while (s < into.uvSets.size() && into.uvSets[s].name != src.name) ++s;
        if (s == into.uvSets.size()) {
            into.uvSets.push_back({src.name, {}, std::vector<int32_t>(fvBefore, -1)});
            filled.push_back(false);
        }
        UvSet& dst = into.uvSets[s];
        const int32_t base = int32_t(dst.uvs.size());
        dst.uvs.insert(dst.uvs.end(), src.uvs.begin(), src.uvs.end());
        dst.faceVertexUvs.resize(fvBefore, -1);
        if (src.faceVertexUvs.size() == part.faceVertices.size())
            for (int32_t id : src.faceVertexUvs) dst.faceVertexUvs.push_back(id >= 0 ? base + id : -1);
        else
            dst.faceVertexUvs.resize(fvAfter, -1);
        filled[s] = true;
    }
    for (size_t s = 0; s < into.uvSets.size(); ++s)
        if (!filled[s]) into.uvSets[s].faceVertexUvs.resize(fvAfter, -1);
    if (into.uvSets.size() > 0 && (into.currentUvSet < 0 || size_t(into.currentUvSet) >= into.uvSets.size())) into.currentUvSet = 0;
    // Colour sets by name, the same way.
    std::vector<bool> colored(into.colorSets.size(), false);
    for (ColorSet& set : into.colorSets) set.faceVertexColors.resize(fvBefore, -1);
    for (const ColorSet& src : part.colorSets) {
        size_t s = 0;
        while (s < into.colorSets.size() && into.colorSets[s].name != src.name) ++s;
        if (s == into.colorSets.size()) {
            into.colorSets.push_back({src.name, {}, std::vector<int32_t>(fvBefore, -1)});
            colored.push_back(false);
        }
        ColorSet& dst = into.colorSets[s];
        const int32_t base = int32_t(dst.colors.size());
        dst.colors.insert(dst.colors.end(), src.colors.begin(), src.colors.end());
        if (src.faceVertexColors.size() == part.faceVertices.size())
            for (int32_t id : src.faceVertexColors) dst.faceVertexColors.push_back(id >= 0 ? base + id : -1);
        else
            dst.faceVertexColors.resize(fvAfter, -1);
        colored[s] = true;
    }
    for (size_t s = 0; s < into.colorSets.size(); ++s)
        if (!colored[s]) into.colorSets[s].faceVertexColors.resize(fvAfter, -1);
    return true;
}

}  // namespace pushpin::geom
