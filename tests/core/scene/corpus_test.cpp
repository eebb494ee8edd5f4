// Reads every public .ma scene and checks what the --info report says about them. The expected
// counts were established by reading the files (createNode lines, parenting, connections).
#include "core/geom/mesh.h"
#include "core/scene/components.h"
#include "core/scene/evaluator.h"
#include "core/scene/ma_reader.h"
#include "core/scene/mesh_eval.h"
#include "core/scene/render_setup.h"
#include "core/scene/scene_info.h"

#include "tests/support/ma_corpus.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

namespace pushpin::scene {
namespace {

namespace fs = std::filesystem;

using test::maCorpusDir;
using test::maCorpusFiles;

TEST(Corpus, EveryFileLoadsAndReports) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    for (const fs::path& file : maCorpusFiles()) {
        SCOPED_TRACE(file.filename().string());
        Graph g;
        ASSERT_NO_THROW(g = MaReader::readFile(file));
        std::string json;
        ASSERT_NO_THROW(json = sceneInfoJson(g, sceneCurrentFrame(g)));
        EXPECT_FALSE(json.empty());
        SceneReport report = describeScene(g, sceneCurrentFrame(g));
        for (const ShapeReport& s : report.shapes) {
            if (s.renderable) {
                EXPECT_FALSE(s.worldBounds.empty()) << s.path;
                EXPECT_FALSE(s.shadingGroups.empty()) << s.path;
            } else {
                EXPECT_FALSE(s.reason.empty()) << s.path;
            }
        }
    }
}

struct Expected {
    const char* file;
    size_t shapes, lights, cameras, shadingGroups;  // shading groups include Maya's two defaults
};

// initialShadingGroup and initialParticleSE exist in every scene.
constexpr size_t kDefaultShadingGroups = 2;

// Reads `folder / e.file` and checks its shape, light, camera and shading-group counts.
void expectCounts(const fs::path& folder, const Expected& e) {
    SCOPED_TRACE(e.file);
    const fs::path file = folder / e.file;
    ASSERT_TRUE(fs::exists(file));
    Graph g = MaReader::readFile(file);
    SceneReport report = describeScene(g, sceneCurrentFrame(g));
    RenderSetup setup = extractRenderSetup(g);
    EXPECT_EQ(report.shapes.size(), e.shapes);
    EXPECT_EQ(setup.lights.size(), e.lights);
    EXPECT_EQ(setup.cameras.size(), e.cameras);
    EXPECT_EQ(setup.shadingGroups.size(), e.shadingGroups + kDefaultShadingGroups);
}

TEST(Corpus, CountsMatchWhatTheFilesSay) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const Expected expected[] = {
        {"yamins81__cgkit__objects.ma", 2, 0, 0, 0},
        {"haggi__OpenMaya__mayaSpotSoftShadows.ma", 2, 1, 4, 0},
        {"appleseedhq__appleseed-maya__face_materials.ma", 1, 1, 4, 3},
        {"Autodesk__maya-usd__ProxyShapeDrawLightingTest.ma", 2, 8, 5, 2},
        {"tws0002__pop2-project__Terrain.ma", 1, 3, 1, 2},
        {"tws0002__pop2-project__LavaLamp.ma", 10, 3, 5, 7},
        {"sebastienblor__arnold-usd__test_0068_test.ma", 3, 2, 5, 13},
        {"amju-games__music-theory__door2.ma", 17, 0, 5, 12},
        {"tws0002__pop2-project__CarrotTop.ma", 6, 0, 4, 4},
    };
    for (const Expected& e : expected) expectCounts(maCorpusDir(), e);
}

// Six scenes laid out as their authors' projects, counted by reading each file's createNode and
// parent -add lines (shapes are mesh and NURBS surface instances).
TEST(Corpus, ProjectSceneCountsMatchWhatTheFilesSay) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    const Expected expected[] = {
        {"Autodesk__maya-hydra__testUDIMs/test/testSamples/testUVandUDIM/testUDIMs.ma", 1, 0, 4, 1},
        {"amju-games__amju-ww__crate2/Assets/maya/unused/crate2.ma", 1, 0, 4, 2},
        {"Crayfish__mayakurs2012__spitzhacke_texture3/group3/spitzhacke_texture3.ma", 2, 0, 4, 4},
        {"Crayfish__mayakurs2012__Hochsitz/group6/__new_feldlager_marlis_streicher/Hochsitz/Hochsitz.ma", 83, 0, 4, 18},
        {"elliotfiske__slumber-models__bed/scenes/bed.ma", 29, 1, 4, 3},
        {"Crayfish__mayakurs2012__ocean/group1/ocean.ma", 2, 2, 4, 8},
    };
    for (const Expected& e : expected) expectCounts(test::maProjectsDir(), e);
}

