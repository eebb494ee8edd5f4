#include "core/render/tile_plan.h"

#include "core/render/image_output.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace pushpin::render {

std::vector<PixelRect> planTiles(const PixelRect& region, int tileWidth, int tileHeight) {
    std::vector<PixelRect> tiles;
    if (region.empty()) return tiles;
    tileWidth = std::max(tileWidth, 1);
    tileHeight = std::max(tileHeight, 1);
    for (int y = region.y0; y < region.y1; y += tileHeight)
        for (int x = region.x0; x < region.x1; x += tileWidth)
            tiles.push_back({x, y, std::min(x + tileWidth, region.x1), std::min(y + tileHeight, region.y1)});
    return tiles;
}

namespace {

// A usable ScreenCost, with the pixel rows it covers worked out once (see tile_plan.h).
struct Footprint {
    double x0, x1, width;    // columns; width = x1 − x0, 0 for a zero-width box
    double row0, row1;       // first and last covered row (integers held as doubles: boxes may
                             // reach far past the int range)
    double trianglesPerScanline;
};

// The footprints of the entries that can contribute; bad entries (tile_plan.h) and entries of zero
// cost are left out. Their indices into the result are what the planner passes down, as 32 bits
// to halve the lists: 2^32 objects would take 160 GB of ScreenCost before planning began.
std::vector<Footprint> footprints(std::span<const ScreenCost> objects) {
    std::vector<Footprint> out;
    out.reserve(objects.size());
    for (const ScreenCost& c : objects) {
        const double width = c.x1 - c.x0, height = c.y1 - c.y0;
        if (!std::isfinite(c.x0) || !std::isfinite(c.y0) || !std::isfinite(c.x1) || !std::isfinite(c.y1) ||
            !std::isfinite(width) || !std::isfinite(height) || width < 0 || height < 0)
            continue;
        if (!std::isfinite(c.trianglesPerScanline) || !(c.trianglesPerScanline > 0)) continue;
        // Rows [y, y+1) overlapping [y0, y1] with positive length are floor(y0) … ceil(y1) − 1; when
        // y1 == y0 that range is empty and the box's own row floor(y0) is taken instead.
        const double row0 = std::floor(c.y0);
        const double row1 = std::max(row0, std::ceil(c.y1) - 1.0);
        out.push_back({c.x0, c.x1, width, row0, row1, c.trianglesPerScanline});
    }
    return out;
}

bool reachesRows(const Footprint& f, const PixelRect& tile) {
    return f.row1 >= double(tile.y0) && f.row0 <= double(tile.y1) - 1.0;
}

// The fraction of the box inside the tile's columns, 0 when none of it is.
double columnFraction(const Footprint& f, const PixelRect& tile) {
    const double tx0 = tile.x0, tx1 = tile.x1;
    if (f.width == 0) return tx0 <= f.x0 && f.x0 < tx1 ? 1.0 : 0.0;
    const double inside = std::min(f.x1, tx1) - std::max(f.x0, tx0);
    if (!(inside > 0)) return 0.0;
    // A box wholly inside gives inside == width exactly, so its fraction is exactly 1.
    return inside / f.width;
}

bool reaches(const Footprint& f, const PixelRect& tile) {
    return reachesRows(f, tile) && columnFraction(f, tile) > 0;
}

// One change of the running scanline cost: an object starts (adds) or ends (subtracts) at `row`.
struct Event {
    int row;
    int starts;   // 0 ends, 1 starts: at one row the ends are applied first
    double cost;  // the object's contribution to each row it covers in this tile, > 0
    bool operator<(const Event& o) const {
        if (row != o.row) return row < o.row;
        if (starts != o.starts) return starts < o.starts;
        return cost < o.cost;
    }
};

// tileCost of `tile` over footprints[ids]. A sweep over the rows where the running sum changes,
// not an array over every row: the work is O(k log k) for k objects, even for a tile millions of
// pixels tall. The events are sorted by (row, kind, cost) before they are summed; two events that
// compare equal are the same numbers, so the sequence of additions, and with it every rounding,
// is the same however the objects were ordered.
double costOf(const PixelRect& tile, const std::vector<Footprint>& all, const std::vector<uint32_t>& ids,
              std::vector<Event>& events) {
    if (tile.empty()) return 0.0;
    events.clear();
    const double lastRow = double(tile.y1) - 1.0;
    for (uint32_t i : ids) {
        const Footprint& f = all[i];
        if (!reachesRows(f, tile)) continue;
        const double c = f.trianglesPerScanline * columnFraction(f, tile);
        if (!(c > 0)) continue;
        // Clamped to the tile's rows while still doubles, so the conversions stay in range.
        const int first = static_cast<int>(std::max(f.row0, double(tile.y0)));
        const int last = static_cast<int>(std::min(f.row1, lastRow));
        events.push_back({first, 1, c});
        if (last < tile.y1 - 1) events.push_back({last + 1, 0, c});
    }
    std::sort(events.begin(), events.end());
    double sum = 0.0, most = 0.0;
    long active = 0;
    for (size_t e = 0; e < events.size();) {
        const int row = events[e].row;
        for (; e < events.size() && events[e].row == row; ++e) {
            if (events[e].starts) {
                sum += events[e].cost;
                ++active;
            } else {
                sum -= events[e].cost;
                --active;
            }
        }
        // Rows no object covers cost exactly 0, not the rounding left over from add-then-subtract.
        if (active == 0) sum = 0.0;
        most = std::max(most, sum);
    }
    return most;
}

// Whether a side of `length` pixels can be halved with both halves at least `minSize`. The first
// half is the shorter one (length / 2), so that is the half to check.
bool halvable(int length, int minSize) { return length / 2 >= minSize; }

// `tile` halved across (when splitX) and down (when splitY): 1, 2 or 4 rectangles. The left and
// top parts take width / 2 and height / 2 pixels.
int halves(const PixelRect& tile, bool splitX, bool splitY, std::array<PixelRect, 4>& out) {
    const int xm = splitX ? tile.x0 + tile.width() / 2 : tile.x1;
    const int ym = splitY ? tile.y0 + tile.height() / 2 : tile.y1;
    int n = 0;
    out[n++] = {tile.x0, tile.y0, xm, ym};
    if (splitX) out[n++] = {xm, tile.y0, tile.x1, ym};
    if (splitY) out[n++] = {tile.x0, ym, xm, tile.y1};
    if (splitX && splitY) out[n++] = {xm, ym, tile.x1, tile.y1};
    return n;
}

struct Planner {
    const std::vector<Footprint>& all;
    double maxTileCost;  // +infinity when unlimited
    int minSize;
    std::vector<Event> events;  // scratch for costOf, reused by every tile
    std::vector<std::pair<PixelRect, double>> placed;
    size_t overCost = 0;

