// core/geom/triangulate.h: triangulation of one planar-ish polygon with holes (a Maya face) by ear
// clipping in the plane perpendicular to a given normal, holes bridged into the outer loop first
// (D. Eberly, "Triangulation by Ear Clipping", Geometric Tools, 2002). Concave outlines are
// handled exactly; triangles keep the winding of the outer loop.
// Thread safety: a PolygonTriangulator holds scratch memory; use one per thread.
// Memory: the scratch grows to the largest polygon seen and is reused.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace pushpin::geom {

class PolygonTriangulator {
public:
    // Triangulates the polygon whose loops are stored back to back in `points`: loop l covers
    // points[loopStarts[l], loopStarts[l+1]); loop 0 is the outer boundary, the others holes
    // (either winding is accepted for holes). `normal` gives the projection plane (any length;
    // when zero or non-finite, the outer loop's Newell normal is used). Appends triangles as
    // triples of indices into `points` and returns how many were appended.
    // Triangles wind like the outer loop (counter-clockwise about `normal` when the outer loop
    // is). Zero-area triangles are never emitted: consecutive duplicate points, collinear
    // spikes and degenerate polygons shrink the output; a hole that does not lie inside the
    // outer loop is ignored. Never throws (beyond std::bad_alloc) and never loops forever,
    // including for NaN/Inf coordinates (such a polygon gives no triangles).
    size_t triangulate(std::span<const glm::dvec3> points, std::span<const uint32_t> loopStarts,
                       const glm::dvec3& normal, std::vector<uint32_t>& triangles);

private:
    bool bridgeHole(size_t holeBegin, size_t holeEnd);
    size_t clipEars(std::vector<uint32_t>& triangles);

    std::vector<glm::dvec2> m_p;       // projected points, parallel to the input
    std::vector<uint32_t> m_ring;      // the outer ring with holes bridged in (indices into m_p)
    std::vector<uint32_t> m_holes;     // hole rings, back to back
    std::vector<uint32_t> m_holeStarts;
    std::vector<size_t> m_order;       // holes, rightmost first
    std::vector<uint32_t> m_prev, m_next;  // linked list over ring positions during clipping
    std::vector<uint8_t> m_reflex;
    double m_epsArea = 0.0;            // cross products below this count as zero
};

}  // namespace pushpin::geom
