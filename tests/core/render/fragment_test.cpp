// Tests for core/render/fragment.h: the sub-sample patterns of the edge anti-aliasing levels.
#include "core/render/fragment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <set>

namespace pushpin::render {
namespace {

int rowOf(int b) { return b / kSubsampleGrid; }
int colOf(int b) { return b % kSubsampleGrid; }
// Quadrant 0..3 of a sub-sample (left/right, top/bottom half of the pixel).
int quadrantOf(int b) { return (rowOf(b) >= 4 ? 2 : 0) + (colOf(b) >= 4 ? 1 : 0); }

TEST(SubsamplePattern, CountsMatchTheLevels) {
    const int expected[4] = {64, 32, 8, 2};  // Highest, High, Medium, Low
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        EXPECT_EQ(p.count, expected[eaa]) << "eaa " << eaa;
        EXPECT_EQ(std::popcount(p.active), expected[eaa]) << "eaa " << eaa;
        EXPECT_EQ(p.edgeAntiAliasing, eaa);
    }
}

TEST(SubsamplePattern, ClampsOutOfRangeLevels) {
    EXPECT_EQ(SubsamplePattern::forEdgeAntiAliasing(-5).count, 64);
    EXPECT_EQ(SubsamplePattern::forEdgeAntiAliasing(-5).edgeAntiAliasing, 0);
    EXPECT_EQ(SubsamplePattern::forEdgeAntiAliasing(7).count, 2);
    EXPECT_EQ(SubsamplePattern::forEdgeAntiAliasing(7).edgeAntiAliasing, 3);
}

TEST(SubsamplePattern, IsDeterministic) {
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern a = SubsamplePattern::forEdgeAntiAliasing(eaa);
        const SubsamplePattern b = SubsamplePattern::forEdgeAntiAliasing(eaa);
        EXPECT_EQ(a.active, b.active);
        EXPECT_EQ(a.order, b.order);
    }
}

TEST(SubsamplePattern, OrderIsAPermutationOfTheActiveBits) {
    for (int eaa = 0; eaa <= 3; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        std::set<int> seen;
        uint64_t fromOrder = 0;
        for (int i = 0; i < p.count; ++i) {
            const int b = p.order[i];
            ASSERT_LT(b, kSubsampleCount) << "eaa " << eaa;
            EXPECT_TRUE((p.active >> b) & 1) << "eaa " << eaa << " bit " << b;
            seen.insert(b);
            fromOrder |= uint64_t(1) << b;
        }
        EXPECT_EQ(int(seen.size()), p.count) << "eaa " << eaa;
        EXPECT_EQ(fromOrder, p.active) << "eaa " << eaa;
    }
}

TEST(SubsamplePattern, MediumAndLowUseDistinctRowsAndColumns) {
    for (int eaa : {2, 3}) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        std::set<int> rows, cols;
        for (int i = 0; i < p.count; ++i) {
            rows.insert(rowOf(p.order[i]));
            cols.insert(colOf(p.order[i]));
        }
        EXPECT_EQ(int(rows.size()), p.count) << "eaa " << eaa;
        EXPECT_EQ(int(cols.size()), p.count) << "eaa " << eaa;
    }
}

TEST(SubsamplePattern, HighIsACheckerboard) {
    const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(1);
    for (int b = 0; b < kSubsampleCount; ++b) {
        const bool active = (p.active >> b) & 1;
        const bool neighbourActive = colOf(b) + 1 < kSubsampleGrid && ((p.active >> (b + 1)) & 1);
        if (active) {
            EXPECT_FALSE(neighbourActive) << "bit " << b;
        }
    }
    // Every row holds four of them.
    for (int row = 0; row < kSubsampleGrid; ++row) {
        EXPECT_EQ(std::popcount((p.active >> (row * kSubsampleGrid)) & 0xffu), 4) << "row " << row;
    }
}

TEST(SubsamplePattern, PrefixesAreSpreadOverThePixel) {
    for (int eaa = 0; eaa <= 2; ++eaa) {
        const SubsamplePattern p = SubsamplePattern::forEdgeAntiAliasing(eaa);
        // The first two sit in opposite quadrants, the first four in four different quadrants.
        EXPECT_EQ(quadrantOf(p.order[0]) + quadrantOf(p.order[1]), 3) << "eaa " << eaa;
        std::set<int> quadrants;
        for (int i = 0; i < 4; ++i) quadrants.insert(quadrantOf(p.order[i]));
        EXPECT_EQ(quadrants.size(), 4u) << "eaa " << eaa;
        // The mean of the first 4 is close to the pixel centre.
        double u = 0, v = 0;
        for (int i = 0; i < 4; ++i) {
            u += (colOf(p.order[i]) + 0.5) / kSubsampleGrid;
            v += (rowOf(p.order[i]) + 0.5) / kSubsampleGrid;
        }
        EXPECT_NEAR(u / 4, 0.5, 0.13) << "eaa " << eaa;
        EXPECT_NEAR(v / 4, 0.5, 0.13) << "eaa " << eaa;
    }
    // Low: its two points lie in opposite quadrants, symmetric about the pixel centre.
    const SubsamplePattern low = SubsamplePattern::forEdgeAntiAliasing(3);
    EXPECT_EQ(quadrantOf(low.order[0]) + quadrantOf(low.order[1]), 3);
    EXPECT_EQ(rowOf(low.order[0]) + rowOf(low.order[1]), kSubsampleGrid - 1);
    EXPECT_EQ(colOf(low.order[0]) + colOf(low.order[1]), kSubsampleGrid - 1);
}

