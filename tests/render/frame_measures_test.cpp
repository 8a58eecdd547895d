// The frame measures without GL: hole pixels from a background mask, popping from two
// surfaces, the surface heights a capture covers.
#include "ridge/render/frame_measures.h"

#include "ridge/core/error.h"
#include "ridge/pyramid/pyramid_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ridge {
namespace {

// A 65 x 65 terrain of 10 m samples (640 m square), heights within [0, 100] m.
lod::TerrainFrame frame65()
{
    return lod::TerrainFrame(PyramidGeometry(65, 65, 33), 10.0, 10.0);
}

lod::Camera lookingDown(lod::Viewport vp)
{
    return lod::Camera({320.0, 320.0, 2000.0}, {320.0, 320.1, 0.0}, 30.0, vp, 1.0, 1e5);
}

TEST(FrameMeasures, EveryBackgroundPixelInsideTheFootprintIsAHoleAndNoneOutside)
{
    const lod::Viewport vp{64, 48};
    const lod::Camera camera = lookingDown(vp);
    std::vector<uint8_t> background(size_t(vp.width) * vp.height, 0);
    const render::HoleReport none = render::countHolePixels(background, camera, frame65(), 0, 100);
    // From 2 km with a 30° field of view the 640 m terrain fills a fifth of the frame.
    EXPECT_GT(none.footprint_pixels, 500u);
    EXPECT_EQ(none.hole_pixels, 0u);
    background[size_t(24) * vp.width + 32] = 1; // the centre: over the terrain
    background[0] = 1;                          // a corner, beyond the terrain: sky
    const render::HoleReport one = render::countHolePixels(background, camera, frame65(), 0, 100);
    EXPECT_EQ(one.hole_pixels, 1u);
    EXPECT_EQ(one.first_x, 32);
    EXPECT_EQ(one.first_y, 24);
    std::vector<uint8_t> all(background.size(), 1);
    const render::HoleReport sky = render::countHolePixels(all, camera, frame65(), 0, 100);
    EXPECT_EQ(sky.hole_pixels, sky.footprint_pixels);
    EXPECT_LT(sky.footprint_pixels, all.size()) << "pixels beyond the border are not judged";
    EXPECT_THROW(render::countHolePixels(std::vector<uint8_t>(3), camera, frame65(), 0, 100),
                 Error);
}

// Two triangles over the whole terrain at constant height z (camera at the origin).
render::CapturedSurface flatSurface(float z)
{
    render::CapturedSurface s;
    const float e = 640.f;
    const render::CapturedVertex a{0, 0, z, 0, 0}, b{e, 0, z, 0, 0}, c{0, e, z, 0, 0},
        d{e, e, z, 0, 0};
    s.vertices = {a, b, c, b, d, c};
    return s;
}

TEST(FrameMeasures, PoppingIsTheLargestProjectedDisplacementBetweenTwoSurfaces)
{
    const lod::TerrainFrame f = frame65();
    const lod::Camera camera = lookingDown({400, 300});
    const render::SampleHeights low = render::surfaceHeightsAtSamples(flatSurface(10.f), f);
    ASSERT_EQ(low.width, 65);
    ASSERT_EQ(low.height, 65);
    EXPECT_EQ(low.at(7, 9), 10.f);
    EXPECT_TRUE(std::isnan(low.at(70, 9)));
    const render::PoppingReport same = render::measurePopping(low, low, f, camera);
    EXPECT_GT(same.samples, 1000u);
    EXPECT_EQ(same.max_px, 0.0);
    // Looking straight down from 2 km, a 20 m rise moves a sample at the view's edge outwards
    // by a fraction of a percent of its distance from the centre: a few pixels at most.
    const render::SampleHeights high = render::surfaceHeightsAtSamples(flatSurface(30.f), f);
    const render::PoppingReport moved = render::measurePopping(low, high, f, camera);
    EXPECT_EQ(moved.max_metres, 20.0);
    EXPECT_GT(moved.max_px, 0.1);
    EXPECT_LT(moved.max_px, 10.0);
}

TEST(FrameMeasures, ALowCameraAboveTheDrawnSurfaceJudgesItsDownwardRays)
{
    // 20 m above a flat surface at 50 m, inside the slab [0, 100], looking ahead and down.
    const lod::Viewport vp{64, 48};
    const lod::Camera low({320.0, 100.0, 70.0}, {320.0, 400.0, 0.0}, 60.0, vp, 0.5, 1e5);
    std::vector<uint8_t> sky(size_t(vp.width) * vp.height, 1);
    const render::CapturedSurface flat = flatSurface(50.f);
    const double under = render::surfaceHeightUnder(flat, frame65(), 320.0, 100.0);
    EXPECT_EQ(under, 50.0);
    EXPECT_TRUE(std::isnan(render::surfaceHeightUnder(flat, frame65(), 700.0, 100.0)));
    // Without the surface's height a camera inside the slab is not judged at all.
    EXPECT_EQ(render::countHolePixels(sky, low, frame65(), 0, 100).footprint_pixels, 0u);
    const render::HoleReport judged =
        render::countHolePixels(sky, low, frame65(), 0, 100, 4.0, under);
    EXPECT_GT(judged.footprint_pixels, 300u);
    EXPECT_EQ(judged.hole_pixels, judged.footprint_pixels);
    EXPECT_LT(judged.footprint_pixels, sky.size()) << "rays that rise or leave are not judged";
    // A camera under the drawn surface (a ridge above it) is not judged.
    EXPECT_EQ(render::countHolePixels(sky, low, frame65(), 0, 100, 4.0, 80.0).footprint_pixels, 0u);
    // Skirts are not the surface.
    render::CapturedSurface skirts = flat;
    for (auto& v : skirts.vertices)
        v.skirt = 1;
    EXPECT_TRUE(std::isnan(render::surfaceHeightUnder(skirts, frame65(), 320.0, 100.0)));
}

TEST(FrameMeasures, SkirtTrianglesAreNotSurface)
{
    render::CapturedSurface s = flatSurface(5.f);
    for (auto& v : s.vertices)
        v.skirt = 2;
    const render::SampleHeights h = render::surfaceHeightsAtSamples(s, frame65());
    EXPECT_EQ(h.width * h.height, 0);
}

} // namespace
} // namespace ridge
