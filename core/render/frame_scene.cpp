#include "core/render/frame_scene.h"

#include "core/geom/finite.h"
#include "core/render/camera.h"
#include "core/util/format.h"
#include "cache/error.h"
#include "core/geom/nurbs.h"
#include "core/geom/triangulate.h"
#include "core/scene/components.h"
#include "core/scene/mesh_eval.h"
#include "core/scene/nurbs_eval.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <new>
#include <numbers>
#include <numeric>
#include <optional>
#include <unordered_map>

namespace pushpin::render {

using scene::Graph;
using scene::NodeId;
using scene::kNoNode;

namespace {

// Why a world matrix cannot place anything the renderer can project, or empty when it can: an
// entry that is not finite or beyond kMaxSceneCoordinate (camera.h says why that limit).
std::string matrixProblem(const glm::dmat4& m) {
    if (!geom::isFinite(m)) return "non-finite world matrix";
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (std::abs(m[c][r]) > kMaxSceneCoordinate)
                return "world matrix entry " + util::formatNumber(m[c][r], 6) +
                       " is beyond 1e18 scene units (a translate or scale on the path is too large)";
    return {};
}

// Why world-space bounds are beyond what the renderer can project, or empty when they are not.
std::string boundsProblem(const geom::Bounds3& b) {
    for (int k = 0; k < 3; ++k) {
        for (double v : {b.lo[k], b.hi[k]})
            if (!std::isfinite(v) || std::abs(v) > kMaxSceneCoordinate)
                return "world-space bounds reach " + util::formatNumber(v, 6) + ", beyond 1e18 scene units";
    }
    return {};
}

// Fills geo.neighbors from the vertex each corner sits on (`cornerVertex`, 3 per triangle): two
// triangles whose edges join the same two vertices are neighbours, flagged with kHardEdgeBit when
// `hard(t0, t1, v0, v1)` says so; edges used by one triangle or by more than two get kNoTriangle.
template <class HardFn>
void buildNeighbors(RenderGeometry& geo, const std::vector<uint32_t>& cornerVertex, HardFn&& hard) {
    const size_t triangles = geo.triangleCount();
    geo.neighbors.assign(3 * triangles, kNoTriangle);
    struct EdgeUse {
        uint64_t key;
        uint32_t slot;  // 3·t + k
    };
    std::vector<EdgeUse> uses;
    uses.reserve(3 * triangles);
    for (size_t t = 0; t < triangles; ++t)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t a = cornerVertex[3 * t + k], b = cornerVertex[3 * t + (k + 1) % 3];
            if (a != b) uses.push_back({geom::edgeKey(a, b), uint32_t(3 * t + k)});
        }
    std::sort(uses.begin(), uses.end(),
              [](const EdgeUse& x, const EdgeUse& y) { return x.key != y.key ? x.key < y.key : x.slot < y.slot; });
    for (size_t i = 0; i < uses.size();) {
        size_t j = i + 1;
        while (j < uses.size() && uses[j].key == uses[i].key) ++j;
        if (j - i == 2) {
            const uint32_t s0 = uses[i].slot, s1 = uses[i + 1].slot;
            const uint32_t t0 = s0 / 3, t1 = s1 / 3;
            if (t0 != t1) {
                const bool isHard = hard(t0, t1, uint32_t(uses[i].key >> 32), uint32_t(uses[i].key & 0xffffffffu));
                const uint32_t bit = isHard ? kHardEdgeBit : 0u;
                geo.neighbors[s0] = t1 | bit;
                geo.neighbors[s1] = t0 | bit;
            }
        }
        i = j;
    }
}

void computeBounds(RenderGeometry& geo) {
    geo.bounds = geom::Bounds3();
    for (const glm::vec3& p : geo.positions) geo.bounds.extend(glm::dvec3(p));
}

// triangulateMesh for a mesh that passed validation; `degenerate` marks faces to drop.
RenderGeometry triangulateValidMesh(const geom::Mesh& mesh, const std::vector<uint16_t>& faceMaterial,
                                    bool smoothShading, const std::vector<bool>& degenerate) {
    RenderGeometry geo;
    const size_t faces = mesh.faceCount();
    std::vector<glm::vec3> shading;
    if (smoothShading) shading = mesh.shadingNormals();
    const geom::UvSet* uvSet = nullptr;
    if (mesh.currentUvSet >= 0 && size_t(mesh.currentUvSet) < mesh.uvSets.size() &&
        mesh.uvSets[size_t(mesh.currentUvSet)].faceVertexUvs.size() == mesh.faceVertexCount())
        uvSet = &mesh.uvSets[size_t(mesh.currentUvSet)];

    std::vector<uint32_t> cornerVertex;
    geom::PolygonTriangulator triangulator;
    std::vector<glm::dvec3> points;
    std::vector<uint32_t> loops, local;
    const size_t expected = mesh.faceVertexCount() * 3;  // a fair upper guess of corner count
    geo.positions.reserve(expected);
    geo.normals.reserve(expected);
    cornerVertex.reserve(expected);

    for (size_t f = 0; f < faces; ++f) {
        const uint16_t material = f < faceMaterial.size() ? faceMaterial[f] : uint16_t(0);
        if (material == kNoMaterial || (f < degenerate.size() && degenerate[f])) continue;
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
            geo.positions.push_back(mesh.points[point]);
            glm::vec3 n = faceNormal;
            if (smoothShading) {
                const glm::vec3 s = shading[fv];
                const float length = glm::length(s);
                if (std::isfinite(length) && length > 1e-20f) n = s / length;
            }
            geo.normals.push_back(n);
            if (uvSet) {
                const int32_t id = uvSet->faceVertexUvs[fv];
                geo.uvs.push_back(id >= 0 ? uvSet->uvs[size_t(id)] : glm::vec2(0.0f));
            }
            cornerVertex.push_back(point);
        }
        for (size_t t = 0; t < local.size() / 3; ++t) {
            geo.face.push_back(uint32_t(f));
            geo.material.push_back(material);
        }
    }
    computeBounds(geo);

