// Precision on the ellipsoid (issue 26): with the camera 1 m, 10 m and 1 km above the ground at
// the equator, 45°N, across the antimeridian and at 89.9°N (real SRTM heights, everest_crop.tif
// relocated there), and on projected grids — UTM 45N in its own place, and a polar
// stereographic grid with the South Pole inside it — every vertex the GPU places matches the
// double-precision position of its sample within 1 mm near the camera and within float's own
// resolution of its distance further out, and a camera moved in 1 mm steps moves every nearby
// vertex by 1 mm a step (no jitter). The same vertices formed the usual way — float ECEF minus the
// float camera — miss by tenths of a metre: the test shows that too.
#include "fixture_archives.h"
#include "gdal_translate.h"

#include "ridge/gpu/context.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/render/terrain_renderer.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ridge {
namespace {

struct Place {
    const char* name;
    const char* tif;                 // in tests/data
    const char* srs;                 // assigned to it (nullptr: its own)
    double west, north, east, south; // its corners moved there (CRS units)
};

// everest_crop.tif is 301 x 203 samples of 3″: 0.2508° x 0.1692°. everest_utm45.tif is
// 262 x 197 samples of 90 m in UTM 45N, and the same samples relabelled in the Antarctic
// polar stereographic projection with the South Pole in the middle.
constexpr double kCropW = 301 * (3.0 / 3600.0), kCropH = 203 * (3.0 / 3600.0);
const Place kPlaces[] = {
    {"equator", "everest_crop.tif", nullptr, 10.0, 0.08, 10.0 + kCropW, 0.08 - kCropH},
    {"45N", "everest_crop.tif", nullptr, 7.0, 45.1, 7.0 + kCropW, 45.1 - kCropH},
    // Columns run on past 180°.
    {"antimeridian", "everest_crop.tif", nullptr, 179.9, -16.0, 179.9 + kCropW, -16.0 - kCropH},
    {"89.9N", "everest_crop.tif", nullptr, 0.0, 89.96, kCropW, 89.96 - kCropH},
    // Projected grids: UTM in its own place, and a polar grid round the pole.
    {"utm45", "everest_utm45.tif", nullptr, 0.0, 0.0, 0.0, 0.0},
    {"south_pole_3031", "everest_utm45.tif", "EPSG:3031", -11790.0, 8865.0, 11790.0, -8865.0},
};

struct Archive {
    std::string path;
    std::unique_ptr<archive::ArchiveReader> reader;
    CodeGrid finest;
};

class GlobePrecision : public ::testing::TestWithParam<Place> {
  protected:
    static void SetUpTestSuite()
    {
        context_ = gpu::HeadlessContext::create().release();
        scratch_ = new test::ScratchDir();
    }
    static void TearDownTestSuite()
    {
        delete scratch_;
        delete context_;
    }

    static Archive relocated(const Place& place)
    {
        std::string tif = test::dataPath(place.tif);
        if (place.west != place.east) {
            tif = scratch_->path(std::string(place.name) + ".tif");
            std::vector<std::string> args{"-a_ullr"};
            for (double v : {place.west, place.north, place.east, place.south}) {
                char text[32];
                std::snprintf(text, sizeof text, "%.12f", v);
                args.push_back(text);
            }
            if (place.srs)
                args.insert(args.end(), {"-a_srs", place.srs});
            test::gdalTranslate(test::dataPath(place.tif), tif, args);
        }
        Archive a;
        a.path = scratch_->path(std::string(place.name) + ".ridge");
        BuildOptions options;
        options.patch_size = 33;
        options.progress = {};
        buildArchive(tif, a.path, options);
        a.reader = std::make_unique<archive::ArchiveReader>(a.path);
        a.finest = decodeLevel(*a.reader, a.reader->geometry().finestLevel());
        return a;
    }

