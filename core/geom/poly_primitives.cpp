// core/geom/poly_primitives.cpp: generators for Maya's polygon creator nodes.
#include "core/geom/poly_primitives.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <unordered_map>

namespace pushpin::geom {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

bool fail(std::string* error, std::string message) {
    if (error) *error = std::move(message);
    return false;
}

// Rejects a non-finite size; clamps a negative one to 0 (Maya's minimum).
bool checkSize(const char* node, const char* attr, double& value, std::string* error) {
    if (!std::isfinite(value))
        return fail(error, std::string(node) + ": " + attr + " is not a finite number");
    value = std::max(value, 0.0);
    return true;
}

bool checkFaceCount(const char* node, double faces, std::string* error) {
    if (faces > double(kMaxPrimitiveFaces))
        return fail(error, std::string(node) + ": the subdivisions would make " + std::to_string(int64_t(faces)) +
                               " faces, more than the limit of " + std::to_string(kMaxPrimitiveFaces));
    return true;
}

// Accumulates points, faces and per-face-vertex UV ids; applies the axis rotation at the end.
struct Builder {
    explicit Builder(bool withUvs) : uvs(withUvs) {}

    uint32_t point(double x, double y, double z) {
        mesh.points.emplace_back(float(x), float(y), float(z));
        return uint32_t(mesh.points.size() - 1);
    }
    int32_t uv(double u, double v) {
        uvValues.emplace_back(float(std::clamp(u, 0.0, 1.0)), float(std::clamp(v, 0.0, 1.0)));
        return int32_t(uvValues.size() - 1);
    }
    void face(std::initializer_list<uint32_t> verts, std::initializer_list<int32_t> uvIds) {
        mesh.addFace(std::span(verts.begin(), verts.size()));
        if (uvs) fvUvs.insert(fvUvs.end(), uvIds.begin(), uvIds.end());
    }
    void face(const std::vector<uint32_t>& verts, const std::vector<int32_t>& uvIds) {
        mesh.addFace(std::span(verts));
        if (uvs) fvUvs.insert(fvUvs.end(), uvIds.begin(), uvIds.end());
    }
    Mesh finish(const glm::dvec3& axis, bool smoothEdges) {
        const glm::dmat3 rot = axisRotation(axis);
        if (rot != glm::dmat3(1.0))
            for (glm::vec3& p : mesh.points) p = glm::vec3(rot * glm::dvec3(p));
        mesh.edges = deriveEdges(mesh, smoothEdges);
        if (uvs) {
            mesh.uvSets.push_back({"map1", std::move(uvValues), std::move(fvUvs)});
            mesh.currentUvSet = 0;
        }
        return std::move(mesh);
    }

    Mesh mesh;
    bool uvs;
    std::vector<glm::vec2> uvValues;
    std::vector<int32_t> fvUvs;
};

// Marks hard every edge whose two points both lie in [first, first + count).
void hardenRing(Mesh& mesh, uint32_t first, uint32_t count) {
    for (MeshEdge& e : mesh.edges)
        if (e.v0 >= first && e.v0 < first + count && e.v1 >= first && e.v1 < first + count) e.smooth = false;
}

}  // namespace

glm::dmat3 axisRotation(const glm::dvec3& axisIn) {
    const double len = glm::length(axisIn);
    if (!(len > 0.0) || !std::isfinite(len)) return glm::dmat3(1.0);
    const glm::dvec3 a = axisIn / len;
    const glm::dvec3 up(0.0, 1.0, 0.0);
    const double c = glm::dot(up, a);
    if (c > 1.0 - 1e-12) return glm::dmat3(1.0);
    if (c < -1.0 + 1e-12) return glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    // Rodrigues' formula about k = up × a (unit), angle acos(c).
    const glm::dvec3 k = glm::normalize(glm::cross(up, a));
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    const glm::dmat3 kx(glm::dvec3(0, k.z, -k.y), glm::dvec3(-k.z, 0, k.x), glm::dvec3(k.y, -k.x, 0));
    return glm::dmat3(1.0) + s * kx + (1.0 - c) * (kx * kx);
}

// ------------------------------------------------------------------------------------ polyCube
namespace {

// Puts the listed edges first, in that order and direction (flags kept), the others after them
// in their order: how the primitives give their edges Maya's numbers.
void orderEdges(Mesh& mesh, const std::vector<std::pair<uint32_t, uint32_t>>& order) {
    std::vector<MeshEdge> ordered;
    ordered.reserve(mesh.edges.size());
    std::vector<bool> taken(mesh.edges.size(), false);
    std::unordered_map<uint64_t, size_t> edgeIndex;
    edgeIndex.reserve(mesh.edges.size());
    for (size_t e = 0; e < mesh.edges.size(); ++e) edgeIndex.emplace(edgeKey(mesh.edges[e].v0, mesh.edges[e].v1), e);
    for (const auto& [a, c] : order) {
        const auto it = edgeIndex.find(edgeKey(a, c));
        if (it == edgeIndex.end() || taken[it->second]) continue;
        taken[it->second] = true;
        MeshEdge edge = mesh.edges[it->second];
        edge.v0 = a;
        edge.v1 = c;
        ordered.push_back(edge);
    }
    for (size_t e = 0; e < mesh.edges.size(); ++e)
        if (!taken[e]) ordered.push_back(mesh.edges[e]);
    mesh.edges = std::move(ordered);
}

}  // namespace

