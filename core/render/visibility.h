// core/render/visibility.h: Exact Area Sampling visibility for one tile (DESIGN.md 6b, 6d, 7;
// reference/algorithms.md §2): rasterizes screen triangles into per-pixel fragment lists, resolves
// each pixel's hidden surfaces with the coverage masks and per-sub-sample depths, merges fragments
// of one surface, and composites shaded surfaces into pixel contributions.
// Thread safety: a TileRasterizer or PixelResolver is used by one thread at a time; make one per
// thread and reuse it across tiles (buffers are kept, so steady state allocates nothing).
// Memory: the rasterizer's fragment buffer grows with the fragments of the tile (48 bytes each),
// in place (util::PageArray: growing holds no second copy), and is sorted by pixel in place; a
// tile keeps its resolved surfaces' members in it (reorderPixel).
//
// Coverage rule (what makes an isolated edge exact): a surface's coverage in a pixel is its exact
// clipped area scaled by the fraction of its mask sub-samples that stay visible. A surface that
// covers the whole pixel and is partly hidden gets exactly what the nearer opaque surfaces leave
// (1 − their coverage), so an edge in front of a full surface is exact as well. An opaque surface
// that covers the whole pixel closes it: a full surface behind it gets nothing. Opaque coverage
// never sums past 1.
#pragma once

#include "core/render/fragment.h"
#include "core/util/page_array.h"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace pushpin::render {

struct RasterStats {
    uint64_t trianglesRasterized = 0;  // triangles that touched the region
    uint64_t trianglesDegenerate = 0;  // zero area or non-finite coordinates: skipped
    uint64_t fragments = 0;            // fragments created
    void merge(const RasterStats& o) {
        trianglesRasterized += o.trianglesRasterized;
        trianglesDegenerate += o.trianglesDegenerate;
        fragments += o.fragments;
    }
};

class TileRasterizer {
public:
    explicit TileRasterizer(const SubsamplePattern& pattern);

    // Starts a new region (clears fragments, keeps capacity).
    void reset(const PixelRect& region);
    const PixelRect& region() const { return m_region; }

    // Adds the fragments of one triangle for every pixel of the region it overlaps with non-zero
    // area. Triangles with zero area or non-finite coordinates add nothing and are counted.
    void add(const ScreenTriangle& triangle);

    // Groups the fragments by pixel, in place; afterwards fragments(x, y) is valid until the next
    // reset/add. The order within a pixel depends only on the order of the adds.
    void finish();
    std::span<const Fragment> fragments(int x, int y) const;
    // After finish(): every fragment, pixel by pixel; each fragments(x, y) is a part of it.
    std::span<const Fragment> sortedFragments() const;
    // Overwrites pixel (x, y)'s fragments with `reordered`, the same fragments in another order (as
    // PixelResolver::members() gives them), so that a tile keeps its surfaces' members where the
    // fragments are instead of in a copy. Throws std::invalid_argument when the counts differ or
    // the fragments are not finished.
    void reorderPixel(int x, int y, std::span<const Fragment> reordered);
    // Fragments added since the last reset.
    size_t fragmentCount() const { return m_fragments.size(); }

    const RasterStats& stats() const { return m_stats; }
    // Puts the counts back to `s` (a tile that is given up and rendered again later).
    void restoreStats(const RasterStats& s) { m_stats = s; }
    // Bytes the rasterizer's buffers hold (their capacities).
    uint64_t bytes() const;
    // Called before a buffer grows, with the bytes the growth allocates while the old buffers are
    // still held (for the fragments, grown in place, only what they grow by), so that a memory
    // budget can make room first (it may throw to stop the tile). Buffers grow at least by half,
    // so the calls are few.
    void setGrowHook(std::function<void(uint64_t)> hook) { m_growHook = std::move(hook); }
    // Gives the buffers' memory back (stats are kept); the next reset() starts from nothing.
    void releaseMemory();

private:
    SubsamplePattern m_pattern;
    PixelRect m_region;
    util::PageArray<Fragment> m_fragments;  // in insertion order until finish(), then by pixel
    std::vector<uint32_t> m_pixelStart;     // region pixel index → first fragment after finish() (+1 end)
    std::vector<uint32_t> m_pixelFill, m_rowStart, m_columnStart;  // finish()'s scratch
    RasterStats m_stats;
    std::function<void(uint64_t)> m_growHook;
    // Whether every fragment is grouped by pixel (finish() since the last reset/add).
    bool finished() const { return !m_pixelStart.empty() && m_pixelStart.back() == m_fragments.size(); }
    // Room for `fragments` fragments in m_fragments (the hook told first).
    void reserveFragments(size_t fragments);
};

// One surface in one pixel: the merged fragments of one object joined by soft edges.
struct SurfaceGroup {
    uint32_t object = 0;
    uint32_t memberBegin = 0, memberCount = 0;  // into PixelResolver::members()
    uint64_t mask = 0;          // union of the members' masks
    uint64_t visibleMask = 0;   // sub-samples where this surface is seen (not behind an opaque one)
    float area = 0.0f;          // sum of the members' exact areas
    float coverage = 0.0f;      // visible area, see the coverage rule above
    float cu = 0.5f, cv = 0.5f; // centroid of the visible part (of the whole group when no bit is visible)
    float depth = 0.0f;         // depth key used to order surfaces front to back
    bool transparent = false;
};

