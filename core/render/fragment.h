// core/render/fragment.h: the plain data of Exact Area Sampling (reference/algorithms.md §2,
// DESIGN.md step 6b): screen triangles, the 8×8 sub-sample grid of a pixel ("the pushpin array"),
// the quality levels that pick which sub-samples are in use, and fragments (a triangle clipped to
// one pixel, with its exact area, its coverage mask and its depth plane).
// Plain values; thread-safe. Memory: fragments live in a per-tile buffer (see visibility.h).
//
// Conventions
// - Raster space: x to the right, y down, in pixels; pixel (i, j) covers [i, i+1) × [j, j+1).
// - Pixel-local space: (u, v) = raster position minus the pixel's corner, both in [0, 1].
// - Sub-sample b (0..63) of the 8×8 grid sits at u = (b % 8 + 0.5) / 8, v = (b / 8 + 0.5) / 8.
// - Depth key `z`: affine in raster space, smaller is nearer. The projection chooses it:
//   −1/distance for perspective cameras (1/distance is affine in screen space), the distance
//   along the view axis for orthographic ones. Only comparisons and interpolation use it.
#pragma once

#include "core/geom/slot_run.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <ostream>

namespace pushpin::render {

constexpr int kSubsampleGrid = 8;
constexpr int kSubsampleCount = kSubsampleGrid * kSubsampleGrid;
constexpr uint32_t kNoTriangle = 0xffffffffu;
// In ObjectTopology neighbour entries: the shared edge is hard (fragments across it never merge).
constexpr uint32_t kHardEdgeBit = 0x80000000u;

// A rectangle of pixels, half-open: [x0, x1) × [y0, y1), raster coordinates.
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 > x0 ? x1 - x0 : 0; }
    int height() const { return y1 > y0 ? y1 - y0 : 0; }
    bool empty() const { return width() == 0 || height() == 0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool operator==(const PixelRect&) const = default;
};
inline std::ostream& operator<<(std::ostream& os, const PixelRect& r) {
    return os << "[" << r.x0 << "," << r.x1 << ")x[" << r.y0 << "," << r.y1 << ")";
}

// Which sub-samples of the 8×8 grid visibility uses, by Maya's edgeAntiAliasing level
// (reference/render-globals.md): Low 2 points, Medium 8, High 32, Highest all 64. The exact
// clipped area is computed at every level; the level decides how finely overlapping surfaces are
// told apart inside a pixel and caps the shading samples a fragment can take.
struct SubsamplePattern {
    uint64_t active = 0;                 // bit b set: sub-sample b is in use
    int count = 0;                       // popcount(active)
    // The active sub-samples in a stratified order: every prefix is spread over the pixel, so the
    // first n of a fragment's visible sub-samples make n well-placed shading positions.
    std::array<uint8_t, kSubsampleCount> order{};
    int edgeAntiAliasing = 0;            // 0 Highest, 1 High, 2 Medium, 3 Low

    // eaa outside 0..3 is clamped.
    static SubsamplePattern forEdgeAntiAliasing(int edgeAntiAliasing);
};

// A triangle ready for visibility, in raster space. Winding may be either way.
struct ScreenTriangle {
    double x[3], y[3];   // raster positions
    double z[3];         // depth keys (see above)
    uint32_t object = 0;     // index of the render object (a shape instance)
    uint32_t triangle = 0;   // index of the triangle within the object
    bool transparent = false;  // its shading network may return transparency: it hides nothing
};

// One triangle clipped to one pixel. 48 bytes: tiles hold millions of these, so it stays small;
// attributes for shading are recovered later from (object, triangle) and the raster position.
struct Fragment {
    uint64_t mask = 0;       // active sub-samples inside the triangle (top-left fill rule on edges)
    float area = 0.0f;       // exact area of triangle ∩ pixel, in pixels (0..1]
    float cu = 0.5f, cv = 0.5f;  // centroid of triangle ∩ pixel, pixel-local
    float z0 = 0.0f, dzdu = 0.0f, dzdv = 0.0f;  // depth plane: z(u, v) = z0 + dzdu·u + dzdv·v
    uint32_t object = 0;
    uint32_t triangle = 0;
    uint32_t flags = 0;      // kFragmentTransparent …
    uint32_t pixel = 0;      // the rasterizer's region pixel, row by row (what the struct's padding held)
    float depthAt(float u, float v) const { return z0 + dzdu * u + dzdv * v; }
};
constexpr uint32_t kFragmentTransparent = 1u;
static_assert(sizeof(Fragment) == 48, "Fragment is the unit of tile memory; keep it at 48 bytes");

// The adjacency of the triangles of one piece of an object made in pieces: neighbors[3·i + k]
// for the piece's triangle i (ObjectTopology::runs say which triangle ids those are); null while
// the piece is not at hand (its triangles then have no fragments). A piece that keeps only some of
// its triangles lists them in `ids` instead: triangleCount ascending indices i, neighbors[3·j + k]
// for the triangle ids[j].
struct TopologyPiece {
    uint32_t triangleCount = 0;
    const uint32_t* neighbors = nullptr;
    const uint32_t* ids = nullptr;
};

// Triangle adjacency of one render object, for merging and occlusion decisions:
// neighbors[3·t + k] is the triangle across edge k of triangle t (edge k joins corner k and
// corner (k+1)%3), with kHardEdgeBit set when the edge is hard or the two triangles belong to
// different shading groups; kNoTriangle on a boundary. Fragments of one object merge across
// soft edges only. An object made in pieces lists them instead (`pieces`, one per piece, and
// `runs`, sorted by firstSlot, the piece and place of each triangle id; `neighbors` null);
// neighbours are then triangle ids of any piece.
struct ObjectTopology {
    const uint32_t* neighbors = nullptr;
    uint32_t triangleCount = 0;
    const TopologyPiece* pieces = nullptr;
    uint32_t pieceCount = 0;
    const geom::SlotRun* runs = nullptr;
    uint32_t runCount = 0;

    // The three neighbour entries of triangle t, or null when it has none at hand.
    const uint32_t* neighborsOf(uint32_t t) const {
        if (!pieces) return neighbors && t < triangleCount ? neighbors + 3 * size_t(t) : nullptr;
        const geom::SlotRun* run = geom::findSlotRun(runs, runCount, t);
        if (!run || run->piece >= pieceCount) return nullptr;
        const TopologyPiece& p = pieces[run->piece];
        if (!p.neighbors) return nullptr;
        const uint32_t local = run->local + (t - run->firstSlot);
        if (p.ids) {
            const uint32_t* end = p.ids + p.triangleCount;
            const uint32_t* at = std::lower_bound(p.ids, end, local);
            return at != end && *at == local ? p.neighbors + 3 * size_t(at - p.ids) : nullptr;
        }
        return local < p.triangleCount ? p.neighbors + 3 * size_t(local) : nullptr;
    }
    bool empty() const { return !neighbors && !pieces; }
};

}  // namespace pushpin::render
