// core/geom/subdivide.cpp: Catmull-Clark subdivision through OpenSubdiv.
#include "core/geom/subdivide.h"

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <glm/common.hpp>

#include <algorithm>
#include <memory>

namespace pushpin::geom {

namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using Descriptor = Far::TopologyDescriptor;

// A primvar OpenSubdiv can interpolate: N floats.
template <int N>
struct Values {
    float v[N];
    void Clear(void* = nullptr) { std::fill(std::begin(v), std::end(v), 0.0f); }
    void AddWithWeight(const Values& src, float weight) {
        for (int i = 0; i < N; ++i) v[i] += src.v[i] * weight;
    }
};

}  // namespace

double subdividedFaceCount(const Mesh& mesh, int levels) {
    if (levels <= 0) return double(mesh.faceCount());
    double faces = 0.0;
    for (size_t f = 0; f < mesh.faceCount(); ++f) faces += double(mesh.faceOuterLoop(f).size());
    for (int l = 1; l < levels; ++l) faces *= 4.0;
    return faces;
}

bool subdivideMesh(Mesh& mesh, const SubdivideParams& params, std::vector<uint32_t>* faceOrigin, std::string* error) {
    auto fail = [&](std::string message) {
        if (error) *error = std::move(message);
        return false;
    };
    const int levels = std::max(0, params.levels);
    if (faceOrigin) {
        faceOrigin->resize(mesh.faceCount());
        for (size_t f = 0; f < mesh.faceCount(); ++f) (*faceOrigin)[f] = uint32_t(f);
    }
    if (levels == 0 || mesh.faceCount() == 0) return true;
    for (size_t f = 0; f < mesh.faceCount(); ++f)
        if (mesh.holeCount(f) != 0) return fail("a face with holes cannot be subdivided");
    if (subdividedFaceCount(mesh, levels) > double(kMaxSubdividedFaces))
        return fail("subdividing " + std::to_string(levels) + " levels would make more than " +
                    std::to_string(kMaxSubdividedFaces) + " faces");

    // Topology, creases from hard edges, and one face-varying channel per UV and colour set.
    std::vector<int> vertsPerFace(mesh.faceCount());
    for (size_t f = 0; f < mesh.faceCount(); ++f) vertsPerFace[f] = int(mesh.faceOuterLoop(f).size());
    std::vector<Far::Index> faceVerts(mesh.faceVertices.begin(), mesh.faceVertices.end());
    std::vector<Far::Index> creasePairs;
    std::vector<float> creaseWeights;
    if (params.keepHardEdges)
        for (const MeshEdge& e : mesh.edges)
            if (!e.smooth) {
                creasePairs.push_back(Far::Index(e.v0));
                creasePairs.push_back(Far::Index(e.v1));
                creaseWeights.push_back(Sdc::Crease::SHARPNESS_INFINITE);
            }
    struct Channel {
        bool uv;
        size_t set;
        std::vector<Far::Index> indices;
        size_t valueCount;
    };
    std::vector<Channel> channels;
    for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
        const UvSet& set = mesh.uvSets[s];
        if (set.faceVertexUvs.size() != mesh.faceVertices.size() || set.uvs.empty()) continue;
        Channel c{true, s, {}, set.uvs.size() + 1};  // the extra value stands for "no UV"
        c.indices.reserve(set.faceVertexUvs.size());
        for (int32_t id : set.faceVertexUvs)
            c.indices.push_back(id >= 0 && size_t(id) < set.uvs.size() ? Far::Index(id) : Far::Index(set.uvs.size()));
        channels.push_back(std::move(c));
    }
    for (size_t s = 0; s < mesh.colorSets.size(); ++s) {
        const ColorSet& set = mesh.colorSets[s];
        if (set.faceVertexColors.size() != mesh.faceVertices.size() || set.colors.empty()) continue;
        Channel c{false, s, {}, set.colors.size() + 1};
        for (int32_t id : set.faceVertexColors)
            c.indices.push_back(id >= 0 && size_t(id) < set.colors.size() ? Far::Index(id) : Far::Index(set.colors.size()));
        channels.push_back(std::move(c));
    }
    std::vector<Descriptor::FVarChannel> fvar(channels.size());
    for (size_t i = 0; i < channels.size(); ++i) {
        fvar[i].numValues = int(channels[i].valueCount);
        fvar[i].valueIndices = channels[i].indices.data();
    }
    Descriptor desc;
    desc.numVertices = int(mesh.points.size());
    desc.numFaces = int(mesh.faceCount());
    desc.numVertsPerFace = vertsPerFace.data();
    desc.vertIndicesPerFace = faceVerts.data();
    desc.numCreases = int(creaseWeights.size());
    desc.creaseVertexIndexPairs = creasePairs.empty() ? nullptr : creasePairs.data();
    desc.creaseWeights = creaseWeights.empty() ? nullptr : creaseWeights.data();
    desc.numFVarChannels = int(fvar.size());
    desc.fvarChannels = fvar.empty() ? nullptr : fvar.data();

    auto makeRefiner = [&](Sdc::SchemeType scheme) -> std::unique_ptr<Far::TopologyRefiner> {
        Sdc::Options options;
        options.SetVtxBoundaryInterpolation(params.keepBorder ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                                              : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
        options.SetFVarLinearInterpolation(params.smoothUvs ? Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1
                                                            : Sdc::Options::FVAR_LINEAR_ALL);
        std::unique_ptr<Far::TopologyRefiner> refiner(Far::TopologyRefinerFactory<Descriptor>::Create(
            desc, Far::TopologyRefinerFactory<Descriptor>::Options(scheme, options)));
        if (!refiner) return nullptr;
        Far::TopologyRefiner::UniformOptions uniform(levels);
        uniform.fullTopologyInLastLevel = true;
        refiner->RefineUniform(uniform);
        return refiner;
    };
    std::unique_ptr<Far::TopologyRefiner> refiner = makeRefiner(Sdc::SCHEME_CATMARK);
    if (!refiner) return fail("OpenSubdiv refused the mesh's topology");

    // Positions at every level, back to back.
    std::vector<size_t> start(size_t(levels) + 1, 0);
    for (int l = 1; l <= levels; ++l) start[size_t(l)] = start[size_t(l - 1)] + size_t(refiner->GetLevel(l - 1).GetNumVertices());
    auto refinePoints = [&](const Far::TopologyRefiner& r) {
        std::vector<Values<3>> buffer(start[size_t(levels)] + size_t(r.GetLevel(levels).GetNumVertices()));
        for (size_t p = 0; p < mesh.points.size(); ++p) buffer[p] = {{mesh.points[p].x, mesh.points[p].y, mesh.points[p].z}};
        Far::PrimvarRefiner primvar(r);
        for (int l = 1; l <= levels; ++l) {
            const Values<3>* src = &buffer[start[size_t(l - 1)]];
            Values<3>* dst = &buffer[start[size_t(l)]];
            primvar.Interpolate(l, src, dst);
        }
        return buffer;
    };
    std::vector<Values<3>> points = refinePoints(*refiner);
    if (params.continuity < 1.0) {
        // A blend towards the linear subdivision of the same topology (same numbering).
        std::unique_ptr<Far::TopologyRefiner> linear = makeRefiner(Sdc::SCHEME_BILINEAR);
        if (!linear) return fail("OpenSubdiv refused the mesh's topology");
        const std::vector<Values<3>> flat = refinePoints(*linear);
        const float c = float(std::clamp(params.continuity, 0.0, 1.0));
        for (size_t i = start[size_t(levels)]; i < points.size(); ++i)
            for (int k = 0; k < 3; ++k) points[i].v[k] = flat[i].v[k] + c * (points[i].v[k] - flat[i].v[k]);
    }

    const Far::TopologyLevel& last = refiner->GetLevel(levels);
    Mesh out;
    out.points.reserve(size_t(last.GetNumVertices()));
    for (int v = 0; v < last.GetNumVertices(); ++v) {
        const Values<3>& p = points[start[size_t(levels)] + size_t(v)];
        out.points.emplace_back(p.v[0], p.v[1], p.v[2]);
    }
    out.currentUvSet = mesh.currentUvSet;
    for (const UvSet& set : mesh.uvSets) out.uvSets.push_back({set.name, {}, {}});
    for (const ColorSet& set : mesh.colorSets) out.colorSets.push_back({set.name, {}, {}});
    out.faceVertices.reserve(size_t(last.GetNumFaces()) * 4);
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int k = 0; k < fv.size(); ++k) out.faceVertices.push_back(uint32_t(fv[k]));
        out.loopStarts.push_back(uint32_t(out.faceVertices.size()));
        out.faceLoopStarts.push_back(uint32_t(out.loopCount()));
    }
    // Face-varying channels.
    Far::PrimvarRefiner primvar(*refiner);
    for (size_t ch = 0; ch < channels.size(); ++ch) {
        const Channel& c = channels[ch];
        std::vector<size_t> fstart(size_t(levels) + 1, 0);
        for (int l = 1; l <= levels; ++l)
            fstart[size_t(l)] = fstart[size_t(l - 1)] + size_t(refiner->GetLevel(l - 1).GetNumFVarValues(int(ch)));
        std::vector<Values<4>> buffer(fstart[size_t(levels)] + size_t(last.GetNumFVarValues(int(ch))));
        for (size_t i = 0; i + 1 < c.valueCount; ++i) {
            if (c.uv) {
                const glm::vec2 uv = mesh.uvSets[c.set].uvs[i];
                buffer[i] = {{uv.x, uv.y, 0.0f, 0.0f}};
            } else {
                const glm::vec4 col = mesh.colorSets[c.set].colors[i];
                buffer[i] = {{col.r, col.g, col.b, col.a}};
            }
        }
        buffer[c.valueCount - 1].Clear();
        for (int l = 1; l <= levels; ++l)
        {
            const Values<4>* src = &buffer[fstart[size_t(l - 1)]];
            Values<4>* dst = &buffer[fstart[size_t(l)]];
            primvar.InterpolateFaceVarying(l, src, dst, int(ch));
        }
        const size_t base = fstart[size_t(levels)];
        std::vector<int32_t> ids;
        ids.reserve(out.faceVertices.size());
        for (int f = 0; f < last.GetNumFaces(); ++f) {
            const Far::ConstIndexArray values = last.GetFaceFVarValues(f, int(ch));
            for (int k = 0; k < values.size(); ++k) ids.push_back(int32_t(values[k]));
        }
        const size_t count = size_t(last.GetNumFVarValues(int(ch)));
        if (c.uv) {
            UvSet& set = out.uvSets[c.set];
            set.uvs.resize(count);
            for (size_t i = 0; i < count; ++i) set.uvs[i] = {buffer[base + i].v[0], buffer[base + i].v[1]};
            set.faceVertexUvs = std::move(ids);
        } else {
            ColorSet& set = out.colorSets[c.set];
            set.colors.resize(count);
            for (size_t i = 0; i < count; ++i)
                set.colors[i] = {buffer[base + i].v[0], buffer[base + i].v[1], buffer[base + i].v[2], buffer[base + i].v[3]};
            set.faceVertexColors = std::move(ids);
        }
    }
    // Edges as OpenSubdiv numbers them; creases stay hard.
    out.edges.reserve(size_t(last.GetNumEdges()));
    for (int e = 0; e < last.GetNumEdges(); ++e) {
        const Far::ConstIndexArray ev = last.GetEdgeVertices(e);
        out.edges.push_back({uint32_t(ev[0]), uint32_t(ev[1]), !(params.keepHardEdges && last.GetEdgeSharpness(e) > 0.0f)});
    }
    if (faceOrigin) {
        std::vector<uint32_t> origin(size_t(last.GetNumFaces()));
        for (int f = 0; f < last.GetNumFaces(); ++f) {
            Far::Index parent = f;
            for (int l = levels; l >= 1; --l) parent = refiner->GetLevel(l).GetFaceParentFace(parent);
            origin[size_t(f)] = uint32_t(parent);
        }
        *faceOrigin = std::move(origin);
    }
    mesh = std::move(out);
    return true;
}

}  // namespace pushpin::geom
