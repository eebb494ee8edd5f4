// Tests for core/scene/components.h.
#include "core/scene/components.h"

#include <gtest/gtest.h>

namespace pushpin::scene {
namespace {

TEST(Components, ParsesKindsAndRanges) {
    std::optional<ComponentRange> r = parseComponent("f[0:5]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Face);
    EXPECT_EQ(r->range.first, 0);
    EXPECT_EQ(r->range.last, 5);
    EXPECT_FALSE(r->second);

    r = parseComponent("vtx[3]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Vertex);
    EXPECT_EQ(r->range.first, 3);
    EXPECT_EQ(r->range.last, 3);

    r = parseComponent(" e[*] ");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Edge);
    EXPECT_TRUE(r->range.all());

    r = parseComponent("map[1:4]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Uv);

    r = parseComponent("vtxFace[2][0:1]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::VertexFace);
    ASSERT_TRUE(r->second);
    EXPECT_EQ(r->second->last, 1);

    r = parseComponent("|pCube1|pCubeShape1.f[7]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Face);
    EXPECT_EQ(r->range.first, 7);

    r = parseComponent("cv[1][2]");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->kind, ComponentKind::Other);
    EXPECT_EQ(r->name, "cv");
}

TEST(Components, RejectsMalformedInputWithAMessage) {
    for (const char* bad : {"", "f", "f[", "f[1", "f[]", "f[a]", "f[-1]", "f[5:2]", "f[1:]", "[3]", "f[1]x",
                            "f[1][2][3]", "f[99999999999]", "vtxFace[2]", "f 1", "f[1:2:3]"}) {
        std::string error;
        EXPECT_FALSE(parseComponent(bad, &error)) << bad;
        EXPECT_FALSE(error.empty()) << bad;
    }
    EXPECT_FALSE(parseComponent("f[", nullptr));  // no error sink is fine too
}

TEST(Components, FaceMaskCoversRangesAndReportsProblems) {
    std::string error;
    std::vector<bool> mask = faceMask(ComponentList{{"f[0:1]", "f[4]"}}, 6, &error);
    EXPECT_EQ(mask, (std::vector<bool>{true, true, false, false, true, false}));
    EXPECT_TRUE(error.empty()) << error;

    mask = faceMask(ComponentList{{"f[*]"}}, 3, &error);
    EXPECT_EQ(mask, (std::vector<bool>{true, true, true}));

    mask = faceMask(ComponentList{{"f[2:9]", "vtx[0]", "garbage"}}, 4, &error);
    EXPECT_EQ(mask, (std::vector<bool>{false, false, true, true}));
    EXPECT_NE(error.find("past the 4"), std::string::npos) << error;
    EXPECT_NE(error.find("not a face"), std::string::npos) << error;
    EXPECT_NE(error.find("garbage"), std::string::npos) << error;

    mask = faceMask(ComponentList{{"f[10:12]"}}, 0, &error);
    EXPECT_TRUE(mask.empty());
    EXPECT_FALSE(error.empty());

    mask = faceMask(ComponentList{}, 2, nullptr);
    EXPECT_EQ(mask, (std::vector<bool>{false, false}));
}

TEST(Components, ComponentMaskSelectsOneKind) {
    const ParsedComponents parsed = parseComponents(ComponentList{{"vtx[1:2]", "f[0]", "e[3]", "vtx[*]x"}});
    EXPECT_EQ(parsed.ranges.size(), 3u);
    ASSERT_EQ(parsed.errors.size(), 1u);
    EXPECT_NE(parsed.errors[0].find("vtx[*]x"), std::string::npos);
    EXPECT_EQ(componentMask(parsed.ranges, ComponentKind::Vertex, 4), (std::vector<bool>{false, true, true, false}));
    EXPECT_EQ(componentMask(parsed.ranges, ComponentKind::Edge, 4), (std::vector<bool>{false, false, false, true}));
    EXPECT_EQ(componentMask(parsed.ranges, ComponentKind::Uv, 2), (std::vector<bool>{false, false}));
}

}  // namespace
}  // namespace pushpin::scene
