// Tests for core/scene/units.h against the table in reference/ma-format.md ("Units").
#include "core/scene/units.h"

#include <gtest/gtest.h>

#include <numbers>

namespace pushpin::scene {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Units, LinearUnitsInCentimetres) {
    struct Case {
        const char* token;
        double cm;
    } cases[] = {{"mm", 0.1},     {"millimeter", 0.1}, {"cm", 1.0},        {"centimeter", 1.0},
                 {"m", 100.0},    {"meter", 100.0},    {"km", 100000.0},   {"kilometer", 100000.0},
                 {"in", 2.54},    {"inch", 2.54},      {"ft", 30.48},      {"foot", 30.48},
                 {"yd", 91.44},   {"yard", 91.44},     {"mi", 160934.4},   {"mile", 160934.4}};
    for (const Case& c : cases) {
        auto v = linearUnitInCm(c.token);
        ASSERT_TRUE(v.has_value()) << c.token;
        EXPECT_DOUBLE_EQ(*v, c.cm) << c.token;
    }
}

TEST(Units, UnknownLinearUnitIsRejected) {
    EXPECT_FALSE(linearUnitInCm("furlong").has_value());
    EXPECT_FALSE(linearUnitInCm("").has_value());
    EXPECT_FALSE(linearUnitInCm("CM").has_value());
}

TEST(Units, AngleUnitsInRadians) {
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("deg"), kPi / 180.0);
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("degree"), kPi / 180.0);
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("rad"), 1.0);
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("radian"), 1.0);
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("min"), kPi / 10800.0);
    EXPECT_DOUBLE_EQ(*angleUnitInRadians("sec"), kPi / 648000.0);
    // 60 arc-minutes make a degree, 60 arc-seconds an arc-minute.
    EXPECT_NEAR(*angleUnitInRadians("min") * 60.0, *angleUnitInRadians("deg"), 1e-18);
    EXPECT_NEAR(*angleUnitInRadians("sec") * 60.0, *angleUnitInRadians("min"), 1e-18);
    EXPECT_FALSE(angleUnitInRadians("gradian").has_value());
}

TEST(Units, TimeUnitsInFramesPerSecond) {
    struct Case {
        const char* token;
        double fps;
    } cases[] = {{"game", 15},     {"film", 24},  {"pal", 25},    {"ntsc", 30},       {"show", 48},
                 {"palf", 50},     {"ntscf", 60}, {"millisec", 1000}, {"sec", 1},     {"min", 1.0 / 60.0},
                 {"hour", 1.0 / 3600.0}};
    for (const Case& c : cases) {
        auto v = timeUnitFps(c.token);
        ASSERT_TRUE(v.has_value()) << c.token;
        EXPECT_DOUBLE_EQ(*v, c.fps) << c.token;
    }
}

TEST(Units, FpsSuffixedTimeUnits) {
    EXPECT_DOUBLE_EQ(*timeUnitFps("23.976fps"), 23.976);
    EXPECT_DOUBLE_EQ(*timeUnitFps("120fps"), 120.0);
    EXPECT_FALSE(timeUnitFps("fps").has_value());
    EXPECT_FALSE(timeUnitFps("0fps").has_value());
    EXPECT_FALSE(timeUnitFps("-24fps").has_value());
    EXPECT_FALSE(timeUnitFps("abcfps").has_value());
    EXPECT_FALSE(timeUnitFps("24 fps").has_value());
    EXPECT_FALSE(timeUnitFps("decade").has_value());
}

TEST(Units, DefaultUnitsAreCentimetreDegreeFilm) {
    const Units u;
    EXPECT_DOUBLE_EQ(u.cmPerLinearUnit, 1.0);
    EXPECT_DOUBLE_EQ(u.radiansPerAngleUnit, kPi / 180.0);
    EXPECT_DOUBLE_EQ(u.framesPerSecond, 24.0);
}

TEST(Units, ToInternalScalesByKind) {
    Units u;
    u.cmPerLinearUnit = 100.0;  // metres
    u.radiansPerAngleUnit = 1.0;
    u.framesPerSecond = 30.0;
    EXPECT_DOUBLE_EQ(toInternal(UnitKind::Distance, u), 100.0);
    EXPECT_DOUBLE_EQ(toInternal(UnitKind::Angle, u), 1.0);
    EXPECT_DOUBLE_EQ(toInternal(UnitKind::None, u), 1.0);
    // Times stay in frames of the scene's own time unit.
    EXPECT_DOUBLE_EQ(toInternal(UnitKind::Time, u), 1.0);
    EXPECT_DOUBLE_EQ(toInternal(UnitKind::Angle, Units{}), kPi / 180.0);
}

}  // namespace
}  // namespace pushpin::scene