std::optional<Mesh> makePolyCube(const PolyCubeParams& pIn, std::string* error) {
    PolyCubeParams p = pIn;
    if (!checkSize("polyCube", "width", p.width, error) || !checkSize("polyCube", "height", p.height, error) ||
        !checkSize("polyCube", "depth", p.depth, error))
        return std::nullopt;
    const int sw = std::max(1, p.subdivisionsWidth), sh = std::max(1, p.subdivisionsHeight),
              sd = std::max(1, p.subdivisionsDepth);
    if (!checkFaceCount("polyCube", 2.0 * (double(sw) * sh + double(sw) * sd + double(sh) * sd), error))
        return std::nullopt;
    const double w = p.width, h = p.height, d = p.depth;
    const int K = 2 * (sh + sd);  // rows of the belt around X
    Builder b(p.createUVs);

    // Belt rows: (y, z) of row k and its v coordinate in the unfolded layout.
    auto rowYZ = [&](int k) {
        if (k <= sh) return glm::dvec2(-h / 2 + h * k / sh, d / 2);
        if (k <= sh + sd) return glm::dvec2(h / 2, d / 2 - d * (k - sh) / sd);
        if (k <= 2 * sh + sd) return glm::dvec2(h / 2 - h * (k - sh - sd) / sh, -d / 2);
        return glm::dvec2(-h / 2, -d / 2 + d * (k - 2 * sh - sd) / sd);
    };
    auto rowV = [&](int k) {
        if (k <= sh) return 0.25 * k / sh;
        if (k <= sh + sd) return 0.25 + 0.25 * (k - sh) / sd;
        if (k <= 2 * sh + sd) return 0.5 + 0.25 * (k - sh - sd) / sh;
        return 0.75 + 0.25 * (k - 2 * sh - sd) / sd;
    };
    for (int k = 0; k < K; ++k) {
        const glm::dvec2 yz = rowYZ(k);
        for (int i = 0; i <= sw; ++i) b.point(-w / 2 + w * i / sw, yz.x, yz.y);
    }
    const uint32_t rightBase = uint32_t(b.mesh.points.size());
    for (int side = 0; side < 2; ++side) {
        const double x = side == 0 ? w / 2 : -w / 2;
        for (int yb = 1; yb < sh; ++yb)
            for (int c = 1; c < sd; ++c) b.point(x, -h / 2 + h * yb / sh, side == 0 ? -d / 2 + d * c / sd : d / 2 - d * c / sd);
    }
    const uint32_t leftBase = rightBase + uint32_t((sh - 1) * (sd - 1));
    auto beltPoint = [&](int k, int i) { return uint32_t((k % K) * (sw + 1) + i); };
    // Point of a side grid: c counts depth steps from the front, yb height steps from the bottom.
    auto sidePoint = [&](bool right, int c, int yb) {
        const int i = right ? sw : 0;
        if (c == 0) return beltPoint(yb, i);
        if (yb == sh) return beltPoint(sh + c, i);
        if (c == sd) return beltPoint(sh + sd + (sh - yb), i);
        if (yb == 0) return beltPoint(2 * sh + sd + (sd - c), i);
        return (right ? rightBase : leftBase) + uint32_t((yb - 1) * (sd - 1) + (right ? sd - 1 - c : c - 1));
    };

    int32_t beltUv0 = 0, rightUv0 = 0, leftUv0 = 0;
    if (p.createUVs) {
        for (int k = 0; k <= K; ++k)
            for (int i = 0; i <= sw; ++i) b.uv(0.375 + 0.25 * i / sw, rowV(k));
        rightUv0 = int32_t(b.uvValues.size());
        for (int c = 1; c <= sd; ++c)
            for (int yb = 0; yb <= sh; ++yb) b.uv(0.625 + 0.25 * c / sd, 0.25 * yb / sh);
        leftUv0 = int32_t(b.uvValues.size());
        for (int c = 0; c < sd; ++c)
            for (int yb = 0; yb <= sh; ++yb) b.uv(0.125 + 0.25 * c / sd, 0.25 * yb / sh);
    }
    auto beltUv = [&](int k, int i) { return beltUv0 + int32_t(k * (sw + 1) + i); };
    auto rightUv = [&](int c, int yb) { return c == 0 ? beltUv(yb, sw) : rightUv0 + (c - 1) * (sh + 1) + yb; };
    // On the -X side, cb counts depth steps from the back.
    auto leftUv = [&](int cb, int yb) { return cb == sd ? beltUv(yb, 0) : leftUv0 + cb * (sh + 1) + yb; };

    for (int k = 0; k < K; ++k)
        for (int i = 0; i < sw; ++i)
            b.face({beltPoint(k, i), beltPoint(k, i + 1), beltPoint(k + 1, i + 1), beltPoint(k + 1, i)},
                   {beltUv(k, i), beltUv(k, i + 1), beltUv(k + 1, i + 1), beltUv(k + 1, i)});
    for (int yb = 0; yb < sh; ++yb)
        for (int c = sd - 1; c >= 0; --c)
            b.face({sidePoint(true, c, yb), sidePoint(true, c + 1, yb), sidePoint(true, c + 1, yb + 1),
                    sidePoint(true, c, yb + 1)},
                   {rightUv(c, yb), rightUv(c + 1, yb), rightUv(c + 1, yb + 1), rightUv(c, yb + 1)});
    for (int yb = 0; yb < sh; ++yb)
        for (int cb = 0; cb < sd; ++cb)
            b.face({sidePoint(false, sd - cb, yb), sidePoint(false, sd - cb - 1, yb),
                    sidePoint(false, sd - cb - 1, yb + 1), sidePoint(false, sd - cb, yb + 1)},
                   {leftUv(cb, yb), leftUv(cb + 1, yb), leftUv(cb + 1, yb + 1), leftUv(cb, yb + 1)});
    Mesh mesh = b.finish(p.axis, false);
    // Maya's edge order: along X row by row round the belt, then round the belt row by row and
    // column by column, then the edges inside the ±X sides (for 1×1×1 exactly Maya's
    // "0 1, 2 3, 4 5, 6 7, 0 2, 1 3, 2 4, 3 5, 4 6, 5 7, 6 0, 7 1").
    std::vector<std::pair<uint32_t, uint32_t>> order;
    for (int k = 0; k < K; ++k)
        for (int i = 0; i < sw; ++i) order.push_back({beltPoint(k, i), beltPoint(k, i + 1)});
    for (int k = 0; k < K; ++k)
        for (int i = 0; i <= sw; ++i) order.push_back({beltPoint(k, i), beltPoint(k + 1, i)});
    orderEdges(mesh, order);
    return mesh;
}