    // Costs `tile` against `ids` (the footprints that reach it) and either keeps it or splits it.
    // Each child gets the sublist that reaches it, so a dense corner does not slow the rest of
    // the image. Depth is at most log2 of the region's side: the recursion stays shallow.
    void plan(const PixelRect& tile, const std::vector<uint32_t>& ids) {
        const double cost = costOf(tile, all, ids, events);
        const bool over = cost > maxTileCost;
        const bool splitX = over && halvable(tile.width(), minSize);
        const bool splitY = over && halvable(tile.height(), minSize);
        if (!splitX && !splitY) {
            placed.push_back({tile, cost});
            if (over) ++overCost;
            return;
        }
        std::array<PixelRect, 4> children;
        const int n = halves(tile, splitX, splitY, children);
        std::vector<uint32_t> childIds;
        for (int c = 0; c < n; ++c) {
            childIds.clear();
            for (uint32_t i : ids)
                if (reaches(all[i], children[c])) childIds.push_back(i);
            plan(children[c], childIds);
        }
    }
};

// The planner's tiles into `plan`, ordered by (y0, x0) (tiles are disjoint, so that orders them
// completely), with their costs, sizes and the count over the limit.
void takePlaced(Planner& planner, TilePlan& plan) {
    std::sort(planner.placed.begin(), planner.placed.end(), [](const auto& a, const auto& b) {
        return a.first.y0 != b.first.y0 ? a.first.y0 < b.first.y0 : a.first.x0 < b.first.x0;
    });
    plan.tiles.reserve(planner.placed.size());
    plan.cost.reserve(planner.placed.size());
    plan.minSize = planner.placed.empty() ? 0 : std::numeric_limits<int>::max();
    for (const auto& [tile, cost] : planner.placed) {
        plan.tiles.push_back(tile);
        plan.cost.push_back(cost);
        plan.minSize = std::min({plan.minSize, tile.width(), tile.height()});
        plan.maxSize = std::max({plan.maxSize, tile.width(), tile.height()});
    }
    plan.overCost = planner.overCost;
}

// Five key colours of matplotlib's "plasma" map (perceptually uniform, dark blue to yellow),
// interpolated linearly; tiles over their limit are red, outside the map.
std::array<uint8_t, 3> heat(double t) {
    static constexpr std::array<std::array<double, 3>, 5> kKeys = {{
        {13, 8, 135},    // 0: dark blue
        {126, 3, 168},   // 0.25: purple
        {204, 71, 120},  // 0.5: pink
        {248, 149, 64},  // 0.75: orange
        {240, 249, 33},  // 1: yellow
    }};
    if (t > 1.0) return {220, 20, 20};
    if (!(t > 0.0)) t = 0.0;  // NaN counts as no cost
    const double s = t * 4.0;
    const int k = std::min(static_cast<int>(s), 3);
    const double f = s - k;
    std::array<uint8_t, 3> rgb{};
    for (int c = 0; c < 3; ++c)
        rgb[c] = static_cast<uint8_t>(std::lround(kKeys[k][c] + (kKeys[k + 1][c] - kKeys[k][c]) * f));
    return rgb;
}

}  // namespace