TEST(Corpus, PerFaceMaterialsAreComponentMembers) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    Graph g = MaReader::readFile(maCorpusDir() / "appleseedhq__appleseed-maya__face_materials.ma");
    RenderSetup setup = extractRenderSetup(g);
    size_t componentMembers = 0;
    for (const ShadingGroupInfo& sg : setup.shadingGroups)
        for (const SetMember& m : sg.members)
            if (m.objectGroup >= 0) {
                ++componentMembers;
                EXPECT_FALSE(m.components.empty()) << sg.name;
            }
    EXPECT_GE(componentMembers, 2u);
    SceneReport report = describeScene(g, 1.0);
    ASSERT_EQ(report.shapes.size(), 1u);
    EXPECT_GE(report.shapes[0].shadingGroups.size(), 2u);
}

TEST(Corpus, LightLinksAreKept) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    Graph g = MaReader::readFile(maCorpusDir() / "Autodesk__maya-usd__ProxyShapeDrawLightingTest.ma");
    RenderSetup setup = extractRenderSetup(g);
    EXPECT_FALSE(setup.lightLinks.empty());
    bool sawLink = false;
    for (const LightLink& l : setup.lightLinks) sawLink |= l.kind == "link";
    EXPECT_TRUE(sawLink);
}

// Across every real scene of both folders: how many shape instances the scene asks to render
// (neither intermediate objects nor hidden) pushpin renders, and why it skips the rest.
TEST(Corpus, ShareOfWantedShapesThatRender) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    size_t renderable = 0, unwanted = 0;
    std::map<std::string, size_t> reasons;
    for (const fs::path& file : test::realSceneFiles()) {
        Graph g = MaReader::readFile(file);
        for (const ShapeReport& s : describeScene(g, sceneCurrentFrame(g)).shapes) {
            if (s.renderable) {
                ++renderable;
            } else if (s.reason == "intermediate object" || s.reason.rfind("hidden", 0) == 0) {
                ++unwanted;
            } else {
                // "history node polySplit (polySplit1) is not evaluated" → "history node polySplit is not evaluated"
                std::string r = s.reason;
                if (size_t open = r.find(" ("); open != std::string::npos)
                    if (size_t close = r.find(')', open); close != std::string::npos) r.erase(open, close + 1 - open);
                ++reasons[r];
            }
        }
    }
    size_t skipped = 0;
    for (const auto& [r, n] : reasons) skipped += n;
    const double share = double(renderable) / double(std::max<size_t>(1, renderable + skipped));
    std::printf("shape instances: %zu render, %zu skipped, %zu intermediate or hidden: %.1f%% of those wanted render\n",
                renderable, skipped, unwanted, 100.0 * share);
    for (const auto& [r, n] : reasons) std::printf("  %4zu  %s\n", n, r.c_str());
    // The acceptance point: at least 95% of the wanted shape instances render.
    EXPECT_GE(share, 0.95);
}

namespace extrude_bounds {

// Maya records on each polyExtrudeFace the world-space bounds of the faces it extrudes, as they
// were when the extrusion was made (compBoundingBoxMin/Max). Evaluating the history below each
// extrusion and measuring the selected faces must give the same box: this pins the numbering of
// points and faces that every earlier extrusion, tweak and split produced.
struct Tally {
    size_t checked = 0, matched = 0;
    std::vector<std::string> mismatches;
};

void checkFile(const fs::path& file, Tally& tally) {
    Graph g = MaReader::readFile(file);
    Evaluator ev(g, sceneCurrentFrame(g));
    for (NodeId n = 0; n < g.size(); ++n) {
        const Node& node = g.node(n);
        if (node.type != "polyExtrudeFace" || !g.value(n, "cbn") || !g.value(n, "ics")) continue;
        const Plug* in = nullptr;
        for (const Connection* c : g.inputs(n))
            if (c->dst.path == "inputPolymesh") in = &c->src;
        if (!in) continue;
        MeshEvaluation input = evaluateMeshPlug(ev, *in);
        if (!input.mesh) continue;
        const ComponentList* list = std::get_if<ComponentList>(g.value(n, "ics"));
        if (!list) continue;
        const std::vector<bool> faces =
            componentMask(parseComponents(*list).ranges, ComponentKind::Face, input.mesh->faceCount());
        std::vector<double> ix;
        glm::dmat4 world(1.0);
        if (ev.numbers(n, "ix", ix) && ix.size() == 16) world = glm::make_mat4(ix.data());
        glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
        bool any = false;
        for (size_t f = 0; f < faces.size(); ++f) {
            if (!faces[f]) continue;
            for (uint32_t fv = input.mesh->faceVertexBegin(f); fv < input.mesh->faceVertexEnd(f); ++fv) {
                const glm::dvec3 p(world * glm::dvec4(glm::dvec3(input.mesh->points[input.mesh->faceVertices[fv]]), 1.0));
                lo = glm::min(lo, p);
                hi = glm::max(hi, p);
                any = true;
            }
        }
        if (!any) continue;
        const glm::dvec3 cbn = ev.getDouble3(n, "cbn"), cbx = ev.getDouble3(n, "cbx");
        const double tolerance = 1e-3 * std::max(1.0, glm::length(cbx - cbn));
        ++tally.checked;
        if (glm::length(lo - cbn) <= tolerance && glm::length(hi - cbx) <= tolerance) {
            ++tally.matched;
        } else {
            char buf[256];
            std::snprintf(buf, sizeof buf, " got (%.4g %.4g %.4g)-(%.4g %.4g %.4g), Maya (%.4g %.4g %.4g)-(%.4g %.4g %.4g)",
                          lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, cbn.x, cbn.y, cbn.z, cbx.x, cbx.y, cbx.z);
            tally.mismatches.push_back(file.filename().string() + " " + node.name + buf);
        }
    }
}

}  // namespace extrude_bounds