    std::unordered_map<uint64_t, bool> smoothByEdge;
    smoothByEdge.reserve(mesh.edges.size());
    for (const geom::MeshEdge& e : mesh.edges) smoothByEdge[geom::edgeKey(e.v0, e.v1)] = e.smooth;
    buildNeighbors(geo, cornerVertex, [&](uint32_t t0, uint32_t t1, uint32_t a, uint32_t b) {
        if (geo.face[t0] == geo.face[t1]) return false;  // a diagonal inside one face
        if (geo.material[t0] != geo.material[t1]) return true;
        if (!smoothShading) return true;
        const auto it = smoothByEdge.find(geom::edgeKey(a, b));
        return it != smoothByEdge.end() && !it->second;
    });
    return geo;
}

// Sorted distinct knot values of a direction's domain [lo, hi] (the span boundaries).
std::vector<double> spanBreaks(const std::vector<double>& knots, double lo, double hi) {
    std::vector<double> breaks;
    for (double k : knots)
        if (k >= lo && k <= hi && (breaks.empty() || k > breaks.back())) breaks.push_back(k);
    if (breaks.empty() || breaks.front() > lo) breaks.insert(breaks.begin(), lo);
    if (breaks.back() < hi) breaks.push_back(hi);
    return breaks;
}

// Grid parameters: `divisions` steps in every non-empty span; `span` receives each step's span.
std::vector<double> gridParameters(const std::vector<double>& breaks, int divisions, std::vector<uint32_t>& span) {
    std::vector<double> params;
    span.clear();
    for (size_t s = 0; s + 1 < breaks.size(); ++s) {
        for (int d = 0; d < divisions; ++d) {
            params.push_back(breaks[s] + (breaks[s + 1] - breaks[s]) * double(d) / double(divisions));
            span.push_back(uint32_t(s));
        }
    }
    params.push_back(breaks.back());
    return params;
}