// ---------------------------------------------------------------------------------- polySphere
std::optional<Mesh> makePolySphere(const PolySphereParams& pIn, std::string* error) {
    PolySphereParams p = pIn;
    if (!checkSize("polySphere", "radius", p.radius, error)) return std::nullopt;
    const int sa = std::max(3, p.subdivisionsAxis), sh = std::max(2, p.subdivisionsHeight);
    if (!checkFaceCount("polySphere", double(sa) * sh, error)) return std::nullopt;
    const double r = p.radius;
    Builder b(p.createUVs);
    for (int ring = 1; ring < sh; ++ring) {
        const double theta = std::numbers::pi * ring / sh;  // from the south pole
        const double y = -r * std::cos(theta), rho = r * std::sin(theta);
        for (int j = 0; j < sa; ++j) {
            // Maya's point 0 of a ring is one step round from +x.
            const double phi = kTwoPi * (j + 1) / sa;
            b.point(rho * std::cos(phi), y, -rho * std::sin(phi));
        }
    }
    const uint32_t south = b.point(0, -r, 0);
    const uint32_t north = b.point(0, r, 0);
    auto pt = [&](int ring, int j) { return uint32_t((ring - 1) * sa + (j % sa)); };
    int32_t poleUv0 = 0;
    if (p.createUVs) {
        for (int ring = 1; ring < sh; ++ring)
            for (int j = 0; j <= sa; ++j) b.uv(double(j) / sa, double(ring) / sh);
        poleUv0 = int32_t(b.uvValues.size());
        for (int j = 0; j < sa; ++j) b.uv((j + 0.5) / sa, 0.0);
        for (int j = 0; j < sa; ++j) b.uv((j + 0.5) / sa, 1.0);
    }
    auto uv = [&](int ring, int j) { return int32_t((ring - 1) * (sa + 1) + j); };
    for (int ring = 1; ring + 1 < sh; ++ring)
        for (int j = 0; j < sa; ++j)
            b.face({pt(ring, j), pt(ring, j + 1), pt(ring + 1, j + 1), pt(ring + 1, j)},
                   {uv(ring, j), uv(ring, j + 1), uv(ring + 1, j + 1), uv(ring + 1, j)});
    for (int j = 0; j < sa; ++j) b.face({pt(1, j + 1), pt(1, j), south}, {uv(1, j + 1), uv(1, j), poleUv0 + j});
    for (int j = 0; j < sa; ++j)
        b.face({pt(sh - 1, j), pt(sh - 1, j + 1), north}, {uv(sh - 1, j), uv(sh - 1, j + 1), poleUv0 + sa + j});
    return b.finish(p.axis, true);
}

// ----------------------------------------------------------------------------------- polyPlane
std::optional<Mesh> makePolyPlane(const PolyPlaneParams& pIn, std::string* error) {
    PolyPlaneParams p = pIn;
    if (!checkSize("polyPlane", "width", p.width, error) || !checkSize("polyPlane", "height", p.height, error))
        return std::nullopt;
    const int sw = std::max(1, p.subdivisionsWidth), sh = std::max(1, p.subdivisionsHeight);
    if (!checkFaceCount("polyPlane", double(sw) * sh, error)) return std::nullopt;
    Builder b(p.createUVs);
    for (int row = 0; row <= sh; ++row)
        for (int i = 0; i <= sw; ++i) {
            b.point(-p.width / 2 + p.width * i / sw, 0.0, p.height / 2 - p.height * row / sh);
            if (p.createUVs) b.uv(double(i) / sw, double(row) / sh);
        }
    auto id = [&](int row, int i) { return uint32_t(row * (sw + 1) + i); };
    for (int row = 0; row < sh; ++row)
        for (int i = 0; i < sw; ++i) {
            const uint32_t a = id(row, i), c = id(row, i + 1), e = id(row + 1, i + 1), g = id(row + 1, i);
            b.face({a, c, e, g}, {int32_t(a), int32_t(c), int32_t(e), int32_t(g)});
        }
    return b.finish(p.axis, true);
}

