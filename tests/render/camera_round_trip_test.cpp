// The viewer's printed camera (P: lod::renderCameraOptions of the fly camera) read back the way
// `ridge render` reads it (resolveCameraPlacement, then lod::Camera as render::cameraFor makes
// it) gives the fly camera's matrices. GL-free.
#include "test_support.h"

#include "ridge/lod/camera_orientation.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/camera_placement.h"
#include "ridge/render/fly_camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

using namespace ridge;

namespace {

constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;

// "--camera X,Y,Z --heading H --pitch P" → the placement render's options make of it.
CameraPlacement parseRenderOptions(const std::string& text)
{
    std::istringstream in(text);
    std::string flag, value;
    CameraPlacement p;
    while (in >> flag >> value) {
        if (flag == "--camera") {
            glm::dvec3 v;
            char* end = value.data();
            for (int k = 0; k < 3; ++k) {
                v[k] = std::strtod(end, &end);
                if (k < 2) {
                    EXPECT_EQ(*end, ',') << text;
                    ++end;
                }
            }
            EXPECT_EQ(*end, '\0') << text;
            p.position = v;
        } else if (flag == "--heading") {
            p.heading_deg = std::strtod(value.c_str(), nullptr);
        } else if (flag == "--pitch") {
            p.pitch_deg = std::strtod(value.c_str(), nullptr);
        } else {
            ADD_FAILURE() << "unexpected " << flag << " in " << text;
        }
    }
    return p;
}

void expectSameMatrix(const glm::dmat4& a, const glm::dmat4& b, double tolerance)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(a[c][r], b[c][r], tolerance) << "element " << c << "," << r;
}

} // namespace

TEST(CameraRoundTrip, ThePrintedViewerCameraRendersTheSameView)
{
    test::ScratchDir dir;
    BuildOptions o;
    o.patch_size = 33;
    const std::string path = dir.path("e.ridge");
    buildArchive(test::dataPath("everest_crop.tif"), path, o);
    HeightQuery query(path);
    const lod::Viewport viewport{1600, 900};
    for (const auto& [position, yaw, pitch] :
         {std::tuple{glm::dvec3(12000.3, 8000.7, 9100.25), 0.7, -0.31},
          std::tuple{glm::dvec3(-500.0, 20000.0, 6000.0), -2.9, 0.2},
          std::tuple{glm::dvec3(1.0 / 3.0, 2.0 / 3.0, 8848.0), 3.1, -1.5}}) {
        const render::FlyCamera fly(position, yaw, pitch, 100.0);
        const std::string printed = lod::renderCameraOptions(
            fly.position(), fly.yaw() * kDegreesPerRadian, fly.pitch() * kDegreesPerRadian);
        const ResolvedCamera resolved = resolveCameraPlacement(query, parseRenderOptions(printed));
        ASSERT_TRUE(resolved.position && resolved.look_at) << printed;
        EXPECT_EQ(*resolved.position, fly.position()) << printed;
        const lod::Camera rendered(*resolved.position, *resolved.look_at, 60.0, viewport, 2.0, 1e5);
        const lod::Camera viewed = fly.camera(viewport, 60.0, 2.0, 1e5);
        // The fly camera looks at a point 1 m ahead, which rounds to the position's ulp
        // (1.8e-12 m at 12 km): its direction carries ~1e-12 of that, the printed form none.
        expectSameMatrix(rendered.view(), viewed.view(), 1e-11);
        expectSameMatrix(rendered.viewProjection(), viewed.viewProjection(), 1e-11);
        // What `render --json` then reports as heading/pitch is what the overlay shows.
        const lod::HeadingPitch angles = lod::headingPitchOf(rendered.forward());
        EXPECT_NEAR(angles.heading_deg, fly.yaw() * kDegreesPerRadian, 1e-9);
        EXPECT_NEAR(angles.pitch_deg, fly.pitch() * kDegreesPerRadian, 1e-9);
    }
}
