// core/geom/detail/face_edit.cpp: FaceEditor and polygon weights.
#include "core/geom/detail/face_edit.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::geom::detail {

FaceEditor::FaceEditor(Mesh& work) : m_work(work), m_originalFaces(work.faceCount()) {}

FaceLoops& FaceEditor::face(uint32_t f) {
    if (f >= m_originalFaces) return m_appended[f - m_originalFaces];
    auto [it, fresh] = m_edited.try_emplace(f);
    if (!fresh) return it->second;
    const size_t uvSets = m_work.uvSets.size(), colorSets = m_work.colorSets.size();
    for (uint32_t l = m_work.faceLoopStarts[f]; l < m_work.faceLoopStarts[f + 1]; ++l) {
        std::vector<Corner>& loop = it->second.emplace_back();
        for (uint32_t fv = m_work.loopStarts[l]; fv < m_work.loopStarts[l + 1]; ++fv) {
            Corner c{m_work.faceVertices[fv], glm::vec3(0.0f), std::vector<int32_t>(uvSets, -1), std::vector<int32_t>(colorSets, -1)};
            if (!m_work.normals.empty()) c.normal = m_work.normals[fv];
            for (size_t s = 0; s < uvSets; ++s)
                if (!m_work.uvSets[s].faceVertexUvs.empty()) c.uvs[s] = m_work.uvSets[s].faceVertexUvs[fv];
            for (size_t s = 0; s < colorSets; ++s)
                if (!m_work.colorSets[s].faceVertexColors.empty()) c.colors[s] = m_work.colorSets[s].faceVertexColors[fv];
            loop.push_back(std::move(c));
        }
    }
    return it->second;
}

uint32_t FaceEditor::append(FaceLoops loops) {
    m_appended.push_back(std::move(loops));
    return uint32_t(faceCount() - 1);
}

Corner FaceEditor::cornerOnEdge(const Corner& a, const Corner& b, uint32_t point, double t) {
    Corner c{point, glm::vec3(0.0f), std::vector<int32_t>(m_work.uvSets.size(), -1),
             std::vector<int32_t>(m_work.colorSets.size(), -1)};
    for (size_t s = 0; s < m_work.uvSets.size(); ++s) {
        const int32_t ua = a.uvs[s], ub = b.uvs[s];
        std::vector<glm::vec2>& uvs = m_work.uvSets[s].uvs;
        if (ua < 0 || ub < 0 || size_t(ua) >= uvs.size() || size_t(ub) >= uvs.size()) continue;
        if (ua == ub) {
            c.uvs[s] = ua;
            continue;
        }
        const auto key = ua < ub ? std::make_tuple(s, ua, ub, t) : std::make_tuple(s, ub, ua, 1.0 - t);
        auto [it, fresh] = m_edgeUvs.try_emplace(key, int32_t(uvs.size()));
        if (fresh) uvs.push_back(glm::mix(uvs[size_t(ua)], uvs[size_t(ub)], float(t)));
        c.uvs[s] = it->second;
    }
    return c;
}

Corner FaceEditor::cornerFromWeights(std::span<const Corner> corners, std::span<const double> weights, uint32_t point) {
    Corner c{point, glm::vec3(0.0f), std::vector<int32_t>(m_work.uvSets.size(), -1),
             std::vector<int32_t>(m_work.colorSets.size(), -1)};
    for (size_t s = 0; s < m_work.uvSets.size(); ++s) {
        std::vector<glm::vec2>& uvs = m_work.uvSets[s].uvs;
        glm::dvec2 sum(0.0);
        bool all = !corners.empty();
        for (size_t i = 0; i < corners.size() && all; ++i) {
            const int32_t u = corners[i].uvs[s];
            all = u >= 0 && size_t(u) < uvs.size();
            if (all) sum += weights[i] * glm::dvec2(uvs[size_t(u)]);
        }
        if (!all) continue;
        c.uvs[s] = int32_t(uvs.size());
        uvs.push_back(glm::vec2(sum));
    }
    return c;
}

