// core/render/tile_plan.h: how the image is cut into tiles rendered in parallel (DESIGN.md step 5):
// the fixed grid of Maya's forceTileSize (planTiles), and the memory-driven plan that starts from
// the four quadrants of the region and splits every tile whose most expensive scanline costs more
// than maxTileCost triangles, down to a floor of 16×16 pixels (planAdaptiveTiles, after the
// Maya Software Rendering technical overview, Pearce & Sung 1998). The adaptive plan works from
// one screen box and one scanline cost per object (ScreenCost), so planning tessellates nothing.
// Also the --tile-pattern picture of a plan: each tile coloured by its cost.
// Pure functions (writeTilePattern writes one file); all reentrant and thread-safe.
// Memory: small and uncharged. planAdaptiveTiles keeps one index list per level of the
// subdivision it is in (at most objects × depth indices) and returns the tiles; tilePatternImage
// returns 3 bytes a pixel; writeTilePattern holds the picture as floats (16 B a pixel) and its
// encoded file while writing.
#pragma once

#include "core/render/fragment.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <ostream>
#include <span>
#include <vector>

namespace pushpin::render {

// Tiles of `region` in row-major order, each at most tileWidth × tileHeight (sizes below 1 are
// taken as 1). Together they cover the region exactly once.
std::vector<PixelRect> planTiles(const PixelRect& region, int tileWidth, int tileHeight);

// The screen footprint of one object, as the renderer estimates it from the object's bounds
// without tessellating it.
struct ScreenCost {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // screen box in raster pixels (x right, y down); may reach off screen
    double trianglesPerScanline = 0;       // triangles one scanline crossing the box meets over its whole width
};
inline std::ostream& operator<<(std::ostream& os, const ScreenCost& c) {
    return os << "{[" << c.x0 << "," << c.x1 << "]x[" << c.y0 << "," << c.y1 << "] " << c.trianglesPerScanline
              << "/scanline}";
}

// What the planner and tileCost make of a ScreenCost:
// - The box covers the pixel rows whose [y, y+1) it overlaps with positive length; a box of zero
//   height covers the one row that holds it (floor(y0)). Rows touched only at an end are not
//   covered: a box [2, 4] covers rows 2 and 3.
// - In a tile's columns [tx0, tx1) a box of positive width counts for the fraction of its width
//   inside them, (min(x1, tx1) − max(x0, tx0)) / (x1 − x0) when positive; a box of zero width
//   counts whole in the tile with tx0 <= x0 < tx1 and not at all elsewhere. So the fractions of
//   one box over side-by-side tiles add up to the part of it they hold.
// - An entry is ignored when a corner, its width or its height is not finite, when x1 < x0 or
//   y1 < y0, or when trianglesPerScanline is negative or not finite: one bad bound cannot spread
//   NaN or infinity into the plan.
//
// The cost of a tile: its most expensive pixel row, where a row costs the sum, over the objects
// covering it, of trianglesPerScanline × the object's fraction in the tile's columns. 0 for an
// empty tile or one no object reaches. The contributions are summed in a canonical order, so the
// result is bit-identical for any permutation of `objects`. O(k log k) for k objects reaching the
// tile, whatever the tile's height.
double tileCost(const PixelRect& tile, std::span<const ScreenCost> objects);

struct TilePlan {
    std::vector<PixelRect> tiles;  // row-major by (y0, x0); together they cover the region once
    std::vector<double> cost;      // per tile, its most expensive scanline (tileCost)
    double maxTileCost = 0;        // the limit planned against; +infinity when unlimited
    int minSize = 0, maxSize = 0;  // smallest and largest tile side in pixels (0 without tiles)
    size_t overCost = 0;           // tiles that cannot be split further and still cost more than maxTileCost
};

// The memory-driven tile plan of `region` (DESIGN.md step 5). The region is first cut into its
// four quadrants (the left and top halves take width/2 and height/2 pixels); then every tile that
// costs more than maxTileCost (tileCost; exactly maxTileCost is fine) is halved in width and
// height, again and again. A tile is only halved in a direction where both halves keep at least
// minTileSize pixels (sizes below 1 are taken as 1): a tile that can be halved in one direction
// only splits into two, one that can be halved in neither stays as it is and is counted in
// overCost. The quadrants follow the same rule, so a region narrower than 2 × minTileSize stays
// whole across. maxTileCost <= 0, infinite or NaN means unlimited: the plan is the quadrants.
// Each tile is costed against only the objects that reach it (the parent's list, filtered), so
// planning is about O(objects × depth × log objects + tiles); the floor bounds the tile count by
// area / minTileSize². Deterministic: the same input always gives the same plan. An empty region
// gives an empty plan.
TilePlan planAdaptiveTiles(const PixelRect& region, std::span<const ScreenCost> objects, double maxTileCost,
                           int minTileSize = 16);

// The same splitting applied to given disjoint `tiles` (the fixed grid of a render without a
// cap): each tile that costs more than maxTileCost is halved as planAdaptiveTiles halves, down to
// minTileSize; a tile within the limit stays as it is. The result is ordered by (y0, x0) and
// covers exactly what `tiles` covered. maxTileCost <= 0, infinite or NaN: the tiles as given.
TilePlan splitTiles(std::span<const PixelRect> tiles, std::span<const ScreenCost> objects, double maxTileCost,
                    int minTileSize = 16);

// Index of point (x, y) (each below 2^order) along the Hilbert curve through the 2^order ×
// 2^order grid: consecutive indices are neighbouring cells.
uint64_t hilbertIndex(uint32_t x, uint32_t y, int order);

// `tiles` reordered along the Hilbert curve through their centres (ties by (y0, x0)), so that
// tiles taken one after another, or a thread's run of them, lie close together on screen and
// meet the same objects: under a memory cap, what one tile made is still cached for the next.
// The image does not depend on the order.
std::vector<PixelRect> alongHilbertCurve(std::vector<PixelRect> tiles);

// The --tile-pattern picture of `plan`: width × height pixels of 8-bit RGB, row-major, top row
// first (3 × width × height bytes; empty when either size is below 1). Each tile is filled with a
// heat-ramp colour by cost / maxTileCost (from dark blue at 0 through purple and orange to yellow
// at 1; red above 1); an unlimited plan is coloured by cost relative to its most expensive tile.
// The outermost pixels of each tile are drawn at half brightness, so the subdivision shows.
// Pixels in no tile (outside the planned region) are mid grey (128, 128, 128). Tiles are clipped
// to the picture.
std::vector<uint8_t> tilePatternImage(const TilePlan& plan, int width, int height);

// Writes tilePatternImage(plan, width, height) to `path` in the format its extension names (the
// -of keywords: .png, .tif, .exr, .jpg …; PNG when it has none) through writeImage
// (image_output.h): encoded in memory, written to a temporary name beside `path` and renamed, so
// the file is whole or absent. Missing parent folders are created. Throws pushpin::Error for an
// extension no writer takes, pushpin::IoError when the picture cannot be encoded (a size below 1,
// a name too long), pushpin::OutputError when the folder cannot be created or written (nothing is
// left behind and what `path` held before is unchanged).
void writeTilePattern(const TilePlan& plan, int width, int height, const std::filesystem::path& path);

}  // namespace pushpin::render