// The shaded result of one surface group: Maya's outColor (already scaled by opacity for the
// materials that do so) and outTransparency, per channel.
struct SurfaceShade {
    float color[3] = {0, 0, 0};
    float transparency[3] = {0, 0, 0};
};

// What one surface contributes to the image: premultiplied colour and alpha, and where in the
// pixel it sits (pixel-local centroid), for multi-pixel filters.
struct SurfaceContribution {
    float color[3] = {0, 0, 0};
    float alpha = 0.0f;
    float cu = 0.5f, cv = 0.5f;
};

struct ResolveStats {
    uint64_t pixels = 0;          // pixels with at least one fragment
    uint64_t surfaces = 0;        // surface groups after merging
    uint64_t mergedFragments = 0; // fragments that joined another fragment's group
    void merge(const ResolveStats& o) {
        pixels += o.pixels;
        surfaces += o.surfaces;
        mergedFragments += o.mergedFragments;
    }
};

class PixelResolver {
public:
    // `topology` is indexed by object id.
    PixelResolver(const SubsamplePattern& pattern, std::span<const ObjectTopology> topology);

    // Resolves one pixel's fragments. Results stay valid until the next call. Deterministic:
    // independent of the order of `fragments` (ties are broken by object, then triangle index).
    void resolve(std::span<const Fragment> fragments);

    // Surfaces sorted front to back (by depth, then object, then first triangle).
    std::span<const SurfaceGroup> groups() const { return m_groups; }
    // Fragment copies of every group's members, group by group (SurfaceGroup::memberBegin/Count).
    std::span<const Fragment> members() const { return m_members; }
    // The member of `group` whose mask holds sub-sample `bit`; the largest member when none does.
    const Fragment& memberAt(const SurfaceGroup& group, int bit) const;
    // Nearest depth key of an opaque visible surface at any active sub-sample, +inf when none.
    float nearestDepth() const { return m_nearestDepth; }
    // Sum of the opaque surfaces' coverage (0..1).
    float opaqueCoverage() const { return m_opaqueCoverage; }

    // The depth key behind which these fragments hide everything (DESIGN.md step 5a): a surface of
    // another object whose every point lies behind it (occludedBehind) gets no coverage, no
    // sub-sample and no shading sample, and changes no other surface's coverage or contribution,
    // whatever else the pixel receives — so leaving it out changes no bit of the image. It takes
    // an opaque surface that covers the whole pixel (soft-edge neighbours of one object with the
    // pixel's area between them) and opaque fragments over every active sub-sample; the depth is
    // the farthest any of them reaches over the pixel square. +inf when the pixel is not sealed.
    // Uses the resolver's scratch buffers: groups() and members() are invalid afterwards.
    float occludingDepth(std::span<const Fragment> fragments);

    // Composites shaded surfaces front to back, sub-sample by sub-sample (transparent surfaces
    // let what lies behind them through, per channel). `shades` is parallel to groups(); `out`
    // receives one contribution per group.
    void composite(std::span<const SurfaceShade> shades, std::span<SurfaceContribution> out) const;

    const ResolveStats& stats() const { return m_stats; }
    // Puts the counts back to `s` (a tile that is given up and rendered again later).
    void restoreStats(const ResolveStats& s) { m_stats = s; }
    // Heap bytes the resolver's buffers hold (their capacities).
    uint64_t bytes() const;
    // Gives the buffers' memory back (stats are kept); results are invalid afterwards.
    void releaseMemory();

private:
    SubsamplePattern m_pattern;
    std::span<const ObjectTopology> m_topology;
    std::vector<SurfaceGroup> m_groups;
    std::vector<Fragment> m_members;
    float m_nearestDepth = 0.0f;
    float m_opaqueCoverage = 0.0f;
    ResolveStats m_stats;
    // scratch
    std::vector<uint32_t> m_parent;
    std::vector<uint64_t> m_triangleTable;  // joinSoftNeighbours' hash table of a run's triangles
    std::vector<uint64_t> m_visible;
    std::vector<Fragment> m_sorted;   // the input in canonical (object, triangle, …) order
    std::vector<uint32_t> m_order;    // m_sorted indices, grouped by surface group
    std::vector<float> m_far, m_groupFar;
    std::vector<double> m_groupArea;
};

// Whether a surface whose depth keys are all at least `nearestDepthKey` lies behind a pixel's
// PixelResolver::occludingDepth, with a margin of 1e-3 of the depth that float depth planes
// cannot cross. False for an infinite or NaN depth (an object reaching the near plane).
bool occludedBehind(float occludingDepth, double nearestDepthKey);

// The member of `group` (members indexed by group.memberBegin/memberCount) whose mask holds
// sub-sample `bit`, the nearest there when several do; the largest member when none does.
const Fragment& surfaceMemberAt(std::span<const Fragment> members, const SurfaceGroup& group, int bit);

// PixelResolver::composite over surfaces kept elsewhere (a tile keeps every pixel's groups and
// members to composite them again after adaptive shading): `groups` are one pixel's surfaces in
// front-to-back order, their member ranges index `members`.
void compositeSurfaces(const SubsamplePattern& pattern, std::span<const SurfaceGroup> groups,
                       std::span<const Fragment> members, std::span<const SurfaceShade> shades,
                       std::span<SurfaceContribution> out);

}  // namespace pushpin::render
