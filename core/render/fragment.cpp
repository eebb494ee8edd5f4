// core/render/fragment.cpp: the sub-sample patterns of the edge anti-aliasing levels.
#include "core/render/fragment.h"

#include <algorithm>
#include <bit>

namespace pushpin::render {

namespace {

// Rank of cell (row, col) in the 8×8 ordered-dither (Bayer) matrix, shifted by two cells so that
// its lattices are centred in the pixel. Sorting cells by this rank gives a progressive order: the
// first 2^k cells always form a regular lattice over the pixel, so every prefix is spread out; the
// first 32 ranks are exactly the cells with (row + col) even.
int bayerRank(int row, int col) {
    row = (row + 2) % kSubsampleGrid;
    col = (col + 2) % kSubsampleGrid;
    int rank = 0;
    for (int k = 0; k < 3; ++k) {
        const int diff = ((row ^ col) >> k) & 1;
        const int r = (row >> k) & 1;
        rank = (rank << 2) | (diff << 1) | r;
    }
    return rank;
}

int bitOf(int row, int col) { return row * kSubsampleGrid + col; }

SubsamplePattern makePattern(int eaa) {
    SubsamplePattern p;
    p.edgeAntiAliasing = eaa;
    switch (eaa) {
    case 3:  // Low: two points, mirror images through the pixel centre, in distinct rows and columns
        p.active = (uint64_t(1) << bitOf(2, 1)) | (uint64_t(1) << bitOf(5, 6));
        break;
    case 2:  // Medium: eight rooks on the rank-1 lattice col = (3·row + 1) mod 8
        for (int row = 0; row < kSubsampleGrid; ++row) {
            p.active |= uint64_t(1) << bitOf(row, (3 * row + 1) % kSubsampleGrid);
        }
        break;
    case 1:  // High: the checkerboard half, (row + col) even
        for (int row = 0; row < kSubsampleGrid; ++row) {
            for (int col = 0; col < kSubsampleGrid; ++col) {
                if (((row + col) & 1) == 0) p.active |= uint64_t(1) << bitOf(row, col);
            }
        }
        break;
    default:  // Highest: every sub-sample
        p.active = ~uint64_t(0);
        break;
    }
    p.count = std::popcount(p.active);
    int n = 0;
    for (int b = 0; b < kSubsampleCount; ++b) {
        if ((p.active >> b) & 1) p.order[n++] = uint8_t(b);
    }
    std::sort(p.order.begin(), p.order.begin() + n, [](uint8_t a, uint8_t b) {
        return bayerRank(a / kSubsampleGrid, a % kSubsampleGrid) <
               bayerRank(b / kSubsampleGrid, b % kSubsampleGrid);
    });
    return p;
}

}  // namespace

SubsamplePattern SubsamplePattern::forEdgeAntiAliasing(int edgeAntiAliasing) {
    static const std::array<SubsamplePattern, 4> patterns = {makePattern(0), makePattern(1),
                                                             makePattern(2), makePattern(3)};
    return patterns[std::clamp(edgeAntiAliasing, 0, 3)];
}

}  // namespace pushpin::render