// --------------------------------------------------------------------- polyCylinder / polyCone
namespace {

constexpr double kSideV0 = 0.3125, kSideV1 = 0.6875, kCapRadius = 0.15625;

// Adds a flat cap closing `outerRing` (sa points, counter-clockwise seen from +Y) at height y with
// `caps` rings (0: one n-gon). `down` caps face −Y. UVs go in a disc centred at (0.5, centreV).
// `phase` turns the inner rings by that many steps, to line up with the outer ring's first point.
void addCap(Builder& b, const std::vector<uint32_t>& outerRing, double radius, double y, int sa, int caps,
            bool down, double centreV, int phase) {
    const int rings = std::max(1, caps);
    std::vector<std::vector<uint32_t>> ring(rings);
    std::vector<std::vector<int32_t>> ringUv(rings);
    ring[0] = outerRing;
    for (int c = 1; c < rings; ++c)
        for (int j = 0; j < sa; ++j) {
            const double phi = kTwoPi * (j + phase) / sa, rho = radius * (1.0 - double(c) / caps);
            ring[c].push_back(b.point(rho * std::cos(phi), y, -rho * std::sin(phi)));
        }
    uint32_t centre = 0;
    if (caps >= 1) centre = b.point(0.0, y, 0.0);
    int32_t centreUv = 0;
    if (b.uvs) {
        // Seen from below the disc is mirrored in u so the texture reads the right way round.
        const double mirror = down ? -1.0 : 1.0;
        for (int c = 0; c < rings; ++c)
            for (int j = 0; j < sa; ++j) {
                const double phi = kTwoPi * (j + phase) / sa, rho = kCapRadius * (1.0 - (caps ? double(c) / caps : 0.0));
                ringUv[c].push_back(b.uv(0.5 + mirror * rho * std::cos(phi), centreV + rho * std::sin(phi)));
            }
        if (caps >= 1) centreUv = b.uv(0.5, centreV);
    } else {
        for (int c = 0; c < rings; ++c) ringUv[c].assign(sa, 0);
    }
    if (caps == 0) {
        std::vector<uint32_t> v(ring[0]);
        std::vector<int32_t> t(ringUv[0]);
        if (down) {
            std::reverse(v.begin(), v.end());
            std::reverse(t.begin(), t.end());
        }
        b.face(v, t);
        return;
    }
    for (int c = 0; c < rings; ++c)
        for (int j = 0; j < sa; ++j) {
            const int k = (j + 1) % sa;
            if (c + 1 < rings) {
                if (down)
                    b.face({ring[c][k], ring[c][j], ring[c + 1][j], ring[c + 1][k]},
                           {ringUv[c][k], ringUv[c][j], ringUv[c + 1][j], ringUv[c + 1][k]});
                else
                    b.face({ring[c][j], ring[c][k], ring[c + 1][k], ring[c + 1][j]},
                           {ringUv[c][j], ringUv[c][k], ringUv[c + 1][k], ringUv[c + 1][j]});
            } else {
                if (down)
                    b.face({ring[c][k], ring[c][j], centre}, {ringUv[c][k], ringUv[c][j], centreUv});
                else
                    b.face({ring[c][j], ring[c][k], centre}, {ringUv[c][j], ringUv[c][k], centreUv});
            }
        }
}

}  // namespace