Mesh FaceEditor::rebuild() {
    Mesh out = facelessCopy(m_work, std::move(m_work.points));
    const bool hasNormals = !m_work.normals.empty();
    const size_t uvSets = m_work.uvSets.size(), colorSets = m_work.colorSets.size();
    auto emit = [&](const FaceLoops& loops) {
        for (const std::vector<Corner>& loop : loops) {
            for (const Corner& c : loop) {
                out.faceVertices.push_back(c.point);
                if (hasNormals) out.normals.push_back(c.normal);
                for (size_t s = 0; s < uvSets; ++s)
                    if (!m_work.uvSets[s].faceVertexUvs.empty()) out.uvSets[s].faceVertexUvs.push_back(c.uvs[s]);
                for (size_t s = 0; s < colorSets; ++s)
                    if (!m_work.colorSets[s].faceVertexColors.empty()) out.colorSets[s].faceVertexColors.push_back(c.colors[s]);
            }
            out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        }
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    };
    // A UV or colour set that mapped no face still maps none, unless a new corner was given one.
    for (size_t f = 0; f < m_originalFaces; ++f) {
        if (const auto it = m_edited.find(uint32_t(f)); it != m_edited.end()) {
            emit(it->second);
            continue;
        }
        for (uint32_t l = m_work.faceLoopStarts[f]; l < m_work.faceLoopStarts[f + 1]; ++l) {
            for (uint32_t fv = m_work.loopStarts[l]; fv < m_work.loopStarts[l + 1]; ++fv) copyFaceVertex(out, m_work, fv);
            out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        }
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    for (const FaceLoops& loops : m_appended) emit(loops);
    out.edges = std::move(m_work.edges);
    return out;
}

std::vector<double> polygonWeights(std::span<const glm::dvec3> loop, const glm::dvec3& p, const glm::dvec3& normal) {
    const size_t n = loop.size();
    std::vector<double> w(n, 0.0);
    if (n == 0) return w;
    // A basis of the plane.
    const glm::dvec3 nz = glm::length(normal) > 0.0 ? glm::normalize(normal) : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec3 helper = std::abs(nz.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    const glm::dvec3 ux = glm::normalize(glm::cross(helper, nz)), uy = glm::cross(nz, ux);
    std::vector<glm::dvec2> s(n);
    double scale = 0.0;
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec3 d = loop[i] - p;
        s[i] = {glm::dot(d, ux), glm::dot(d, uy)};
        scale = std::max(scale, glm::length(s[i]));
    }
    const double eps = 1e-12 * std::max(scale, 1e-300);
    for (size_t i = 0; i < n; ++i)
        if (glm::length(s[i]) <= eps) {
            w[i] = 1.0;
            return w;
        }
    // On an edge: linear along it.
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = s[i], b = s[(i + 1) % n];
        const double area = a.x * b.y - a.y * b.x;
        if (std::abs(area) <= eps * glm::length(b - a) && glm::dot(a, b) < 0.0) {
            const double la = glm::length(a), lb = glm::length(b);
            w[i] = lb / (la + lb);
            w[(i + 1) % n] = la / (la + lb);
            return w;
        }
    }
    // tan(alpha_i / 2) for the angle at p between corners i and i+1.
    std::vector<double> halfTan(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = s[i], b = s[(i + 1) % n];
        const double area = a.x * b.y - a.y * b.x, dot = glm::dot(a, b);
        halfTan[i] = area != 0.0 ? (glm::length(a) * glm::length(b) - dot) / area : 0.0;
    }
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        w[i] = (halfTan[(i + n - 1) % n] + halfTan[i]) / glm::length(s[i]);
        sum += w[i];
    }
    if (!std::isfinite(sum) || std::abs(sum) < 1e-300) {
        std::fill(w.begin(), w.end(), 1.0 / double(n));
        return w;
    }
    for (double& x : w) x /= sum;
    return w;
}

}  // namespace pushpin::geom::detail