// Uniform per-span grid tessellation of a NURBS surface (reference/algorithms.md §8, primary
// pass): positions and normals evaluated exactly, uvs the normalised parameters, poles given a
// neighbouring normal, every grid edge soft. Returns nullopt with `problem` set when the surface
// evaluates to non-finite values.
std::optional<RenderGeometry> tessellateNurbs(const geom::NurbsSurface& s, int divU, int divV, std::string& problem) {
    std::vector<uint32_t> spanOfU, spanOfV;
    const std::vector<double> breaksU = spanBreaks(s.knotsU(), s.uMin(), s.uMax());
    const std::vector<double> breaksV = spanBreaks(s.knotsV(), s.vMin(), s.vMax());
    const std::vector<double> us = gridParameters(breaksU, divU, spanOfU);
    const std::vector<double> vs = gridParameters(breaksV, divV, spanOfV);
    const size_t nu = us.size(), nv = vs.size();
    const size_t spansV = breaksV.size() - 1;
    if (nu < 2 || nv < 2) {
        problem = "the surface has an empty parameter domain";
        return std::nullopt;
    }
    std::vector<glm::dvec3> pos(nu * nv), nrm(nu * nv);
    geom::Bounds3 box;
    for (size_t i = 0; i < nu; ++i)
        for (size_t j = 0; j < nv; ++j) {
            const glm::dvec3 p = s.point(us[i], vs[j]);
            const glm::dvec3 n = s.normal(us[i], vs[j]);
            if (!geom::isFinite(p) || !geom::isFinite(n)) {
                problem = "the surface evaluates to NaN/Inf";
                return std::nullopt;
            }
            pos[i * nv + j] = p;
            nrm[i * nv + j] = n;
            box.extend(p);
        }
    // Poles: the nearest grid normal that is not zero, searching outwards ring by ring.
    for (size_t i = 0; i < nu; ++i)
        for (size_t j = 0; j < nv; ++j) {
            if (glm::dot(nrm[i * nv + j], nrm[i * nv + j]) > 0.0) continue;
            bool found = false;
            for (size_t r = 1; r < std::max(nu, nv) && !found; ++r)
                for (size_t a = (i >= r ? i - r : 0); a <= std::min(nu - 1, i + r) && !found; ++a)
                    for (size_t b = (j >= r ? j - r : 0); b <= std::min(nv - 1, j + r) && !found; ++b) {
                        const glm::dvec3& q = nrm[a * nv + b];
                        if (glm::dot(q, q) > 0.0) {
                            nrm[i * nv + j] = q;
                            found = true;
                        }
                    }
        }

    // Vertex identities for adjacency: seams of closed directions and collapsed rows (poles)
    // are welded so that the triangles around them are neighbours.
    const double tol = 1e-6 * std::max({box.size().x, box.size().y, box.size().z, 1e-30});
    std::vector<uint32_t> id(nu * nv);
    std::iota(id.begin(), id.end(), 0u);
    auto close = [&](size_t a, size_t b) { return glm::length(pos[a] - pos[b]) <= tol; };
    auto root = [&](uint32_t x) {
        while (id[x] != x) x = id[x];
        return x;
    };
    auto weld = [&](size_t a, size_t b) {
        const uint32_t ra = root(uint32_t(a)), rb = root(uint32_t(b));
        if (ra != rb) id[std::max(ra, rb)] = std::min(ra, rb);
    };
    for (size_t j = 0; j < nv; ++j)
        if (close(j, (nu - 1) * nv + j)) weld(j, (nu - 1) * nv + j);
    for (size_t i = 0; i < nu; ++i)
        if (close(i * nv, i * nv + nv - 1)) weld(i * nv, i * nv + nv - 1);
    for (size_t i = 0; i < nu; ++i) {
        bool collapsed = true;
        for (size_t j = 1; j < nv && collapsed; ++j) collapsed = close(i * nv, i * nv + j);
        if (collapsed)
            for (size_t j = 1; j < nv; ++j) weld(i * nv, i * nv + j);
    }
    for (size_t j = 0; j < nv; ++j) {
        bool collapsed = true;
        for (size_t i = 1; i < nu && collapsed; ++i) collapsed = close(j, i * nv + j);
        if (collapsed)
            for (size_t i = 1; i < nu; ++i) weld(j, i * nv + j);
    }

    RenderGeometry geo;
    std::vector<uint32_t> cornerVertex;
    const double du = s.uMax() - s.uMin(), dv = s.vMax() - s.vMin();
    const double minArea2 = 1e-24 * std::pow(std::max({box.size().x, box.size().y, box.size().z}), 4.0);
    auto corner = [&](size_t i, size_t j) {
        const size_t k = i * nv + j;
        geo.positions.push_back(glm::vec3(pos[k]));
        geo.normals.push_back(glm::vec3(glm::normalize(glm::dot(nrm[k], nrm[k]) > 0.0 ? nrm[k] : glm::dvec3(0, 0, 1))));
        geo.uvs.push_back(glm::vec2(float((us[i] - s.uMin()) / du), float((vs[j] - s.vMin()) / dv)));
        cornerVertex.push_back(root(uint32_t(k)));
    };
    // Quad (i, j)–(i+1, j+1) splits into (a, b, c) and (a, c, d), counter-clockwise in (u, v):
    // their geometric normal is dP/du × dP/dv, the surface normal. Zero-area halves (poles) go.
    for (size_t i = 0; i + 1 < nu; ++i)
        for (size_t j = 0; j + 1 < nv; ++j) {
            const size_t quad[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
            const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
            for (const auto& t : tris) {
                const glm::dvec3& p0 = pos[quad[t[0]][0] * nv + quad[t[0]][1]];
                const glm::dvec3& p1 = pos[quad[t[1]][0] * nv + quad[t[1]][1]];
                const glm::dvec3& p2 = pos[quad[t[2]][0] * nv + quad[t[2]][1]];
                const glm::dvec3 c = glm::cross(p1 - p0, p2 - p0);
                if (!(glm::dot(c, c) > minArea2)) continue;
                for (int k = 0; k < 3; ++k) corner(quad[t[k]][0], quad[t[k]][1]);
                geo.face.push_back(spanOfU[i] * uint32_t(spansV) + spanOfV[j]);
                geo.material.push_back(0);
            }
        }
    computeBounds(geo);
    buildNeighbors(geo, cornerVertex, [](uint32_t, uint32_t, uint32_t, uint32_t) { return false; });
    return geo;
}

// Per-span divisions for one direction: ceil(number · factor), at least 1 (reference/algorithms.md
// §8: numberU/V isoparms per span, u/vDivisionsFactor). Capped so a wild value cannot exhaust memory.
int spanDivisions(scene::Evaluator& ev, NodeId shape, const char* numberAttr, const char* factorAttr,
                  const std::string& label, std::vector<std::string>& notes) {
    constexpr int kMaxDivisions = 256;
    double number = ev.getDouble(shape, numberAttr, 3.0);
    double factor = ev.getDouble(shape, factorAttr, 1.5);
    if (!std::isfinite(number) || !std::isfinite(factor)) {
        notes.push_back(label + ": non-finite " + numberAttr + " or " + factorAttr + " replaced by the defaults");
        number = 3.0;
        factor = 1.5;
    }
    const double divisions = std::ceil(number * factor - 1e-9);
    if (divisions > kMaxDivisions) {
        notes.push_back(label + ": " + numberAttr + " × " + factorAttr + " capped at " + std::to_string(kMaxDivisions) +
                        " divisions per span");
        return kMaxDivisions;
    }
    return std::max(1, int(divisions));
}

// One shading-group membership of a shape instance.
struct Membership {
    const scene::ShadingGroupInfo* group = nullptr;
    const scene::SetMember* member = nullptr;
};

// Every shading-group membership by member shape, in the order of the sets in the scene.
std::unordered_map<NodeId, std::vector<Membership>> membershipsByShape(const scene::RenderSetup& setup) {
    std::unordered_map<NodeId, std::vector<Membership>> out;
    for (const scene::ShadingGroupInfo& sg : setup.shadingGroups) {
        if (!sg.inRenderPartition) continue;  // outside the render partition nothing renders
        for (const scene::SetMember& m : sg.members) out[m.shape].push_back({&sg, &m});
    }
    return out;
}

// The groupId node wired to shape.instObjGroups[instance].objectGroups[group].objectGroupId.
NodeId objectGroupIdNode(const Graph& g, NodeId shape, int instance, int group) {
    for (const scene::Connection* c : g.inputs(shape)) {
        auto segs = scene::parsePlugPath(c->dst.path);
        if (!segs || segs->size() != 3) continue;
        const auto& s = *segs;
        if (s[0].name != "instObjGroups" || s[1].name != "objectGroups" || s[2].name != "objectGroupId") continue;
        if ((s[0].indexed() ? s[0].first : 0) != instance || (s[1].indexed() ? s[1].first : 0) != group) continue;
        return c->src.node;
    }
    return kNoNode;
}

// Face components of a per-face membership: the member's own objectGrpCompList, or, when that is
// empty, the groupParts component list of the mesh history tied to the same groupId node.
scene::ComponentList memberComponents(scene::Evaluator& ev, const scene::SetMember& m,
                                      const scene::MeshEvaluation& evaluation) {
    if (!m.components.empty()) return scene::ComponentList{m.components};
    const Graph& g = ev.graph();
    const NodeId groupId = objectGroupIdNode(g, m.shape, m.instance, m.objectGroup);
    if (groupId == kNoNode) return {};
    for (const scene::MeshComponentGroup& group : evaluation.groups) {
        const NodeId parts = g.find(group.groupParts);
        if (parts == kNoNode) continue;
        if (auto src = g.source(parts, "groupId"); src && src->node == groupId) return group.components;
    }
    // Both sides may store the numeric id instead of a connection.
    const int id = ev.getInt(groupId, "groupId", -1);
    if (id >= 0)
        for (const scene::MeshComponentGroup& group : evaluation.groups)
            if (group.groupId == id) return group.components;
    return {};
}

// Light linking (reference/nodes.md §5): a link side names a light or object directly, a DAG
// ancestor of it, a set containing it (sets nest), or, on the object side, its shading group.
class LinkResolver {
public:
    explicit LinkResolver(const Graph& g) : m_graph(g) {}

    bool contains(NodeId side, const std::vector<NodeId>& path, NodeId shadingGroup, int depth = 0) {
        if (side == kNoNode) return false;
        if (side == shadingGroup) return true;
        if (std::find(path.begin(), path.end(), side) != path.end()) return true;
        if (depth > 16) return false;  // sets nested deeper than this are a cycle
        for (NodeId m : members(side))
            if (contains(m, path, shadingGroup, depth + 1)) return true;
        return false;
    }

private:
    const std::vector<NodeId>& members(NodeId set) {
        auto it = m_members.find(set);
        if (it != m_members.end()) return it->second;
        std::vector<NodeId> out;
        for (const scene::Connection* c : m_graph.inputs(set))
            if (c->dst.path.rfind("dagSetMembers", 0) == 0 || c->dst.path.rfind("dnSetMembers", 0) == 0)
                out.push_back(c->src.node);
        return m_members.emplace(set, std::move(out)).first->second;
    }

    const Graph& m_graph;
    std::unordered_map<NodeId, std::vector<NodeId>> m_members;
};

// The largest light value (intensity, angles, dropoff, colour × intensity) kept: shading holds
// them in float, and sums and products of a few such values must stay within float's 3.4e38.
constexpr double kMaxLightValue = 1e30;

// A number read through the evaluator, `fallback` (with a note) when it is not finite or its
// magnitude exceeds kMaxLightValue.
double finiteValue(scene::Evaluator& ev, NodeId node, const char* attr, double fallback, const std::string& label,
                   std::vector<std::string>& notes) {
    const double v = ev.getDouble(node, attr, fallback);
    if (std::isfinite(v) && std::abs(v) <= kMaxLightValue) return v;
    notes.push_back(label + ": " + (std::isfinite(v) ? attr + std::string(" ") + util::formatNumber(v, 10) + " is beyond 1e30"
                                                     : "non-finite " + std::string(attr)) +
                    "; replaced by " + util::formatNumber(fallback, 6));
    return fallback;
}

struct LightRecord {
    std::vector<NodeId> path;
};

void readLights(scene::Evaluator& ev, const scene::RenderSetup& setup, FrameScene& out,
                std::vector<LightRecord>& records) {
    const Graph& g = ev.graph();
    for (const scene::LightInfo& info : setup.lights) {
        const std::string label = g.dagPathName(info.path);
        shade::Light light;
        if (info.type == "ambientLight") light.type = shade::LightType::Ambient;
        else if (info.type == "directionalLight") light.type = shade::LightType::Directional;
        else if (info.type == "pointLight") light.type = shade::LightType::Point;
        else if (info.type == "spotLight") light.type = shade::LightType::Spot;
        else {
            out.notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (!info.supported) {
            out.notes.push_back(label + ": light type " + info.type + " is not supported; not rendered");
            continue;
        }
        if (std::string why = ev.hiddenReason(info.path); !why.empty()) {
            out.notes.push_back(label + ": light " + why + "; not rendered");
            continue;
        }
        const glm::dmat4 world = ev.worldMatrix(info.path);
        if (std::string why = matrixProblem(world); !why.empty()) {
            out.notes.push_back(label + ": " + why + "; light not rendered");
            continue;
        }
        const glm::dvec3 position(world * glm::dvec4(0, 0, 0, 1));
        const glm::dvec3 axis(world * glm::dvec4(0, 0, -1, 0));
        const double axisLength = glm::length(axis);
        if (!(axisLength > 0.0) || !std::isfinite(axisLength)) {
            out.notes.push_back(label + ": degenerate world matrix (scale 0 on the path); light not rendered");
            continue;
        }
        const NodeId n = info.shape;
        light.name = label;
        light.shape = n;
        light.position = position;
        light.direction = axis / axisLength;
        glm::dvec3 color = ev.getDouble3(n, "color", glm::dvec3(1.0));
        if (!geom::isFinite(color)) {
            out.notes.push_back(label + ": non-finite color replaced by 1 1 1");
            color = glm::dvec3(1.0);
        }
        const double intensity = finiteValue(ev, n, "intensity", 1.0, label, out.notes);
        const glm::dvec3 emitted = color * intensity;
        if (!(std::max({std::abs(emitted.x), std::abs(emitted.y), std::abs(emitted.z)}) <= kMaxLightValue)) {
            out.notes.push_back(label + ": color × intensity is beyond 1e30; light not rendered");
            continue;
        }
        light.color = glm::vec3(emitted);
        light.decayRate = ev.getInt(n, "decayRate", 0);
        if (light.decayRate < 0 || light.decayRate > 3) {
            out.notes.push_back(label + ": decayRate " + std::to_string(light.decayRate) + " out of range, 0 (none) used");
            light.decayRate = 0;
        }
        light.coneAngle = float(finiteValue(ev, n, "coneAngle", 40.0 * std::numbers::pi / 180.0, label, out.notes));
        light.penumbraAngle = float(finiteValue(ev, n, "penumbraAngle", 0.0, label, out.notes));
        light.dropoff = float(finiteValue(ev, n, "dropoff", 0.0, label, out.notes));
        light.ambientShade = float(finiteValue(ev, n, "ambientShade", 0.45, label, out.notes));
        light.emitDiffuse = ev.getBool(n, "emitDiffuse", true);
        light.emitSpecular = ev.getBool(n, "emitSpecular", true);
        out.lights.push_back(std::move(light));
        records.push_back({info.path});
    }
}

// Geometry of one shape, evaluated once whatever its number of instances.
struct ShapeGeometry {
    bool failed = false;
    std::string skipReason;
    scene::MeshEvaluation mesh;         // meshes
    std::vector<bool> degenerate;       // meshes: faces to drop
    std::optional<RenderGeometry> nurbs;  // NURBS surfaces (one material)
    // The last triangulation (held by FrameScene::objects[lastObject]), reused by the next
    // instance with the same face materials and smoothShading.
    std::vector<uint16_t> lastMaterials;
    bool lastSmooth = true;
    size_t lastObject = ~size_t(0);
};

void evaluateShape(scene::Evaluator& ev, NodeId shape, const std::string& label, ShapeGeometry& out,
                   std::vector<std::string>& notes) {
    const Graph& g = ev.graph();
    try {
        if (g.node(shape).type == "mesh") {
            out.mesh = scene::evaluateMeshShape(ev, shape);
            for (const std::string& note : out.mesh.notes) notes.push_back(label + ": " + note);
            if (!out.mesh.mesh) {
                out.failed = true;
                out.skipReason = out.mesh.skipReason.empty() ? "the mesh could not be evaluated" : out.mesh.skipReason;
                return;
            }
            const geom::MeshValidation validation = out.mesh.mesh->validate();
            if (!validation.ok()) {
                out.failed = true;
                out.skipReason = "invalid mesh: " + validation.errors.front();
                out.mesh.mesh.reset();
                return;
            }
            if (out.mesh.mesh->empty()) {
                out.failed = true;
                out.skipReason = "mesh has no faces";
                return;
            }
            out.degenerate.assign(out.mesh.mesh->faceCount(), false);
            for (uint32_t f : validation.degenerateFaces) out.degenerate[f] = true;
            if (!validation.degenerateFaces.empty())
                notes.push_back(label + ": " + std::to_string(validation.degenerateFaces.size()) +
                                " degenerate face(s) not rendered");
            return;
        }
        std::string reason, note;
        auto surface = scene::evaluateNurbsSurface(ev, shape, &reason, &note);
        if (!note.empty()) notes.push_back(label + ": " + note);
        if (!surface) {
            out.failed = true;
            out.skipReason = reason.empty() ? "the surface could not be evaluated" : reason;
            return;
        }
        const int divU = spanDivisions(ev, shape, "numberU", "uDivisionsFactor", label, notes);
        const int divV = spanDivisions(ev, shape, "numberV", "vDivisionsFactor", label, notes);
        std::string problem;
        out.nurbs = tessellateNurbs(*surface, divU, divV, problem);
        if (!out.nurbs) {
            out.failed = true;
            out.skipReason = problem;
        }
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        out.failed = true;
        out.skipReason = e.what();
    }
}

// Numbers at the door for objects: a world matrix with an entry beyond kMaxSceneCoordinate, or
// world bounds that reach past it (finite entries can still carry float geometry out of range),
// cannot be projected without overflow, so the object is skipped with a note instead of being
// culled without a word later. `paths` runs parallel to scene.objects and is compacted with it.
void dropUnplaceableObjects(FrameScene& scene, std::vector<std::vector<NodeId>>& paths) {
    size_t kept = 0;
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        RenderObject& o = scene.objects[i];
        std::string why = matrixProblem(o.worldFromObject);
        if (why.empty()) why = boundsProblem(o.worldBounds);
        if (!why.empty()) {
            scene.notes.push_back(o.name + ": " + why + "; not rendered");
            ++scene.skippedShapes;
            continue;
        }
        if (kept != i) {
            scene.objects[kept] = std::move(o);
            paths[kept] = std::move(paths[i]);
        }
        ++kept;
    }
    scene.objects.resize(kept);
    paths.resize(kept);
}

}  // namespace