std::optional<Mesh> makePolyCylinder(const PolyCylinderParams& pIn, std::string* error) {
    PolyCylinderParams p = pIn;
    if (!checkSize("polyCylinder", "radius", p.radius, error) || !checkSize("polyCylinder", "height", p.height, error))
        return std::nullopt;
    const int sa = std::max(3, p.subdivisionsAxis), sh = std::max(1, p.subdivisionsHeight),
              sc = std::max(0, p.subdivisionsCaps);
    if (!checkFaceCount("polyCylinder", double(sa) * (sh + 2.0 * std::max(sc, 1)), error)) return std::nullopt;
    const double r = p.radius, h = p.height;
    Builder b(p.createUVs);
    for (int k = 0; k <= sh; ++k)
        for (int j = 0; j < sa; ++j) {
            // As on Maya's cylinder, point 0 of each ring is one step round from +x.
            const double phi = kTwoPi * (j + 1) / sa;
            b.point(r * std::cos(phi), -h / 2 + h * k / sh, -r * std::sin(phi));
        }
    if (p.createUVs)
        for (int k = 0; k <= sh; ++k)
            for (int j = 0; j <= sa; ++j) b.uv(double(j) / sa, kSideV0 + (kSideV1 - kSideV0) * k / sh);
    auto pt = [&](int k, int j) { return uint32_t(k * sa + j % sa); };
    auto uv = [&](int k, int j) { return int32_t(k * (sa + 1) + j); };
    for (int k = 0; k < sh; ++k)
        for (int j = 0; j < sa; ++j)
            b.face({pt(k, j), pt(k, j + 1), pt(k + 1, j + 1), pt(k + 1, j)},
                   {uv(k, j), uv(k, j + 1), uv(k + 1, j + 1), uv(k + 1, j)});
    // Cap points come after all side points: the bottom cap's inner rings and centre, then the top's.
    std::vector<uint32_t> bottom(sa), top(sa);
    for (int j = 0; j < sa; ++j) {
        bottom[j] = pt(0, j);
        top[j] = pt(sh, j);
    }
    addCap(b, bottom, r, -h / 2, sa, sc, true, kCapRadius, 1);
    addCap(b, top, r, h / 2, sa, sc, false, 1.0 - kCapRadius, 1);
    Mesh mesh = b.finish(p.axis, true);
    hardenRing(mesh, 0, uint32_t(sa));
    hardenRing(mesh, uint32_t(sh * sa), uint32_t(sa));
    // Maya's edge order: round each ring bottom to top, then up each band, then the caps' edges
    // (a later polySplitRing on a real scene names the side edges e[16:23] of an 8-sided cylinder).
    std::vector<std::pair<uint32_t, uint32_t>> order;
    for (int k = 0; k <= sh; ++k)
        for (int j = 0; j < sa; ++j) order.push_back({pt(k, j), pt(k, j + 1)});
    for (int k = 0; k < sh; ++k)
        for (int j = 0; j < sa; ++j) order.push_back({pt(k, j), pt(k + 1, j)});
    orderEdges(mesh, order);
    return mesh;
}

std::optional<Mesh> makePolyCone(const PolyConeParams& pIn, std::string* error) {
    PolyConeParams p = pIn;
    if (!checkSize("polyCone", "radius", p.radius, error) || !checkSize("polyCone", "height", p.height, error))
        return std::nullopt;
    const int sa = std::max(3, p.subdivisionsAxis), sh = std::max(1, p.subdivisionsHeight),
              sc = std::max(0, p.subdivisionsCap);
    if (!checkFaceCount("polyCone", double(sa) * (sh + std::max(sc, 1)), error)) return std::nullopt;
    const double r = p.radius, h = p.height;
    Builder b(p.createUVs);
    for (int k = 0; k < sh; ++k)
        for (int j = 0; j < sa; ++j) {
            const double phi = kTwoPi * j / sa, rho = r * (1.0 - double(k) / sh);
            b.point(rho * std::cos(phi), -h / 2 + h * k / sh, -rho * std::sin(phi));
        }
    const uint32_t apex = b.point(0.0, h / 2, 0.0);
    int32_t apexUv0 = 0;
    if (p.createUVs) {
        for (int k = 0; k < sh; ++k)
            for (int j = 0; j <= sa; ++j) b.uv(double(j) / sa, kSideV0 + (kSideV1 - kSideV0) * k / sh);
        apexUv0 = int32_t(b.uvValues.size());
        for (int j = 0; j < sa; ++j) b.uv((j + 0.5) / sa, kSideV1);
    }
    auto pt = [&](int k, int j) { return uint32_t(k * sa + j % sa); };
    auto uv = [&](int k, int j) { return int32_t(k * (sa + 1) + j); };
    for (int k = 0; k + 1 < sh; ++k)
        for (int j = 0; j < sa; ++j)
            b.face({pt(k, j), pt(k, j + 1), pt(k + 1, j + 1), pt(k + 1, j)},
                   {uv(k, j), uv(k, j + 1), uv(k + 1, j + 1), uv(k + 1, j)});
    for (int j = 0; j < sa; ++j)
        b.face({pt(sh - 1, j), pt(sh - 1, j + 1), apex}, {uv(sh - 1, j), uv(sh - 1, j + 1), apexUv0 + j});
    std::vector<uint32_t> base(sa);
    for (int j = 0; j < sa; ++j) base[j] = pt(0, j);
    addCap(b, base, r, -h / 2, sa, sc, true, kCapRadius, 0);
    Mesh mesh = b.finish(p.axis, true);
    hardenRing(mesh, 0, uint32_t(sa));
    return mesh;
}

// ----------------------------------------------------------------------------------- polyTorus
std::optional<Mesh> makePolyTorus(const PolyTorusParams& pIn, std::string* error) {
    PolyTorusParams p = pIn;
    if (!checkSize("polyTorus", "radius", p.radius, error) ||
        !checkSize("polyTorus", "sectionRadius", p.sectionRadius, error))
        return std::nullopt;
    if (!std::isfinite(p.twistRadians)) {
        fail(error, "polyTorus: twist is not a finite number");
        return std::nullopt;
    }
    const int sa = std::max(3, p.subdivisionsAxis), sh = std::max(3, p.subdivisionsHeight);
    if (!checkFaceCount("polyTorus", double(sa) * sh, error)) return std::nullopt;
    Builder b(p.createUVs);
    for (int a = 0; a < sa; ++a) {
        const double phi = kTwoPi * a / sa;
        for (int s = 0; s < sh; ++s) {
            const double psi = kTwoPi * s / sh + p.twistRadians;
            const double rho = p.radius + p.sectionRadius * std::cos(psi);
            b.point(rho * std::cos(phi), p.sectionRadius * std::sin(psi), -rho * std::sin(phi));
        }
    }
    if (p.createUVs)
        for (int a = 0; a <= sa; ++a)
            for (int s = 0; s <= sh; ++s) b.uv(double(a) / sa, double(s) / sh);
    auto pt = [&](int a, int s) { return uint32_t((a % sa) * sh + s % sh); };
    auto uv = [&](int a, int s) { return int32_t(a * (sh + 1) + s); };
    for (int a = 0; a < sa; ++a)
        for (int s = 0; s < sh; ++s)
            b.face({pt(a, s), pt(a + 1, s), pt(a + 1, s + 1), pt(a, s + 1)},
                   {uv(a, s), uv(a + 1, s), uv(a + 1, s + 1), uv(a, s + 1)});
    return b.finish(p.axis, true);
}

