// core/geom/detail/face_edit.h: editing a few faces of a large mesh in place, for the operators
// that cut faces (polySplit, polySplitRing): editable copies of the faces touched, faces appended
// after the existing ones, new corners with UVs interpolated, and the mesh rebuilt at the end.
// Private to core/geom.
// Thread safety: one editor per mesh, used by one thread. Memory: a copy of each face touched;
// untouched faces are copied once, when the mesh is rebuilt.
#pragma once

#include "core/geom/mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <map>
#include <span>
#include <tuple>
#include <vector>

namespace pushpin::geom::detail {

// A face-vertex of an edited face: its point and per-face-vertex data.
struct Corner {
    uint32_t point = 0;
    glm::vec3 normal{0.0f};       // zero: not set
    std::vector<int32_t> uvs;     // per UV set, -1 for none
    std::vector<int32_t> colors;  // per colour set, -1 for none
};
using FaceLoops = std::vector<std::vector<Corner>>;  // outer loop first, then holes

class FaceEditor {
public:
    // `work` is the mesh being edited; it must outlive the editor. Points may be appended to it
    // while editing; its faces must not change except through the editor.
    explicit FaceEditor(Mesh& work);

    // The editable loops of face `f` (an existing face, copied on first use, or an appended one).
    FaceLoops& face(uint32_t f);
    // Appends a face after every existing and earlier appended one; returns its index.
    uint32_t append(FaceLoops loops);
    size_t faceCount() const { return m_originalFaces + m_appended.size(); }

    // A corner at `point` on the edge from corner `a` to corner `b`, at fraction `t` from `a`: its
    // UVs interpolated along the edge (shared by every face that asks for the same pair and
    // fraction), no normal, no colour.
    Corner cornerOnEdge(const Corner& a, const Corner& b, uint32_t point, double t);
    // A corner at `point` whose UVs are the weighted sums of the UVs of `corners` (`weights`
    // parallel to them, summing to one); a set gets no UV where some corner has none.
    Corner cornerFromWeights(std::span<const Corner> corners, std::span<const double> weights, uint32_t point);

    // The edited mesh: `work`'s points and edges (moved out), faces in order with the edited
    // ones from their copies, then the appended ones. The editor is spent afterwards.
    Mesh rebuild();

private:
    Mesh& m_work;
    size_t m_originalFaces;
    std::map<uint32_t, FaceLoops> m_edited;
    std::vector<FaceLoops> m_appended;
    std::map<std::tuple<size_t, int32_t, int32_t, double>, int32_t> m_edgeUvs;
};

// Generalised barycentric (mean value) weights of `p` in the polygon `loop`, both taken into the
// plane perpendicular to `normal`: they interpolate linearly along the polygon's edges and are
// 1 at a corner `p` lies on.
std::vector<double> polygonWeights(std::span<const glm::dvec3> loop, const glm::dvec3& p, const glm::dvec3& normal);

}  // namespace pushpin::geom::detail
