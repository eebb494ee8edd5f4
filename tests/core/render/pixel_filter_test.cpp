// Tests for core/render/pixel_filter.h: the filter each setting gives (types, clamped widths,
// reach), the kernels against their closed forms, the 3×3 cubic B-spline summing to one inside
// the image and to the in-image part at a corner, and shares that hand out a surface exactly once.
#include "core/render/pixel_filter.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pushpin::render {
namespace {

RenderSettings filterSettings(int type, double widthX = 2.2, double widthY = 2.2) {
    RenderSettings s;
    s.useMultiPixelFilter = true;
    s.pixelFilterType = type;
    s.pixelFilterWidthX = widthX;
    s.pixelFilterWidthY = widthY;
    return s;
}

TEST(PixelFilter, WithoutTheMultiPixelFilterEachPixelKeepsItsSurfaces) {
    RenderSettings s;
    s.useMultiPixelFilter = false;
    s.pixelFilterType = 6;
    const PixelFilter f = makePixelFilter(s);
    EXPECT_EQ(f.type, -1);
    EXPECT_EQ(f.reach, 0);
    EXPECT_EQ(f.weight(0.0, 0.0), 0.0);
    EXPECT_EQ(filterNorm(f, PixelRect{0, 0, 8, 8}, 3, 3, 0.5f, 0.5f), 0.0);
    // A surface with no norm stays whole in its own pixel.
    EXPECT_EQ(filterShare(f, 0.0, 3, 3, 0.5f, 0.5f, 3, 3), 1.0);
    EXPECT_EQ(filterShare(f, 0.0, 3, 3, 0.5f, 0.5f, 4, 3), 0.0);
}

TEST(PixelFilter, WidthsAreClampedAndUnknownTypesAreTheTriangle) {
    PixelFilter f = makePixelFilter(filterSettings(0, 0.2, 9.0));
    EXPECT_EQ(f.type, 0);
    EXPECT_DOUBLE_EQ(f.radiusX, 0.5);
    EXPECT_DOUBLE_EQ(f.radiusY, 1.5);
    EXPECT_EQ(f.reach, 2);  // ceil(1.5 + 0.5)
    f = makePixelFilter(filterSettings(3));
    EXPECT_EQ(f.type, 2);
    EXPECT_DOUBLE_EQ(f.radiusX, 1.1);
    EXPECT_EQ(f.reach, 2);  // ceil(1.1 + 0.5)
    f = makePixelFilter(filterSettings(6, 3.0, 3.0));  // the 3×3 B-spline ignores the widths
    EXPECT_EQ(f.reach, 1);
    EXPECT_DOUBLE_EQ(f.radiusX, 2.0);
}

TEST(PixelFilter, KernelsMatchTheirClosedForms) {
    const PixelFilter box = makePixelFilter(filterSettings(0, 2.0, 2.0));
    EXPECT_EQ(box.weight(0.99, -1.0), 1.0);
    EXPECT_EQ(box.weight(1.01, 0.0), 0.0);
    const PixelFilter tri = makePixelFilter(filterSettings(2, 2.0, 2.0));  // radius 1
    EXPECT_DOUBLE_EQ(tri.weight(0.25, 0.5), 0.75 * 0.5);
    EXPECT_EQ(tri.weight(1.0, 0.0), 0.0);
    const PixelFilter gauss = makePixelFilter(filterSettings(4, 2.0, 2.0));  // sigma 0.5, zero at 1
    const double edge = std::exp(-1.0 / 0.5);
    EXPECT_NEAR(gauss.weight(0.5, 0.0), (std::exp(-0.25 / 0.5) - edge) * (1.0 - edge), 1e-15);
    EXPECT_EQ(gauss.weight(1.0, 0.0), 0.0);
    EXPECT_DOUBLE_EQ(gauss.weight(0.3, -0.7), gauss.weight(-0.3, 0.7));
    const PixelFilter quad = makePixelFilter(filterSettings(5, 3.0, 3.0));  // radius 1.5: natural scale
    EXPECT_DOUBLE_EQ(quad.weight(0.0, 1.0), 0.75 * 0.125);
    EXPECT_EQ(quad.weight(1.5, 0.0), 0.0);
    const PixelFilter cubic = makePixelFilter(filterSettings(6));
    EXPECT_DOUBLE_EQ(cubic.weight(0.0, 0.0), (4.0 / 6.0) * (4.0 / 6.0));
    EXPECT_DOUBLE_EQ(cubic.weight(1.0, 0.0), (1.0 / 6.0) * (4.0 / 6.0));
    EXPECT_DOUBLE_EQ(cubic.weight(1.5, 0.5), (0.125 / 6.0) * ((3 * 0.125 - 6 * 0.25 + 4) / 6.0));
}

TEST(PixelFilter, CubicBSplineNormSumsToOneInsideAndToTheInImagePartAtACorner) {
    const PixelFilter f = makePixelFilter(filterSettings(6));
    const PixelRect image{0, 0, 16, 16};
    // A centred surface: (1/6 + 4/6 + 1/6)² inside, (4/6 + 1/6)² at the corner.
    EXPECT_NEAR(filterNorm(f, image, 7, 7, 0.5f, 0.5f), 1.0, 1e-15);
    EXPECT_NEAR(filterNorm(f, image, 0, 0, 0.5f, 0.5f), 25.0 / 36.0, 1e-15);
    EXPECT_NEAR(filterNorm(f, image, 15, 0, 0.5f, 0.5f), 25.0 / 36.0, 1e-15);
}

// Whatever the kernel, the centroid and where the pixel lies, the shares a surface hands to the
// pixels within reach inside the image add up to one: nothing is lost or made at the borders.
TEST(PixelFilter, SharesHandOutEachSurfaceExactlyOnce) {
    const PixelRect image{0, 0, 9, 7};
    for (int type : {0, 2, 4, 5, 6}) {
        for (double width : {1.0, 2.2, 3.0}) {
            const PixelFilter f = makePixelFilter(filterSettings(type, width, 3.0 - width / 2));
            for (auto [x, y] : {std::pair{0, 0}, std::pair{4, 3}, std::pair{8, 6}, std::pair{1, 5}}) {
                for (auto [cu, cv] : {std::pair{0.5f, 0.5f}, std::pair{0.1f, 0.9f}, std::pair{0.97f, 0.03f}}) {
                    SCOPED_TRACE(::testing::Message() << "type " << type << " width " << width << " pixel " << x << ","
                                                      << y << " centroid " << cu << "," << cv);
                    const double norm = filterNorm(f, image, x, y, cu, cv);
                    double total = 0.0;
                    for (int ty = y - f.reach; ty <= y + f.reach; ++ty)
                        for (int tx = x - f.reach; tx <= x + f.reach; ++tx)
                            if (image.contains(tx, ty)) total += filterShare(f, norm, x, y, cu, cv, tx, ty);
                    EXPECT_NEAR(total, 1.0, 1e-12);
                }
            }
        }
    }
}

}  // namespace
}  // namespace pushpin::render
