// core/geom/geometry_handle.h: one shape's renderable geometry before it has triangles (DESIGN.md
// step 2): its source (an evaluated polygon mesh with the material of each face, or a NURBS surface
// with its per-span divisions), its object-space bounds, how many triangles it will make and how
// many of them a scanline crosses at a given screen size — all known without tessellating — and
// tessellate(), which the renderer calls when a tile first needs the shape (its tessellation cache
// keeps one per handle, shared by every instance that uses the handle).
// Thread safety: immutable after creation; every method may be called from any thread at once.
// Memory: a handle shares its source (std::shared_ptr) with the other handles of the same shape
// and keeps no triangles; sourceBytes() and tessellationBytesEstimate() are what it costs.
#pragma once

#include "core/geom/bounds.h"
#include "core/geom/mesh.h"
#include "core/geom/nurbs.h"
#include "core/geom/tessellation.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pushpin::geom {

class GeometryHandle {
public:
    // A mesh that passed Mesh::validate(), with one material slot per face (kNoFaceMaterial: not
    // rendered; empty: all 0) and the faces to drop (MeshValidation::degenerateFaces, or empty).
    static std::shared_ptr<GeometryHandle> fromMesh(std::shared_ptr<const Mesh> mesh, std::vector<uint16_t> faceMaterial,
                                                    std::shared_ptr<const std::vector<bool>> degenerate,
                                                    bool smoothShading);
    // A NURBS surface tessellated on a uniform grid of divU × divV steps per span (material 0).
    static std::shared_ptr<GeometryHandle> fromNurbs(std::shared_ptr<const NurbsSurface> surface, int divU, int divV);

    GeometryHandle(const GeometryHandle&) = delete;
    GeometryHandle& operator=(const GeometryHandle&) = delete;

    bool isMesh() const { return m_mesh != nullptr; }
    // Object space, conservative: the points of the faces kept (meshes), the control hull (NURBS
    // surfaces with positive weights, which lie inside it).
    const Bounds3& bounds() const { return m_bounds; }
    // Triangles the tessellation will have at most (meshes: exact unless ear clipping gives up on
    // a face; NURBS: zero-area triangles at poles are dropped).
    uint64_t triangleCount() const { return m_triangles; }
    // Material slots used (one more than the largest faceMaterial entry kept; 1 for NURBS).
    uint32_t materialCount() const { return m_materials; }
    // Triangles one scanline crossing the object is expected to meet when its screen box is
    // `screenHeight` pixels high: the triangles spread over the box's height, each as tall as a
    // cell of a square grid of triangleCount() triangles over it, and at least one pixel row.
    double trianglesPerScanline(double screenHeight) const;
    // Vertices the tessellation is expected to have (an estimate: the points used, and some more
    // where hard edges and uv seams split them; one per grid point for NURBS).
    uint64_t vertexCountEstimate() const { return m_vertices; }
    // Bytes the tessellation will hold (an estimate from the triangle and vertex counts).
    uint64_t tessellationBytesEstimate() const;
    // Bytes of the source (the mesh or surface), shared by the handles of one shape.
    uint64_t sourceBytes() const;
    const std::shared_ptr<const Mesh>& mesh() const { return m_mesh; }
    const std::shared_ptr<const NurbsSurface>& surface() const { return m_surface; }

    // Makes the tessellation, without keeping it. For NURBS surfaces that evaluate to
    // NaN/Inf the result is empty and `problem` (when given) says why.
    Tessellation tessellate(std::string* problem = nullptr) const;

private:
    GeometryHandle() = default;

    std::shared_ptr<const Mesh> m_mesh;
    std::vector<uint16_t> m_faceMaterial;
    std::shared_ptr<const std::vector<bool>> m_degenerate;
    bool m_smooth = true;
    std::shared_ptr<const NurbsSurface> m_surface;
    int m_divU = 1, m_divV = 1;
    Bounds3 m_bounds;
    uint64_t m_triangles = 0;
    uint64_t m_vertices = 0;  // estimate
    uint32_t m_materials = 1;
};

}  // namespace pushpin::geom