// --------------------------------------------------------------------------- polyPlatonicSolid
std::optional<Mesh> makePolyPlatonicSolid(const PolyPlatonicParams& pIn, std::string* error) {
    PolyPlatonicParams p = pIn;
    if (!checkSize("polyPlatonicSolid", "radius", p.radius, error)) return std::nullopt;
    if (p.solidType < 0 || p.solidType > 3) {
        fail(error, "polyPlatonicSolid: solidType " + std::to_string(p.solidType) + " is not 0..3");
        return std::nullopt;
    }
    const double phi = std::numbers::phi, iphi = 1.0 / std::numbers::phi;
    std::vector<glm::dvec3> icosa, dodeca;
    for (double s1 : {-1.0, 1.0})
        for (double s2 : {-1.0, 1.0}) {
            icosa.push_back({0, s1, s2 * phi});
            icosa.push_back({s1, s2 * phi, 0});
            icosa.push_back({s2 * phi, 0, s1});
            // The dodecahedron dual to this icosahedron (its face centres), not its mirror image.
            dodeca.push_back({0, s1 * phi, s2 * iphi});
            dodeca.push_back({s1 * iphi, 0, s2 * phi});
            dodeca.push_back({s2 * phi, s1 * iphi, 0});
        }
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0})
            for (double sz : {-1.0, 1.0}) dodeca.push_back({sx, sy, sz});
    std::vector<glm::dvec3> verts, faceDirs;
    switch (p.solidType) {
    case 0: verts = dodeca; faceDirs = icosa; break;
    case 1: verts = icosa; faceDirs = dodeca; break;
    case 2:
        verts = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (double sx : {-1.0, 1.0})
            for (double sy : {-1.0, 1.0})
                for (double sz : {-1.0, 1.0}) faceDirs.push_back({sx, sy, sz});
        break;
    default:
        verts = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
        for (const glm::dvec3& v : verts) faceDirs.push_back(-v);
        break;
    }
    Builder b(p.createUVs);
    for (const glm::dvec3& v : verts) {
        const glm::dvec3 q = glm::normalize(v) * p.radius;
        b.point(q.x, q.y, q.z);
    }
    // The faces of a platonic solid are the vertex sets furthest along the dual's vertex
    // directions; each is sorted counter-clockwise about its direction.
    const int faceCount = int(faceDirs.size());
    const int columns = int(std::ceil(std::sqrt(double(faceCount))));
    const double cell = 1.0 / columns;
    for (int f = 0; f < faceCount; ++f) {
        const glm::dvec3 n = glm::normalize(faceDirs[f]);
        double best = -1e300;
        for (const glm::dvec3& v : verts) best = std::max(best, glm::dot(glm::normalize(v), n));
        std::vector<uint32_t> loop;
        for (size_t i = 0; i < verts.size(); ++i)
            if (glm::dot(glm::normalize(verts[i]), n) > best - 1e-9) loop.push_back(uint32_t(i));
        const glm::dvec3 t0 = glm::normalize(glm::normalize(verts[loop[0]]) - n * best);
        const glm::dvec3 t1 = glm::cross(n, t0);
        auto angle = [&](uint32_t i) {
            const glm::dvec3 v = glm::normalize(verts[i]);
            return std::atan2(glm::dot(v, t1), glm::dot(v, t0));
        };
        std::sort(loop.begin(), loop.end(), [&](uint32_t a, uint32_t c) { return angle(a) < angle(c); });
        std::vector<int32_t> uvIds;
        if (p.createUVs) {
            const double cu = (f % columns + 0.5) * cell, cv = (f / columns + 0.5) * cell;
            for (uint32_t i : loop) {
                const double a = angle(i);
                uvIds.push_back(b.uv(cu + 0.45 * cell * std::cos(a), cv + 0.45 * cell * std::sin(a)));
            }
        }
        b.face(loop, uvIds);
    }
    return b.finish(p.axis, false);
}