TEST(Corpus, ExtrudedFacesHaveTheBoundsMayaRecorded) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    extrude_bounds::Tally tally;
    for (const fs::path& file : test::realSceneFiles()) extrude_bounds::checkFile(file, tally);
    std::printf("polyExtrudeFace selections: %zu of %zu match Maya's recorded bounds\n", tally.matched, tally.checked);
    for (const std::string& m : tally.mismatches) std::printf("  %s\n", m.c_str());
    // Three selections on one clock pillar stay off by a few percent: a fan of triangles scaled
    // about their own centres spreads a little less here than in Maya.
    EXPECT_GE(tally.checked, 68u);
    EXPECT_GE(tally.matched, 46u);
}

// Every polySplitRing names its ring by edge numbers of the mesh below it: the ring is whole
// (each of its edges faces another of them across a quad) only when every extrusion, split and
// primitive upstream numbered its edges as Maya did.
TEST(Corpus, SplitRingsNameWholeRings) {
    PUSHPIN_REQUIRE_MA_CORPUS();
    size_t checked = 0, whole = 0;
    std::vector<std::string> broken;
    for (const fs::path& file : test::realSceneFiles()) {
        Graph g = MaReader::readFile(file);
        Evaluator ev(g, sceneCurrentFrame(g));
        for (NodeId n = 0; n < g.size(); ++n) {
            if (g.node(n).type != "polySplitRing") continue;
            const ComponentList* list = g.value(n, "ics") ? std::get_if<ComponentList>(g.value(n, "ics")) : nullptr;
            const Plug* in = nullptr;
            for (const Connection* c : g.inputs(n))
                if (c->dst.path == "inputPolymesh") in = &c->src;
            if (!list || !in) continue;
            MeshEvaluation input = evaluateMeshPlug(ev, *in);
            if (!input.mesh) continue;
            geom::Mesh& m = *input.mesh;
            geom::completeEdges(m, true);
            const std::vector<bool> ring = componentMask(parseComponents(*list).ranges, ComponentKind::Edge, m.edges.size());
            std::map<std::pair<uint32_t, uint32_t>, size_t> index;
            for (size_t e = 0; e < m.edges.size(); ++e)
                index[{std::min(m.edges[e].v0, m.edges[e].v1), std::max(m.edges[e].v0, m.edges[e].v1)}] = e;
            auto edgeOf = [&](uint32_t a, uint32_t b) {
                const auto it = index.find({std::min(a, b), std::max(a, b)});
                return it == index.end() ? SIZE_MAX : it->second;
            };
            std::vector<bool> paired(m.edges.size(), false);
            for (size_t f = 0; f < m.faceCount(); ++f) {
                const auto q = m.faceOuterLoop(f);
                if (q.size() != 4 || m.holeCount(f) != 0) continue;
                for (size_t k = 0; k < 2; ++k) {
                    const size_t a = edgeOf(q[k], q[k + 1]), b = edgeOf(q[k + 2], q[(k + 3) % 4]);
                    if (a < ring.size() && b < ring.size() && ring[a] && ring[b]) paired[a] = paired[b] = true;
                }
            }
            size_t edges = 0, ok = 0;
            for (size_t e = 0; e < ring.size(); ++e)
                if (ring[e]) {
                    ++edges;
                    ok += paired[e];
                }
            if (edges < 2) continue;
            ++checked;
            if (ok == edges) ++whole;
            else broken.push_back(file.filename().string() + " " + g.node(n).name);
        }
    }
    std::printf("polySplitRing rings: %zu of %zu whole on the evaluated mesh below them\n", whole, checked);
    for (size_t k = 0; k < broken.size() && k < 8; ++k) std::printf("  %s\n", broken[k].c_str());
    // bed.ma's polySplitRing5 follows a polyDelEdge and extrusions of three-face regions whose
    // edge numbering is not yet Maya's.
    EXPECT_GE(checked, 40u);
    EXPECT_GE(whole, 39u);
}

}  // namespace
}  // namespace pushpin::scene
