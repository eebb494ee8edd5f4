#include "core/render/shading_points.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace pushpin::render {

ShadingPoint shadingPointOn(const ShadingTriangle& t, const glm::dvec3& origin, const glm::dvec3& dir) {
    ShadingPoint s;
    const glm::dvec3 &p0 = t.p[0], &p1 = t.p[1], &p2 = t.p[2];
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec3 n = glm::cross(e1, e2);
    const double nn = glm::dot(n, n);
    const double denom = glm::dot(n, dir);
    double b0 = 1.0 / 3.0, b1 = 1.0 / 3.0, b2 = 1.0 / 3.0;
    glm::dvec3 p = (p0 + p1 + p2) / 3.0;
    if (nn > 0.0 && std::fabs(denom) > 1e-300) {
        const double along = glm::dot(n, p0 - origin) / denom;
        const glm::dvec3 hit = origin + dir * along;
        const glm::dvec3 d = hit - p0;
        b1 = glm::dot(glm::cross(d, e2), n) / nn;
        b2 = glm::dot(glm::cross(e1, d), n) / nn;
        b0 = 1.0 - b1 - b2;
        if (std::isfinite(b0) && std::isfinite(b1) && std::isfinite(b2)) {
            p = hit;
            if (b0 < 0.0 || b1 < 0.0 || b2 < 0.0) {
                b0 = std::max(b0, 0.0), b1 = std::max(b1, 0.0), b2 = std::max(b2, 0.0);
                const double sum = b0 + b1 + b2;
                b0 /= sum, b1 /= sum, b2 /= sum;
                p = p0 * b0 + p1 * b1 + p2 * b2;
            }
        } else {
            b0 = b1 = b2 = 1.0 / 3.0;
        }
    }
    glm::dvec3 ng = nn > 0.0 ? n / std::sqrt(nn) : -dir;
    glm::dvec3 ns = t.n[0] * b0 + t.n[1] * b1 + t.n[2] * b2;
    const double nsLen = glm::length(ns);
    ns = nsLen > 1e-12 ? ns / nsLen : ng;
    if (t.opposite) {
        ng = -ng;
        ns = -ns;
    }
    if (glm::dot(ng, dir) > 0.0) {
        ng = -ng;
        ns = -ns;
        s.flipped = true;
    }
    s.position = p;
    s.weight[0] = b0, s.weight[1] = b1, s.weight[2] = b2;
    s.shadingNormal = ns;
    s.geometricNormal = ng;
    if (t.hasUvs) {
        s.uv = t.uv[0] * b0 + t.uv[1] * b1 + t.uv[2] * b2;
        const glm::dvec2 d1 = t.uv[1] - t.uv[0], d2 = t.uv[2] - t.uv[0];
        const double det = d1.x * d2.y - d2.x * d1.y;
        if (std::fabs(det) > 1e-20) {
            s.tangentU = (e1 * d2.y - e2 * d1.y) / det;
            s.tangentV = (e2 * d1.x - e1 * d2.x) / det;
        }
    }
    return s;
}

}  // namespace pushpin::render