double tileCost(const PixelRect& tile, std::span<const ScreenCost> objects) {
    const std::vector<Footprint> all = footprints(objects);
    std::vector<uint32_t> ids(all.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<uint32_t>(i);
    std::vector<Event> events;
    return costOf(tile, all, ids, events);
}

TilePlan planAdaptiveTiles(const PixelRect& region, std::span<const ScreenCost> objects, double maxTileCost,
                           int minTileSize) {
    TilePlan result;
    const bool limited = std::isfinite(maxTileCost) && maxTileCost > 0;
    result.maxTileCost = limited ? maxTileCost : std::numeric_limits<double>::infinity();
    if (region.empty()) return result;
    const int minSize = std::max(minTileSize, 1);

    const std::vector<Footprint> all = footprints(objects);
    Planner planner{all, result.maxTileCost, minSize, {}, {}, 0};
    std::array<PixelRect, 4> quadrants;
    const int n = halves(region, halvable(region.width(), minSize), halvable(region.height(), minSize), quadrants);
    std::vector<uint32_t> ids;
    ids.reserve(all.size());
    for (int q = 0; q < n; ++q) {
        ids.clear();
        for (size_t i = 0; i < all.size(); ++i)
            if (reaches(all[i], quadrants[q])) ids.push_back(static_cast<uint32_t>(i));
        planner.plan(quadrants[q], ids);
    }

    takePlaced(planner, result);
    return result;
}

TilePlan splitTiles(std::span<const PixelRect> tiles, std::span<const ScreenCost> objects, double maxTileCost,
                    int minTileSize) {
    TilePlan result;
    const bool limited = std::isfinite(maxTileCost) && maxTileCost > 0;
    result.maxTileCost = limited ? maxTileCost : std::numeric_limits<double>::infinity();
    const std::vector<Footprint> all = footprints(objects);
    Planner planner{all, result.maxTileCost, std::max(minTileSize, 1), {}, {}, 0};
    std::vector<uint32_t> ids;
    ids.reserve(all.size());
    for (const PixelRect& tile : tiles) {
        if (tile.empty()) continue;
        ids.clear();
        for (size_t i = 0; i < all.size(); ++i)
            if (reaches(all[i], tile)) ids.push_back(static_cast<uint32_t>(i));
        planner.plan(tile, ids);
    }
    takePlaced(planner, result);
    return result;
}

std::vector<uint8_t> tilePatternImage(const TilePlan& plan, int width, int height) {
    if (width < 1 || height < 1) return {};
    std::vector<uint8_t> image(size_t(width) * size_t(height) * 3, 128);

    // The scale: the plan's limit, or for an unlimited plan its most expensive tile.
    double scale = plan.maxTileCost;
    if (!std::isfinite(scale) || !(scale > 0)) {
        scale = 0.0;
        for (double c : plan.cost)
            if (std::isfinite(c)) scale = std::max(scale, c);
    }
    for (size_t i = 0; i < plan.tiles.size(); ++i) {
        const PixelRect& t = plan.tiles[i];
        const double cost = i < plan.cost.size() ? plan.cost[i] : 0.0;
        const double level = scale > 0 ? cost / scale : 0.0;
        const std::array<uint8_t, 3> fill = heat(level);
        const std::array<uint8_t, 3> edge = {uint8_t(fill[0] / 2), uint8_t(fill[1] / 2), uint8_t(fill[2] / 2)};
        const int x0 = std::max(t.x0, 0), x1 = std::min(t.x1, width);
        const int y0 = std::max(t.y0, 0), y1 = std::min(t.y1, height);
        for (int y = y0; y < y1; ++y) {
            const bool edgeRow = y == t.y0 || y == t.y1 - 1;
            uint8_t* row = image.data() + size_t(y) * size_t(width) * 3;
            for (int x = x0; x < x1; ++x) {
                const std::array<uint8_t, 3>& rgb = edgeRow || x == t.x0 || x == t.x1 - 1 ? edge : fill;
                std::copy(rgb.begin(), rgb.end(), row + size_t(x) * 3);
            }
        }
    }
    return image;
}

void writeTilePattern(const TilePlan& plan, int width, int height, const std::filesystem::path& path) {
    std::string extension = path.extension().string();
    if (!extension.empty()) extension.erase(0, 1);
    const OutputFormat format = outputFormatFromName(extension.empty() ? "png" : extension);

    // The bytes as a framebuffer of exact k/255 values: with gamma 1, no dither and no alpha,
    // writeImage stores each byte unchanged in 8-bit formats.
    Framebuffer frame;
    frame.resize(width, height, false);
    const std::vector<uint8_t> rgb = tilePatternImage(plan, width, height);
    for (size_t p = 0; p < rgb.size() / 3; ++p) {
        for (int c = 0; c < 3; ++c) frame.rgba[p * 4 + c] = float(rgb[p * 3 + c]) / 255.0f;
        frame.rgba[p * 4 + 3] = 1.0f;
    }
    RenderSettings settings;
    settings.gammaCorrection = 1.0;
    settings.clipFinalShadedColor = true;
    settings.jitterFinalColor = false;
    settings.mask = false;
    writeImage(frame, path, format, settings, false);
}

uint64_t hilbertIndex(uint32_t x, uint32_t y, int order) {
    uint64_t d = 0;
    for (uint64_t s = order > 0 ? uint64_t(1) << (order - 1) : 0; s > 0; s /= 2) {
        const uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
        d += s * s * ((3 * rx) ^ ry);
        // Rotate the quadrant so that the curve's sub-curve starts and ends where it joins.
        if (ry == 0) {
            if (rx == 1) {
                x = uint32_t(s - 1) - (x & uint32_t(s - 1));
                y = uint32_t(s - 1) - (y & uint32_t(s - 1));
            }
            std::swap(x, y);
        }
        x &= uint32_t(s - 1);
        y &= uint32_t(s - 1);
    }
    return d;
}

std::vector<PixelRect> alongHilbertCurve(std::vector<PixelRect> tiles) {
    if (tiles.size() < 2) return tiles;
    int x0 = tiles[0].x0, y0 = tiles[0].y0, x1 = tiles[0].x1, y1 = tiles[0].y1;
    for (const PixelRect& t : tiles) {
        x0 = std::min(x0, t.x0), y0 = std::min(y0, t.y0);
        x1 = std::max(x1, t.x1), y1 = std::max(y1, t.y1);
    }
    // Centres on the pixel grid, doubled so that they are whole.
    const uint64_t extent = 2 * uint64_t(std::max(x1 - x0, y1 - y0)) + 1;
    int order = 0;
    while ((uint64_t(1) << order) < extent) ++order;
    std::vector<std::pair<uint64_t, PixelRect>> keyed;
    keyed.reserve(tiles.size());
    for (const PixelRect& t : tiles) {
        const uint32_t cx = uint32_t(int64_t(t.x0) + t.x1 - 2 * int64_t(x0));
        const uint32_t cy = uint32_t(int64_t(t.y0) + t.y1 - 2 * int64_t(y0));
        keyed.push_back({hilbertIndex(cx, cy, order), t});
    }
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first < b.first;
        return a.second.y0 != b.second.y0 ? a.second.y0 < b.second.y0 : a.second.x0 < b.second.x0;
    });
    for (size_t i = 0; i < tiles.size(); ++i) tiles[i] = keyed[i].second;
    return tiles;
}

}  // namespace pushpin::render
