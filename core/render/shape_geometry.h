// core/render/shape_geometry.h: a shape's geometry as the frame scene gets it (DESIGN.md step 2):
// a mesh evaluated through its history and validated, with its degenerate faces marked, or a
// NURBS surface with its per-span divisions; evaluated once whatever the number of instances. A
// mesh a handle must make again later (under a memory cap, or straight from a primitive) comes
// from an EvaluatedMesh, which evaluates it again on the tessellating thread.
#pragma once

#include "core/geom/geometry_handle.h"
#include "core/geom/mesh.h"
#include "core/geom/nurbs.h"
#include "core/geom/poly_primitives.h"
#include "core/scene/evaluator.h"
#include "core/scene/graph.h"
#include "core/scene/mesh_eval.h"

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace pushpin::render {

// One Evaluator per thread over the scene at the frame, for meshes evaluated again when a tile
// needs their triangles (an Evaluator is not thread-safe; the Graph is only read).
class EvaluatorPool {
public:
    EvaluatorPool(const scene::Graph& graph, double frame) : m_graph(graph), m_frame(frame) {}
    scene::Evaluator& local() {
        std::unique_ptr<scene::Evaluator>& ev = m_evaluators.local();
        if (!ev) ev = std::make_unique<scene::Evaluator>(m_graph, m_frame);
        return *ev;
    }

private:
    const scene::Graph& m_graph;
    double m_frame;
    tbb::enumerable_thread_specific<std::unique_ptr<scene::Evaluator>> m_evaluators;
};

// A mesh shape evaluated again, on the calling thread's Evaluator, each time it is asked for.
// A shape that is its stored mesh (scene::storedMeshMakesWindows) makes each piece's window from
// the stored data alone.
class EvaluatedMesh final : public geom::MeshSource {
public:
    EvaluatedMesh(std::shared_ptr<EvaluatorPool> pool, scene::NodeId shape)
        : m_pool(std::move(pool)), m_shape(shape), m_windows(scene::storedMeshMakesWindows(m_pool->local(), shape)) {}
    std::shared_ptr<const geom::Mesh> mesh() const override {
        scene::MeshEvaluation e = scene::evaluateMeshShape(m_pool->local(), m_shape);
        return std::make_shared<const geom::Mesh>(e.mesh ? std::move(*e.mesh) : geom::Mesh{});
    }
    bool keepsMesh() const override { return false; }
    bool makesWindows() const override { return m_windows; }
    std::optional<geom::MeshWindow> window(const geom::MeshPieces& pieces, size_t piece,
                                           uint64_t faceVertexCount) const override {
        if (!m_windows) return std::nullopt;
        return scene::decodeStoredMeshWindow(m_pool->local().graph(), m_shape, pieces, piece, faceVertexCount);
    }

private:
    std::shared_ptr<EvaluatorPool> m_pool;
    scene::NodeId m_shape;
    bool m_windows;
};

// Geometry of one shape, evaluated once whatever its number of instances.
struct ShapeGeometry {
    bool failed = false;
    std::string skipReason;
    scene::MeshEvaluation evaluation;                    // meshes: groups, face origins (mesh moved out)
    std::shared_ptr<const geom::Mesh> mesh;              // meshes, validated
    std::shared_ptr<const geom::MeshSource> source;      // meshes: where the handles get them again
    std::shared_ptr<const std::vector<bool>> degenerate;  // meshes: faces to drop
    std::shared_ptr<const geom::NurbsSurface> surface;   // NURBS surfaces (one material)
    int divU = 1, divV = 1;
    // The handle made for the last instance, reused by the next with the same face materials and
    // smoothShading: instances share one tessellation.
    std::shared_ptr<const geom::GeometryHandle> lastHandle;
    std::vector<uint16_t> lastMaterials;
    bool lastSmooth = true;
    // Meshes straight from a primitive: its counts and bounds, so that an instance in one shading
    // group as a whole gets a handle that makes the mesh only when a tile first needs it.
    std::optional<geom::PrimitiveCounts> counts;
    std::shared_ptr<const geom::GeometryHandle> deferredHandle;
    bool deferredSmooth = true;
};

// Evaluates `shape` (a mesh or a NURBS surface; `label` names it in notes) into `out`. A shape
// that cannot render sets out.failed with the reason in out.skipReason; notes about what was
// dropped or replaced (degenerate faces, evaluation notes) go to `notes`. std::bad_alloc passes
// through; any other exception fails the shape.
void evaluateShape(scene::Evaluator& ev, scene::NodeId shape, const std::string& label, ShapeGeometry& out,
                   std::vector<std::string>& notes);

// Per-span divisions for one direction: ceil(number · factor), at least 1 (reference/algorithms.md
// §8: numberU/V isoparms per span, u/vDivisionsFactor). Capped so a wild value cannot exhaust memory.
// A value that is not finite falls back to the defaults (3 and 1.5) with a note; more than 256
// divisions are capped with a note.
int spanDivisions(scene::Evaluator& ev, scene::NodeId shape, const char* numberAttr, const char* factorAttr,
                  const std::string& label, std::vector<std::string>& notes);

}  // namespace pushpin::render