// ------------------------------------------------------------------------- counts and bounds
namespace {

// Sizes and cells the counts vouch for: finite positive sizes of at most 1e12, cells no thinner
// than 1e-4 of their length and no smaller than 1e-5 of the primitive (float points keep every
// face's area well above Mesh::validate's degenerate threshold).
bool sane(double size) { return std::isfinite(size) && size > 0.0 && size <= 1e12; }
bool saneCell(double a, double b, double extent) {
    return a >= 1e-4 * b && b >= 1e-4 * a && std::min(a, b) >= 1e-5 * extent;
}

// The box of `corners` rotated by the axis rotation, widened for the points' float rounding.
Bounds3 rotatedBox(const glm::dvec3& axis, std::initializer_list<glm::dvec3> corners) {
    const glm::dmat3 rot = axisRotation(axis);
    Bounds3 b;
    double reach = 0.0;
    for (const glm::dvec3& c : corners) {
        const glm::dvec3 r = rot * c;
        b.extend(r);
        reach = std::max({reach, std::fabs(r.x), std::fabs(r.y), std::fabs(r.z)});
    }
    const glm::dvec3 pad(1e-6 * reach);  // about 16 float steps
    b.lo -= pad;
    b.hi += pad;
    return b;
}

}  // namespace

std::optional<PrimitiveCounts> polySphereCounts(const PolySphereParams& p) {
    const uint64_t sa = uint64_t(std::max(3, p.subdivisionsAxis)), sh = uint64_t(std::max(2, p.subdivisionsHeight));
    const double r = p.radius;
    if (!sane(r) || double(sa) * double(sh) > double(kMaxPrimitiveFaces)) return std::nullopt;
    if (!saneCell(kTwoPi * r / double(sa), std::numbers::pi * r / double(sh), r)) return std::nullopt;
    PrimitiveCounts c;
    c.points = sa * (sh - 1) + 2;
    c.faces = sa * sh;
    c.faceVertices = 4 * sa * (sh - 2) + 6 * sa;
    c.edges = sa * (2 * sh - 1);
    c.triangles = 2 * sa * (sh - 1);
    c.uvs = p.createUVs ? (sa + 1) * (sh - 1) + 2 * sa : 0;
    // Every point lies on the sphere, whatever the axis.
    c.bounds = rotatedBox({0.0, 1.0, 0.0}, {glm::dvec3(-r), glm::dvec3(r)});
    return c;
}

std::optional<PrimitiveCounts> polyPlaneCounts(const PolyPlaneParams& p) {
    const uint64_t sw = uint64_t(std::max(1, p.subdivisionsWidth)), sh = uint64_t(std::max(1, p.subdivisionsHeight));
    const double w = p.width, h = p.height;
    if (!sane(w) || !sane(h) || double(sw) * double(sh) > double(kMaxPrimitiveFaces)) return std::nullopt;
    if (!saneCell(w / double(sw), h / double(sh), std::max(w, h))) return std::nullopt;
    PrimitiveCounts c;
    c.points = (sw + 1) * (sh + 1);
    c.faces = sw * sh;
    c.faceVertices = 4 * c.faces;
    c.edges = sw * (sh + 1) + sh * (sw + 1);
    c.triangles = 2 * c.faces;
    c.uvs = p.createUVs ? c.points : 0;
    c.bounds = rotatedBox(p.axis, {{-w / 2, 0.0, -h / 2}, {w / 2, 0.0, -h / 2}, {-w / 2, 0.0, h / 2}, {w / 2, 0.0, h / 2}});
    return c;
}

std::optional<PrimitiveCounts> polyCubeCounts(const PolyCubeParams& p) {
    const uint64_t sw = uint64_t(std::max(1, p.subdivisionsWidth)), sh = uint64_t(std::max(1, p.subdivisionsHeight)),
                   sd = uint64_t(std::max(1, p.subdivisionsDepth));
    const double w = p.width, h = p.height, d = p.depth;
    if (!sane(w) || !sane(h) || !sane(d)) return std::nullopt;
    const double faces = 2.0 * (double(sw) * double(sh) + double(sh) * double(sd) + double(sd) * double(sw));
    if (faces > double(kMaxPrimitiveFaces)) return std::nullopt;
    const double extent = std::max({w, h, d}), cw = w / double(sw), ch = h / double(sh), cd = d / double(sd);
    if (!saneCell(cw, ch, extent) || !saneCell(ch, cd, extent) || !saneCell(cd, cw, extent)) return std::nullopt;
    PrimitiveCounts c;
    c.faces = uint64_t(faces);
    c.points = c.faces + 2;  // a closed quad mesh of genus 0: V − E + F = 2 with E = 2F
    c.faceVertices = 4 * c.faces;
    c.edges = 2 * c.faces;
    c.triangles = 2 * c.faces;
    c.uvs = p.createUVs ? c.faceVertices : 0;  // at most one per face-vertex
    c.bounds = rotatedBox(p.axis, {{-w / 2, -h / 2, -d / 2}, {w / 2, -h / 2, -d / 2}, {-w / 2, h / 2, -d / 2},
                                   {w / 2, h / 2, -d / 2}, {-w / 2, -h / 2, d / 2}, {w / 2, -h / 2, d / 2},
                                   {-w / 2, h / 2, d / 2}, {w / 2, h / 2, d / 2}});
    return c;
}