TEST(SubsamplePattern, HighestOrderPrefixOf32IsTheHighPattern) {
    const SubsamplePattern highest = SubsamplePattern::forEdgeAntiAliasing(0);
    const SubsamplePattern high = SubsamplePattern::forEdgeAntiAliasing(1);
    uint64_t prefix = 0;
    for (int i = 0; i < 32; ++i) prefix |= uint64_t(1) << highest.order[i];
    EXPECT_EQ(prefix, high.active);
}

TEST(Fragment, DepthAtIsThePlane) {
    Fragment f;
    f.z0 = 2.0f;
    f.dzdu = 0.5f;
    f.dzdv = -0.25f;
    EXPECT_FLOAT_EQ(f.depthAt(0.0f, 0.0f), 2.0f);
    EXPECT_FLOAT_EQ(f.depthAt(1.0f, 0.0f), 2.5f);
    EXPECT_FLOAT_EQ(f.depthAt(0.5f, 1.0f), 2.0f);
}

TEST(ObjectTopology, FindsNeighboursInWholePiecesAndInPiecesThatKeepSomeTriangles) {
    // Object of 3 triangles in one array.
    const uint32_t whole[9] = {1, kNoTriangle, 2, 0, 2, kNoTriangle, 0 | kHardEdgeBit, 1, kNoTriangle};
    const ObjectTopology one{whole, 3, nullptr, 0};
    EXPECT_EQ(one.neighborsOf(1), whole + 3);
    EXPECT_EQ(one.neighborsOf(3), nullptr);
    // Pieces [0, 10) whole, [10, 20) keeping triangles 12, 15 and 19, [20, 30) not at hand.
    uint32_t first[30], kept[9];
    for (uint32_t i = 0; i < 30; ++i) first[i] = 100 + i;
    for (uint32_t i = 0; i < 9; ++i) kept[i] = 200 + i;
    const uint32_t ids[3] = {2, 5, 9};
    const TopologyPiece pieces[3] = {{10, first, nullptr}, {3, kept, ids}, {10, nullptr, nullptr}};
    const geom::SlotRun runs[3] = {{0, 0, 0}, {10, 1, 0}, {20, 2, 0}};
    const ObjectTopology split{nullptr, 0, pieces, 3, runs, 3};
    EXPECT_EQ(split.neighborsOf(0), first);
    EXPECT_EQ(split.neighborsOf(9), first + 27);
    EXPECT_EQ(split.neighborsOf(12), kept);
    EXPECT_EQ(split.neighborsOf(15), kept + 3);
    EXPECT_EQ(split.neighborsOf(19), kept + 6);
    for (const uint32_t absent : {10u, 11u, 13u, 18u, 20u, 25u, 31u}) EXPECT_EQ(split.neighborsOf(absent), nullptr) << absent;
    // Pieces whose triangle ids take several runs: piece 0 holds ids [0, 4) and [8, 12), piece 1
    // ids [4, 8) keeping its triangles 1 and 3 (ids 5 and 7).
    const uint32_t keptIds[2] = {1, 3};
    const TopologyPiece interleaved[2] = {{8, first, nullptr}, {2, kept, keptIds}};
    const geom::SlotRun interleavedRuns[3] = {{0, 0, 0}, {4, 1, 0}, {8, 0, 4}};
    const ObjectTopology runsOfIds{nullptr, 0, interleaved, 2, interleavedRuns, 3};
    EXPECT_EQ(runsOfIds.neighborsOf(3), first + 9);
    EXPECT_EQ(runsOfIds.neighborsOf(8), first + 12);
    EXPECT_EQ(runsOfIds.neighborsOf(11), first + 21);
    EXPECT_EQ(runsOfIds.neighborsOf(5), kept);
    EXPECT_EQ(runsOfIds.neighborsOf(7), kept + 3);
    for (const uint32_t absent : {4u, 6u, 12u, 40u}) EXPECT_EQ(runsOfIds.neighborsOf(absent), nullptr) << absent;
}

}  // namespace
}  // namespace pushpin::render
