// core/geom/poly_dissolve.cpp: Maya's deleteComponent on edges and points.
#include "core/geom/poly_dissolve.h"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace pushpin::geom {

namespace {

// Editable faces: loops of face-vertex indices into the original mesh (their data is copied on
// the rebuild).
struct Faces {
    std::vector<std::vector<std::vector<uint32_t>>> loops;  // per face, per loop, face-vertices
    std::vector<bool> gone;

    explicit Faces(const Mesh& m) : loops(m.faceCount()), gone(m.faceCount(), false) {
        for (size_t f = 0; f < m.faceCount(); ++f)
            for (uint32_t l = m.faceLoopStarts[f]; l < m.faceLoopStarts[f + 1]; ++l) {
                std::vector<uint32_t>& loop = loops[f].emplace_back();
                for (uint32_t fv = m.loopStarts[l]; fv < m.loopStarts[l + 1]; ++fv) loop.push_back(fv);
            }
    }
};

// Cuts spikes (… x, p, x …) out of a loop of face-vertices.
void cutSpikes(const Mesh& m, std::vector<uint32_t>& loop) {
    bool changed = true;
    while (changed && loop.size() >= 3) {
        changed = false;
        for (size_t i = 0; i < loop.size() && loop.size() >= 3; ++i) {
            const size_t prev = (i + loop.size() - 1) % loop.size(), next = (i + 1) % loop.size();
            if (m.faceVertices[loop[prev]] == m.faceVertices[loop[next]]) {
                // Remove the spike tip and one copy of its base.
                const size_t a = std::max(i, next), b = std::min(i, next);
                loop.erase(loop.begin() + std::ptrdiff_t(a));
                loop.erase(loop.begin() + std::ptrdiff_t(b));
                changed = true;
                break;
            }
        }
    }
}

// Rebuilds the mesh from the editable faces, dropping removed faces, the edges in `dropEdges` and
// the points no face uses any more (only those in `mayDrop`, when given).
DissolveResult rebuild(Mesh& mesh, const Faces& faces, const std::unordered_set<uint64_t>& dropEdges,
                       DissolveResult r) {
    Mesh out = facelessCopy(mesh, mesh.points);
    for (size_t f = 0; f < faces.loops.size(); ++f) {
        if (faces.gone[f]) continue;
        bool any = false;
        for (const std::vector<uint32_t>& loop : faces.loops[f]) {
            if (loop.size() < 3) continue;
            any = true;
            for (uint32_t fv : loop) copyFaceVertex(out, mesh, fv);
            out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        }
        if (!any) {
            ++r.removedFaces;
            continue;
        }
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    std::unordered_set<uint64_t> used;
    for (size_t l = 0; l < out.loopCount(); ++l) {
        const std::span<const uint32_t> lp = out.loop(l);
        for (size_t k = 0; k < lp.size(); ++k) used.insert(edgeKey(lp[k], lp[(k + 1) % lp.size()]));
    }
    for (const MeshEdge& e : mesh.edges)
        if (!dropEdges.count(edgeKey(e.v0, e.v1)) && used.count(edgeKey(e.v0, e.v1))) out.edges.push_back(e);
    r.removedPoints = removeUnusedPoints(out);
    mesh = std::move(out);
    return r;
}

}  // namespace

DissolveResult dissolveEdges(Mesh& mesh, const std::vector<bool>& edges, bool cleanPoints) {
    DissolveResult r;
    completeEdges(mesh, true);
    Faces faces(mesh);
    // Which face holds each undirected edge, by face-vertex of its first point.
    std::unordered_map<uint64_t, std::vector<uint32_t>> facesOn;
    for (size_t f = 0; f < faces.loops.size(); ++f)
        for (const std::vector<uint32_t>& loop : faces.loops[f])
            for (size_t k = 0; k < loop.size(); ++k)
                facesOn[edgeKey(mesh.faceVertices[loop[k]], mesh.faceVertices[loop[(k + 1) % loop.size()]])].push_back(uint32_t(f));
    std::vector<uint32_t> owner(faces.loops.size());  // merged faces point at their survivor
    for (size_t f = 0; f < owner.size(); ++f) owner[f] = uint32_t(f);
    auto root = [&](uint32_t f) {
        while (owner[f] != f) f = owner[f] = owner[owner[f]];
        return f;
    };
    std::unordered_set<uint64_t> dropped;
    for (size_t e = 0; e < std::min(edges.size(), mesh.edges.size()); ++e) {
        if (!edges[e]) continue;
        const uint32_t a = mesh.edges[e].v0, b = mesh.edges[e].v1;
        const uint64_t key = edgeKey(a, b);
        std::vector<uint32_t> on;
        for (uint32_t f : facesOn[key]) {
            const uint32_t s = root(f);
            if (!faces.gone[s] && std::find(on.begin(), on.end(), s) == on.end()) on.push_back(s);
        }
        if (on.size() == 1) {
            // A border edge (or one with the same face on both sides): a face on one side only
            // goes with it; a face on both sides keeps it.
            size_t uses = 0;
            for (const std::vector<uint32_t>& loop : faces.loops[on[0]])
                for (size_t k = 0; k < loop.size(); ++k)
                    uses += edgeKey(mesh.faceVertices[loop[k]], mesh.faceVertices[loop[(k + 1) % loop.size()]]) == key;
            if (uses == 1) {
                faces.gone[on[0]] = true;
                dropped.insert(key);
            }
            continue;
        }
        if (on.size() != 2) continue;
        const uint32_t keep = std::min(on[0], on[1]), absorb = std::max(on[0], on[1]);
        // Find the edge in each face's outer loop; merging across holes is left alone.
        std::vector<uint32_t>& A = faces.loops[keep].front();
        std::vector<uint32_t>& B = faces.loops[absorb].front();
        auto at = [&](const std::vector<uint32_t>& loop, uint32_t from, uint32_t to) -> int64_t {
            for (size_t k = 0; k < loop.size(); ++k)
                if (mesh.faceVertices[loop[k]] == from && mesh.faceVertices[loop[(k + 1) % loop.size()]] == to) return int64_t(k);
            return -1;
        };
        int64_t ia = at(A, a, b), ib = at(B, b, a);
        uint32_t p = a, q = b;
        if (ia < 0 || ib < 0) {
            ia = at(A, b, a);
            ib = at(B, a, b);
            p = b;
            q = a;
        }
        if (ia < 0 || ib < 0) continue;  // the faces do not run the edge opposite ways
        (void)p;
        (void)q;
        // A from the edge's second point round to its first, then B between them.
        const uint32_t firstCorner = A.front();
        std::vector<uint32_t> merged;
        for (size_t k = 1; k <= A.size(); ++k) merged.push_back(A[(size_t(ia) + k) % A.size()]);
        for (size_t k = 2; k < B.size(); ++k) merged.push_back(B[(size_t(ib) + k) % B.size()]);
        cutSpikes(mesh, merged);
        const auto start = std::find(merged.begin(), merged.end(), firstCorner);
        if (start != merged.end()) std::rotate(merged.begin(), start, merged.end());
        A = std::move(merged);
        for (size_t l = 1; l < faces.loops[absorb].size(); ++l) faces.loops[keep].push_back(faces.loops[absorb][l]);
        faces.loops[absorb].clear();
        faces.gone[absorb] = true;
        owner[absorb] = keep;
        dropped.insert(key);
        ++r.dissolvedEdges;
    }
    const size_t removedBefore = size_t(std::count(faces.gone.begin(), faces.gone.end(), true)) - r.dissolvedEdges;
    // The ends of the dissolved edges, numbered as they will be once unused points have gone
    // (removeUnusedPoints keeps the order of the rest).
    std::vector<bool> ends;
    if (cleanPoints) {
        std::vector<bool> used(mesh.points.size(), false);
        for (size_t f = 0; f < faces.loops.size(); ++f)
            if (!faces.gone[f])
                for (const std::vector<uint32_t>& loop : faces.loops[f])
                    if (loop.size() >= 3)
                        for (uint32_t fv : loop) used[mesh.faceVertices[fv]] = true;
        std::vector<uint32_t> renumber(mesh.points.size(), UINT32_MAX);
        uint32_t next = 0;
        for (size_t p = 0; p < used.size(); ++p)
            if (used[p]) renumber[p] = next++;
        ends.assign(next, false);
        for (uint64_t key : dropped)
            for (const uint32_t p : {uint32_t(key >> 32), uint32_t(key & 0xffffffffu)})
                if (p < renumber.size() && renumber[p] != UINT32_MAX) ends[renumber[p]] = true;
    }
    DissolveResult out = rebuild(mesh, faces, dropped, r);
    out.removedFaces += removedBefore;
    if (cleanPoints) {
        const DissolveResult winged = removeWingedPoints(mesh, ends);
        out.removedPoints += winged.removedPoints;
    }
    return out;
}

DissolveResult removeWingedPoints(Mesh& mesh, const std::vector<bool>& points) {
    DissolveResult r;
    completeEdges(mesh, true);
    std::vector<uint32_t> valence(mesh.points.size(), 0);
    for (const MeshEdge& e : mesh.edges) {
        ++valence[e.v0];
        ++valence[e.v1];
    }
    std::vector<bool> remove(mesh.points.size(), false);
    for (size_t p = 0; p < std::min(points.size(), mesh.points.size()); ++p) {
        if (!points[p]) continue;
        if (valence[p] == 2) remove[p] = true;
        else ++r.keptPoints;
    }
    Faces faces(mesh);
    for (auto& face : faces.loops)
        for (std::vector<uint32_t>& loop : face)
            loop.erase(std::remove_if(loop.begin(), loop.end(), [&](uint32_t fv) { return remove[mesh.faceVertices[fv]]; }),
                       loop.end());
    // The two edges at a removed point become one, in the place of the first.
    std::vector<MeshEdge> edges;
    std::unordered_map<uint32_t, size_t> firstAt;  // removed point → its first edge's slot
    for (const MeshEdge& e : mesh.edges) {
        if (remove[e.v0] || remove[e.v1]) {
            const uint32_t w = remove[e.v0] ? e.v0 : e.v1, keepEnd = remove[e.v0] ? e.v1 : e.v0;
            if (const auto it = firstAt.find(w); it != firstAt.end()) {
                MeshEdge& first = edges[it->second];
                // The first edge stays in its place and direction, reaching this one's far end.
                if (first.v0 == w) first.v0 = keepEnd;
                else first.v1 = keepEnd;
                firstAt.erase(it);
            } else {
                firstAt[w] = edges.size();
                edges.push_back(e);
            }
            continue;
        }
        edges.push_back(e);
    }
    mesh.edges = std::move(edges);
    return rebuild(mesh, faces, {}, r);
}

size_t closeBorders(Mesh& mesh, const std::vector<bool>& edges) {
    completeEdges(mesh, true);
    // Border edges as the faces run them: a → b once, and never b → a.
    std::unordered_map<uint64_t, int> uses;
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> run;
    for (size_t l = 0; l < mesh.loopCount(); ++l) {
        const std::span<const uint32_t> lp = mesh.loop(l);
        for (size_t k = 0; k < lp.size(); ++k) {
            const uint32_t a = lp[k], b = lp[(k + 1) % lp.size()];
            ++uses[edgeKey(a, b)];
            run[edgeKey(a, b)] = {a, b};
        }
    }
    // next[b] = a for every selected border edge a → b: the new face runs b → a.
    std::unordered_map<uint32_t, std::pair<uint32_t, size_t>> next;  // point → (next point, edge index)
    std::vector<size_t> border;
    for (size_t e = 0; e < std::min(edges.size(), mesh.edges.size()); ++e) {
        if (!edges[e]) continue;
        const uint64_t key = edgeKey(mesh.edges[e].v0, mesh.edges[e].v1);
        if (const auto it = uses.find(key); it == uses.end() || it->second != 1) continue;
        const auto [a, b] = run[key];
        if (next.count(b)) continue;  // a point where borders cross: left open
        next[b] = {a, e};
        border.push_back(e);
    }
    std::vector<bool> done(mesh.edges.size(), false);
    size_t added = 0;
    for (size_t e : border) {  // ascending edge index
        if (done[e]) continue;
        const auto [a, b] = run[edgeKey(mesh.edges[e].v0, mesh.edges[e].v1)];
        std::vector<uint32_t> loop{b};
        std::vector<size_t> used{e};
        uint32_t at = a;
        bool closed = false;
        while (loop.size() <= next.size()) {
            if (at == b) {
                closed = true;
                break;
            }
            loop.push_back(at);
            const auto it = next.find(at);
            if (it == next.end() || done[it->second.second]) break;
            used.push_back(it->second.second);
            at = it->second.first;
        }
        for (size_t u : used) done[u] = true;
        if (!closed || loop.size() < 3) continue;
        mesh.addFace(loop);
        ++added;
    }
    return added;
}

}  // namespace pushpin::geom