namespace {

// A flat cap of `sc` rings (0: one n-gon) closing a ring of `sa` points: what it adds.
void addCapCounts(PrimitiveCounts& c, uint64_t sa, uint64_t sc, bool uvs) {
    if (sc == 0) {
        c.faces += 1;
        c.faceVertices += sa;
        c.triangles += sa - 2;
        c.uvs += uvs ? sa : 0;
        return;
    }
    c.points += (sc - 1) * sa + 1;
    c.faces += sc * sa;
    c.faceVertices += 4 * sa * (sc - 1) + 3 * sa;
    c.triangles += 2 * sa * (sc - 1) + sa;
    c.edges += sa * (2 * sc - 1);
    c.uvs += uvs ? sc * sa + 1 : 0;
}

}  // namespace

std::optional<PrimitiveCounts> polyCylinderCounts(const PolyCylinderParams& p) {
    const uint64_t sa = uint64_t(std::max(3, p.subdivisionsAxis)), sh = uint64_t(std::max(1, p.subdivisionsHeight)),
                   sc = uint64_t(std::max(0, p.subdivisionsCaps));
    const double r = p.radius, h = p.height;
    if (!sane(r) || !sane(h) || double(sa) * (double(sh) + 2.0 * double(std::max<uint64_t>(sc, 1))) > double(kMaxPrimitiveFaces))
        return std::nullopt;
    const double extent = std::max(r, h), rings = double(std::max<uint64_t>(sc, 1));
    if (!saneCell(kTwoPi * r / double(sa), h / double(sh), extent) ||
        !saneCell(kTwoPi * r / (double(sa) * rings), r / rings, extent))
        return std::nullopt;
    PrimitiveCounts c;
    c.points = (sh + 1) * sa;
    c.faces = sa * sh;
    c.faceVertices = 4 * sa * sh;
    c.triangles = 2 * sa * sh;
    c.edges = (sh + 1) * sa + sh * sa;
    c.uvs = p.createUVs ? (sh + 1) * (sa + 1) : 0;
    addCapCounts(c, sa, sc, p.createUVs);
    addCapCounts(c, sa, sc, p.createUVs);
    c.bounds = rotatedBox(p.axis, {{-r, -h / 2, -r}, {r, -h / 2, -r}, {-r, h / 2, -r}, {r, h / 2, -r},
                                   {-r, -h / 2, r}, {r, -h / 2, r}, {-r, h / 2, r}, {r, h / 2, r}});
    return c;
}

std::optional<PrimitiveCounts> polyConeCounts(const PolyConeParams& p) {
    const uint64_t sa = uint64_t(std::max(3, p.subdivisionsAxis)), sh = uint64_t(std::max(1, p.subdivisionsHeight)),
                   sc = uint64_t(std::max(0, p.subdivisionsCap));
    const double r = p.radius, h = p.height;
    if (!sane(r) || !sane(h) || double(sa) * (double(sh) + double(std::max<uint64_t>(sc, 1))) > double(kMaxPrimitiveFaces))
        return std::nullopt;
    const double extent = std::max(r, h), rings = double(std::max<uint64_t>(sc, 1));
    // The ring nearest the apex is the thinnest side cell: radius r / sh.
    if (!saneCell(kTwoPi * r / (double(sa) * double(sh)), h / double(sh), extent) ||
        !saneCell(kTwoPi * r / (double(sa) * rings), r / rings, extent))
        return std::nullopt;
    PrimitiveCounts c;
    c.points = sh * sa + 1;
    c.faces = (sh - 1) * sa + sa;
    c.faceVertices = 4 * (sh - 1) * sa + 3 * sa;
    c.triangles = 2 * (sh - 1) * sa + sa;
    c.edges = sh * sa + (sh - 1) * sa + sa;
    c.uvs = p.createUVs ? sh * (sa + 1) + sa : 0;
    addCapCounts(c, sa, sc, p.createUVs);
    c.bounds = rotatedBox(p.axis, {{-r, -h / 2, -r}, {r, -h / 2, -r}, {-r, h / 2, -r}, {r, h / 2, -r},
                                   {-r, -h / 2, r}, {r, -h / 2, r}, {-r, h / 2, r}, {r, h / 2, r}});
    return c;
}

std::optional<PrimitiveCounts> polyTorusCounts(const PolyTorusParams& p) {
    const uint64_t sa = uint64_t(std::max(3, p.subdivisionsAxis)), sh = uint64_t(std::max(3, p.subdivisionsHeight));
    const double r = p.radius, sr = p.sectionRadius;
    if (!sane(r) || !sane(sr) || !std::isfinite(p.twistRadians) || !(sr < r) ||
        double(sa) * double(sh) > double(kMaxPrimitiveFaces))
        return std::nullopt;
    const double outer = r + sr;
    if (!saneCell(kTwoPi * (r - sr) / double(sa), kTwoPi * sr / double(sh), outer)) return std::nullopt;
    PrimitiveCounts c;
    c.points = sa * sh;
    c.faces = sa * sh;
    c.faceVertices = 4 * c.faces;
    c.edges = 2 * c.faces;
    c.triangles = 2 * c.faces;
    c.uvs = p.createUVs ? (sa + 1) * (sh + 1) : 0;
    c.bounds = rotatedBox(p.axis, {{-outer, -sr, -outer}, {outer, -sr, -outer}, {-outer, sr, -outer}, {outer, sr, -outer},
                                   {-outer, -sr, outer}, {outer, -sr, outer}, {-outer, sr, outer}, {outer, sr, outer}});
    return c;
}

}  // namespace pushpin::geom