std::vector<ObjectTopology> FrameScene::topology() const {
    std::vector<ObjectTopology> out;
    out.reserve(objects.size());
    for (const RenderObject& o : objects)
        out.push_back({o.geometry.neighbors.data(), uint32_t(o.geometry.triangleCount())});
    return out;
}

RenderGeometry triangulateMesh(const geom::Mesh& mesh, const std::vector<uint16_t>& faceMaterial, bool smoothShading) {
    const geom::MeshValidation validation = mesh.validate();
    if (!validation.ok()) return {};
    std::vector<bool> degenerate(mesh.faceCount(), false);
    for (uint32_t f : validation.degenerateFaces) degenerate[f] = true;
    return triangulateValidMesh(mesh, faceMaterial, smoothShading, degenerate);
}

FrameScene buildFrameScene(scene::Evaluator& ev, const scene::RenderSetup& setup, const RenderSettings& settings) {
    const Graph& g = ev.graph();
    FrameScene scene;
    scene.frame = ev.frame();

    // Shading groups: compiled once each, the first time an object uses one.
    std::unordered_map<NodeId, uint32_t> groupIndex;
    auto useGroup = [&](const scene::ShadingGroupInfo& sg) {
        auto it = groupIndex.find(sg.node);
        if (it != groupIndex.end()) return it->second;
        RenderShadingGroup group;
        group.name = sg.name;
        group.node = sg.node;
        try {
            group.network = shade::ShadingNetwork::compile(ev, sg.surfaceShader, scene.notes);
        } catch (const std::bad_alloc&) {
            throw;
        } catch (const std::exception& e) {
            scene.notes.push_back(sg.name + ": shading network not compiled (" + e.what() + "); rendered black");
        }
        if (!group.network) group.network = shade::ShadingNetwork::compile(ev, kNoNode, scene.notes);
        const uint32_t index = uint32_t(scene.shadingGroups.size());
        scene.shadingGroups.push_back(std::move(group));
        groupIndex.emplace(sg.node, index);
        return index;
    };

    const auto memberships = membershipsByShape(setup);
    std::vector<std::vector<NodeId>> objectPaths;
    scene::DagPathBudget pathBudget;  // one bound for every shape's instance paths together
    for (const scene::Node& node : g.nodes()) {
        if (node.type != "mesh" && node.type != "nurbsSurface") continue;
        const bool pathsCutBefore = pathBudget.exhausted;
        const auto paths = g.dagPaths(node.id, &pathBudget);
        if (pathBudget.exhausted && !pathsCutBefore) scene.notes.push_back(dagPathBudgetMessage(g, node.id, pathBudget));
        // Geometry is evaluated once per shape, on its first renderable instance.
        ShapeGeometry shape;
        bool evaluated = false;
        for (size_t instance = 0; instance < paths.size(); ++instance) {
            const std::vector<NodeId>& path = paths[instance];
            const std::string label = g.dagPathName(path);
            auto skip = [&](const std::string& why) {
                scene.notes.push_back(label + ": " + why);
                ++scene.skippedShapes;
            };
            if (ev.getBool(node.id, "intermediateObject", false)) {
                skip("intermediate object");
                continue;
            }
            if (std::string why = ev.hiddenReason(path); !why.empty()) {
                skip(why);
                continue;
            }
            if (!ev.getBool(node.id, "primaryVisibility", true)) {
                skip("primaryVisibility is off");
                continue;
            }
            std::vector<Membership> groups;
            if (auto it = memberships.find(node.id); it != memberships.end())
                for (const Membership& m : it->second)
                    if (m.member->instance == int(instance)) groups.push_back(m);
            if (groups.empty()) {
                skip(scene::shadingGroupsOf(setup, node.id, int(instance)).empty()
                         ? "belongs to no shading group"
                         : "its shading groups are not in the renderPartition");
                continue;
            }

            if (!evaluated) {
                evaluateShape(ev, node.id, label, shape, scene.notes);
                evaluated = true;
            }
            if (shape.failed) {
                skip(shape.skipReason);
                continue;
            }

            RenderObject object;
            std::vector<const scene::ShadingGroupInfo*> slotGroups;  // per material slot
            bool triangulated = false;
            object.name = label;
            object.shape = node.id;
            object.instance = int(instance);
            object.worldFromObject = ev.worldMatrix(path);
            if (!geom::isFinite(object.worldFromObject)) {
                skip("non-finite world matrix");
                continue;
            }
            object.primaryVisibility = true;
            object.doubleSided = ev.getBool(node.id, "doubleSided", true);
            object.opposite = ev.getBool(node.id, "opposite", false);
            object.castsShadows = ev.getBool(node.id, "castsShadows", true);
            object.receiveShadows = ev.getBool(node.id, "receiveShadows", true);
            object.smoothShading = ev.getBool(node.id, "smoothShading", true);
            object.shadingSamplesOverride = ev.getBool(node.id, "shadingSamplesOverride", false);
            object.shadingSamples = std::max(1, ev.getInt(node.id, "shadingSamples", 1));
            object.maxShadingSamples = std::max(object.shadingSamples, ev.getInt(node.id, "maxShadingSamples", 1));

            // Shading groups per face: the whole-object group, overridden by per-face groups.
            std::vector<const scene::ShadingGroupInfo*> candidates;  // index = provisional material
            const scene::ShadingGroupInfo* whole = nullptr;
            for (const Membership& m : groups)
                if (m.member->objectGroup < 0 && !whole) whole = m.group;

            if (shape.nurbs) {
                const scene::ShadingGroupInfo* sg = whole ? whole : groups.front().group;
                if (!whole)
                    scene.notes.push_back(label + ": component shading assignment on a NURBS surface; " + sg->name +
                                          " used for the whole surface");
                object.geometry = *shape.nurbs;
                slotGroups.push_back(sg);
            } else {
                const geom::Mesh& mesh = *shape.mesh.mesh;
                const size_t faces = mesh.faceCount();
                // Shading assignments name the faces of the unsmoothed mesh when the shape renders
                // its smooth preview; each smoothed face takes the group of the face it comes from.
                const std::vector<uint32_t>& origin = shape.mesh.faceOrigin;
                const size_t sourceFaces = origin.size() == faces ? shape.mesh.sourceFaceCount : faces;
                std::vector<int32_t> sourceGroup(sourceFaces, -1);
                if (whole) {
                    candidates.push_back(whole);
                    std::fill(sourceGroup.begin(), sourceGroup.end(), 0);
                }
                for (const Membership& m : groups) {
                    if (m.member->objectGroup < 0) continue;
                    const scene::ComponentList list = memberComponents(ev, *m.member, shape.mesh);
                    if (list.items.empty()) {
                        scene.notes.push_back(label + ": objectGroups[" + std::to_string(m.member->objectGroup) +
                                              "] in " + m.group->name + " lists no components");
                        continue;
                    }
                    std::string error;
                    const std::vector<bool> mask = scene::faceMask(list, sourceFaces, &error);
                    if (!error.empty()) scene.notes.push_back(label + ": " + m.group->name + ": " + error);
                    const int32_t index = int32_t(candidates.size());
                    candidates.push_back(m.group);
                    for (size_t f = 0; f < sourceFaces; ++f)
                        if (mask[f]) sourceGroup[f] = index;
                }
                std::vector<int32_t> faceGroup(faces, -1);
                for (size_t f = 0; f < faces; ++f) {
                    const size_t from = origin.size() == faces ? origin[f] : f;
                    faceGroup[f] = from < sourceFaces ? sourceGroup[from] : -1;
                }
                // Slots for the groups that kept at least one face, in first-use order.
                std::vector<int32_t> slotOf(candidates.size(), -1);
                std::vector<uint16_t> faceMaterial(faces, kNoMaterial);
                size_t dropped = 0;
                for (size_t f = 0; f < faces; ++f) {
                    const int32_t c = faceGroup[f];
                    if (c < 0) {
                        ++dropped;
                        continue;
                    }
                    if (slotOf[size_t(c)] < 0) {
                        if (slotGroups.size() >= kNoMaterial) {
                            ++dropped;
                            continue;
                        }
                        slotOf[size_t(c)] = int32_t(slotGroups.size());
                        slotGroups.push_back(candidates[size_t(c)]);
                    }
                    faceMaterial[f] = uint16_t(slotOf[size_t(c)]);
                }
                if (dropped == faces) {
                    skip("no face belongs to a shading group");
                    continue;
                }
                if (dropped > 0)
                    scene.notes.push_back(label + ": " + std::to_string(dropped) +
                                          " face(s) in no shading group not rendered");
                if (shape.lastObject < scene.objects.size() && shape.lastMaterials == faceMaterial &&
                    shape.lastSmooth == object.smoothShading) {
                    object.geometry = scene.objects[shape.lastObject].geometry;
                } else {
                    object.geometry = triangulateValidMesh(mesh, faceMaterial, object.smoothShading, shape.degenerate);
                    shape.lastObject = ~size_t(0);
                    shape.lastMaterials = std::move(faceMaterial);
                    shape.lastSmooth = object.smoothShading;
                    triangulated = true;
                }
            }
            if (object.geometry.triangleCount() == 0) {
                skip("no renderable triangles (every face degenerate or unassigned)");
                continue;
            }
            object.worldBounds = object.geometry.bounds.transformed(object.worldFromObject);
            for (const scene::ShadingGroupInfo* sg : slotGroups) object.materials.push_back({useGroup(*sg), {}});
            if (triangulated) shape.lastObject = scene.objects.size();
            scene.objects.push_back(std::move(object));
            objectPaths.push_back(path);
        }
    }

    dropUnplaceableObjects(scene, objectPaths);

    std::vector<LightRecord> lightRecords;
    readLights(ev, setup, scene, lightRecords);
    scene.usesDefaultLight = scene.lights.empty() && settings.enableDefaultLight;

    // Light linking: light L lights (object O, shading group S) when a "link" pairs a light side
    // containing L with an object side containing O or S, and no "ignore" does. Without any
    // "link" in the scene every light lights everything that is not explicitly ignored.
    LinkResolver resolver(g);
    std::vector<const scene::LightLink*> links, ignores;
    for (const scene::LightLink& l : setup.lightLinks) {
        if (l.kind == "link") links.push_back(&l);
        else if (l.kind == "ignore") ignores.push_back(&l);
    }
    const bool linkedScene = !links.empty();
    auto lightSides = [&](const std::vector<const scene::LightLink*>& list) {
        std::vector<std::vector<char>> out(list.size(), std::vector<char>(scene.lights.size(), 0));
        for (size_t k = 0; k < list.size(); ++k)
            for (size_t l = 0; l < scene.lights.size(); ++l)
                out[k][l] = resolver.contains(list[k]->light, lightRecords[l].path, kNoNode) ? 1 : 0;
        return out;
    };
    const auto linkLights = lightSides(links), ignoreLights = lightSides(ignores);
    for (size_t o = 0; o < scene.objects.size(); ++o) {
        for (MaterialSlot& slot : scene.objects[o].materials) {
            const NodeId sgNode = scene.shadingGroups[slot.shadingGroup].node;
            std::vector<char> lit(scene.lights.size(), linkedScene ? 0 : 1);
            for (size_t k = 0; k < links.size(); ++k) {
                if (std::find(linkLights[k].begin(), linkLights[k].end(), 1) == linkLights[k].end()) continue;
                if (!resolver.contains(links[k]->object, objectPaths[o], sgNode)) continue;
                for (size_t l = 0; l < lit.size(); ++l) lit[l] |= linkLights[k][l];
            }
            for (size_t k = 0; k < ignores.size(); ++k) {
                if (std::find(ignoreLights[k].begin(), ignoreLights[k].end(), 1) == ignoreLights[k].end()) continue;
                if (!resolver.contains(ignores[k]->object, objectPaths[o], sgNode)) continue;
                for (size_t l = 0; l < lit.size(); ++l)
                    if (ignoreLights[k][l]) lit[l] = 0;
            }
            for (size_t l = 0; l < lit.size(); ++l)
                if (lit[l]) slot.lights.push_back(uint32_t(l));
        }
    }
    return scene;
}

}  // namespace pushpin::render