    static gpu::HeadlessContext* context_;
    static test::ScratchDir* scratch_;
};

gpu::HeadlessContext* GlobePrecision::context_ = nullptr;
test::ScratchDir* GlobePrecision::scratch_ = nullptr;

struct Errors {
    size_t near_vertices = 0; // within the near radius of the camera
    double near_max = 0.0;    // metres
    double worst_ratio = 0.0; // error / max(1 mm, 2^-20 · distance), all vertices
    double naive_near_max = 0.0;
    size_t morphed = 0; // vertices off their sample's height (geomorph), held to the segment
};

// Where a morphing scheme may draw the vertex of finest sample (c, r) of patch `p`: anywhere
// on the segment from the sample to the sample at its target height (geomorph.vert morphs
// heights). The target is the parent's surface there: its sample's height at an even position
// of the patch, else the mean of the two samples whose chord the sample halves (an edge, or
// the cell diagonal b–c, lod::targetPair), `rounded` as the compact layout's target codes are
// (k + ½ up). Levels are the finest samples (a decimated pyramid), so the finest codes give
// every level's.
glm::dvec3 parentSurfacePoint(const lod::TerrainFrame& frame, const Archive& a, PatchId p, int c,
                              int r, bool rounded)
{
    const PyramidGeometry& g = frame.geometry();
    const int64_t step = g.step(p.level), span = int64_t(g.cells()) * step;
    const int64_t i = (c - p.x * span) / step, j = (r - p.y * span) / step;
    auto code = [&](int64_t x, int64_t y) {
        x = std::clamp<int64_t>(x, 0, a.finest.width - 1);
        y = std::clamp<int64_t>(y, 0, a.finest.height - 1);
        return double(a.finest.at(int(x), int(y)));
    };
    const HeightQuantization& q = a.reader->quantization();
    double target = code(c, r);
    if (p.level > 0 && ((i & 1) != 0 || (j & 1) != 0)) {
        const int dx = int(i & 1), dy = (i & 1) && (j & 1) ? -1 : int(j & 1);
        const double mean =
            0.5 * (code(c + dx * step, r + dy * step) + code(c - dx * step, r - dy * step));
        target = rounded ? std::floor(mean + 0.5) : mean;
    }
    return frame.worldOf(c, r, q.toMetres(target));
}

// Distance from point q to the segment a–b.
double toSegment(glm::dvec3 q, glm::dvec3 a, glm::dvec3 b)
{
    const glm::dvec3 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
    return glm::length(q - (a + t * ab));
}

// Every surface vertex of `s` against the double position of its sample, or for a morphing
// scheme against the segment from it to the parent's surface there; "near" within
// `near_radius` metres of the camera.
Errors measure(const render::CapturedSurface& s, const lod::TerrainFrame& frame, const Archive& a,
               double near_radius)
{
    Errors e;
    const glm::dvec3 cam = s.camera_position;
    const glm::vec3 cam_f(cam);
    const int w = a.finest.width, h = a.finest.height;
    for (const render::CapturedVertex& v : s.vertices) {
        if (v.skirt != 0)
            continue;
        const glm::dvec3 got(v.x, v.y, v.z);
        const glm::dvec3 g = frame.gridOf(cam + got);
        const int c = int(std::lround(g.x)), r = int(std::lround(g.y));
        // The last column and row are where patches past the extent are clipped: points cut
        // inside a coarse cell lie on its surface, not on a sample.
        if (c < 0 || r < 0 || c >= w - 1 || r >= h - 1)
            continue;
        const double metres = a.reader->quantization().toMetres(a.finest.at(c, r));
        // A morphing scheme draws some vertices between their sample and the parent's
        // surface (counted: a vertex further than 1 mm from its sample's height).
        e.morphed += std::abs(g.z - metres) > 1e-3;
        const glm::dvec3 world = frame.worldOf(c, r, metres);
        const glm::dvec3 truth = world - cam;
        const PatchId patch = s.patches[size_t(v.instance)];
        const double d = glm::length(truth);
        double err = glm::length(got - truth);
        for (const bool rounded : {false, true})
            err =
                std::min(err, toSegment(got, truth,
                                        parentSurfacePoint(frame, a, patch, c, r, rounded) - cam));
        e.worst_ratio = std::max(e.worst_ratio, err / std::max(1e-3, std::ldexp(d, -20)));
        if (d <= near_radius) {
            ++e.near_vertices;
            e.near_max = std::max(e.near_max, err);
            // Plain float world coordinates: each position rounded at Earth scale.
            const glm::vec3 naive = glm::vec3(world) - cam_f;
            e.naive_near_max = std::max(e.naive_near_max, glm::length(glm::dvec3(naive) - truth));
        }
    }
    return e;
}

lod::Camera cameraAbove(const lod::TerrainFrame& frame, const Archive& a, double above,
                        glm::dvec3 shift = glm::dvec3(0.0))
{
    const int c = 150, r = 101;
    const double ground = a.reader->quantization().toMetres(a.finest.at(c, r));
    const lod::EnuBasis b = frame.basisAt(c, r);
    const glm::dvec3 pos = frame.worldOf(c, r, ground + above) + shift;
    // Along the ground to the north-east, a little down.
    const glm::dvec3 at = pos + 1000.0 * glm::normalize(b.east + b.north) - 30.0 * b.up;
    return lod::Camera(pos, at, 60.0, {320, 240}, 0.05, 2e6, b.up);
}

TEST_P(GlobePrecision, VerticesMatchDoublePrecisionWithinAMillimetreNearTheCamera)
{
    const Archive a = relocated(GetParam());
    render::RendererOptions ro;
    ro.schemes = render::lodSchemeNames();
    ro.frame = lod::FrameChoice::Ellipsoid;
    ro.max_resident_patches = 256;
    render::TerrainRenderer renderer(*a.reader, ro);
    const lod::TerrainFrame& frame = renderer.quadtree().frame();
    ASSERT_TRUE(frame.onEllipsoid());
    for (const std::string& scheme : renderer.schemes())
        for (double above : {1.0, 10.0, 1000.0}) {
            render::RenderSettings settings;
            settings.scheme = scheme;
            // Near: within 1 km of the ground point under the camera.
            const Errors e = measure(renderer.capture(cameraAbove(frame, a, above), settings),
                                     frame, a, 1000.0 + above);
            SCOPED_TRACE(std::string(GetParam().name) + ", " + scheme + ", " +
                         std::to_string(above) + " m up");
            std::printf("%-12s %-9s %6.0f m: %zu vertices near, worst %.3f mm there (float "
                        "world coordinates: %.0f mm); worst error / max(1 mm, 2^-20 d) = %.2f\n",
                        GetParam().name, scheme.c_str(), above, e.near_vertices, 1e3 * e.near_max,
                        1e3 * e.naive_near_max, e.worst_ratio);
            EXPECT_GT(e.near_vertices, 0u);
            EXPECT_LE(e.near_max, 1e-3);
            EXPECT_LE(e.worst_ratio, 1.0);
            // The same vertices in plain float world coordinates are decimetres off.
            EXPECT_GT(e.naive_near_max, 0.02);
        }
}

TEST_P(GlobePrecision, ACameraMovedInMillimetreStepsMovesNearbyVerticesSmoothly)
{
    const Archive a = relocated(GetParam());
    render::RendererOptions ro;
    ro.frame = lod::FrameChoice::Ellipsoid;
    ro.max_resident_patches = 256;
    render::TerrainRenderer renderer(*a.reader, ro);
    const lod::TerrainFrame& frame = renderer.quadtree().frame();
    const render::RenderSettings settings; // the default scheme
    const lod::Camera base = cameraAbove(frame, a, 1.0);
    const glm::dvec3 east = frame.basisAt(150, 101).east;
    const render::CapturedSurface s0 = renderer.capture(base, settings, &base);
    std::vector<glm::dvec3> previous;
    for (const render::CapturedVertex& v : s0.vertices)
        previous.emplace_back(v.x, v.y, v.z);
    size_t checked = 0;
    double worst = 0.0;
    for (int k = 1; k <= 5; ++k) {
        const lod::Camera moved = cameraAbove(frame, a, 1.0, 1e-3 * k * east);
        // LOD for the first camera: the same triangles, only the camera moves.
        const render::CapturedSurface s = renderer.capture(moved, settings, &base);
        ASSERT_EQ(s.vertices.size(), previous.size());
        for (size_t i = 0; i < s.vertices.size(); ++i) {
            const glm::dvec3 p(s.vertices[i].x, s.vertices[i].y, s.vertices[i].z);
            if (s.vertices[i].skirt == 0 && glm::length(p) <= 1000.0) {
                // Each step moves the vertex 1 mm west relative to the camera, ± 0.25 mm.
                const glm::dvec3 step = p - previous[i];
                worst = std::max(worst, glm::length(step + 1e-3 * east));
                EXPECT_LT(glm::dot(step, east), 0.0) << "vertex " << i << " step " << k;
                ++checked;
            }
            previous[i] = p;
        }
    }
    std::printf("%-12s: %zu vertex steps within 1 km, worst deviation from a 1 mm step %.3f mm\n",
                GetParam().name, checked, 1e3 * worst);
    EXPECT_GT(checked, 250u);
    EXPECT_LE(worst, 0.25e-3);
}

INSTANTIATE_TEST_SUITE_P(Places, GlobePrecision, ::testing::ValuesIn(kPlaces),
                         [](const auto& info) {
                             std::string n = info.param.name;
                             for (char& ch : n)
                                 if (!std::isalnum(static_cast<unsigned char>(ch)))
                                     ch = '_';
                             return n;
                         });

} // namespace
} // namespace ridge
