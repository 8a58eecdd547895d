// ridge::Renderer inside a host application's scene, through the public API only: the host's
// matrices and depth convention, its own geometry intersecting the terrain, picking what was
// drawn, the GL state it finds again, and timed waits. A real EGL context on llvmpipe; the
// tests skip (they do not pass) without one.
#include <ridge/ridge.h>

#include "host_gl.h"
#include "test_support.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

using ridge::test::dataPath;
using ridge::test::ScratchDir;

constexpr int kWidth = 256, kHeight = 192;

std::string everestArchive(const ScratchDir& dir)
{
    ridge::BuildParameters p;
    p.patch_size = 33;
    const std::string path = dir.path("everest.ridge");
    ridge::build(dataPath("everest_crop.tif"), path, p);
    return path;
}

// The highest finest sample of the archive (nearest over every pixel centre): Everest.
struct Summit {
    ridge::LocalPoint local;
    double height = 0.0;
    std::array<double, 2> lon_lat{};
};

Summit findSummit(const ridge::Terrain& terrain)
{
    const ridge::TerrainInfo& info = terrain.info();
    std::vector<std::array<double, 2>> centres;
    for (int64_t r = 0; r < info.height; ++r)
        for (int64_t c = 0; c < info.width; ++c)
            centres.push_back({c + 0.5, r + 0.5});
    ridge::QueryParameters q;
    q.coordinates = ridge::Coordinates::Pixel;
    q.resampling = ridge::Resampling::Nearest;
    const std::vector<ridge::PointHeight> h = terrain.heights(centres, q);
    size_t best = 0;
    for (size_t k = 0; k < h.size(); ++k)
        if (h[k].status == ridge::HeightStatus::Ok && h[k].height > h[best].height)
            best = k;
    Summit s;
    s.local = terrain.localFromPixel(centres[best][0], centres[best][1]);
    s.height = h[best].height;
    s.lon_lat = terrain.lonLatFromLocal(s.local.x, s.local.y);
    return s;
}

bool isColour(const std::vector<uint8_t>& rgba, int x, int y, std::array<int, 3> rgb)
{
    const size_t i = (size_t(y) * kWidth + size_t(x)) * 4;
    return std::abs(rgba[i] - rgb[0]) <= 2 && std::abs(rgba[i + 1] - rgb[1]) <= 2 &&
           std::abs(rgba[i + 2] - rgb[2]) <= 2;
}

const char* nameOf(ridge::DepthConvention c)
{
    return c == ridge::DepthConvention::Standard    ? "Standard"
           : c == ridge::DepthConvention::ZeroToOne ? "ZeroToOne"
                                                    : "ReverseZ";
}

#define REQUIRE_GL()                                                                               \
    if (!host::makeContext())                                                                      \
    GTEST_SKIP() << "no OpenGL 4.5 core context through EGL"

TEST(HostScene, HostGeometryIntersectsTheTerrainWithCorrectDepth)
{
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    const ridge::Terrain terrain(path);
    const Summit summit = findSummit(terrain);
    ridge::RendererParameters rp;
    rp.streaming = false;
    ridge::Renderer renderer(path, rp);
    host::Framebuffer target(kWidth, kHeight);
    const host::Box box;

    // The host looks down at the summit at 45° from 4 km (south-west), and plants a pole
    // 50 m square through it, 1500 m above and below the summit's height. Around a summit
    // everything is lower, so the pole shows from its foot on the drawn surface up; below the
    // surface it is inside the mountain and must be hidden by it.
    const host::Vec3 top{summit.local.x, summit.local.y, summit.height};
    const double d = 4000.0 / std::sqrt(2.0);
    const host::Vec3 eye{top[0] - d * 0.6, top[1] - d * 0.8, top[2] + d};
    const host::Mat4 view = host::lookAt(eye, top);
    const host::Vec3 pole_lo{top[0] - 25.0, top[1] - 25.0, top[2] - 1500.0};
    const host::Vec3 pole_hi{top[0] + 25.0, top[1] + 25.0, top[2] + 1500.0};
    const std::array<float, 3> magenta{1.f, 0.f, 1.f};
    double gx = 0, gy = 0, tx = 0, ty = 0;
    for (const ridge::DepthConvention convention :
         {ridge::DepthConvention::Standard, ridge::DepthConvention::ZeroToOne,
          ridge::DepthConvention::ReverseZ}) {
        const host::Mat4 projection =
            host::perspective(40.0, double(kWidth) / kHeight, 10.0, 2e5, convention);
        ASSERT_TRUE(host::project(view, projection, kWidth, kHeight, top, gx, gy));
        ASSERT_TRUE(
            host::project(view, projection, kWidth, kHeight, {top[0], top[1], pole_hi[2]}, tx, ty));
        ridge::HostView hv;
        hv.view = view;
        hv.projection = projection;
        hv.width = kWidth;
        hv.height = kHeight;
        hv.depth = convention;
        ridge::DrawParameters draw;
        draw.clear = false; // the host's scene stays
        draw.sky = false;
        draw.max_screen_error_px = 1.0;
        for (const bool pole_first : {true, false}) {
            SCOPED_TRACE(std::string(nameOf(convention)) +
                         (pole_first ? ", pole first" : ", terrain first"));
            target.bind();
            host::beginHostFrame(convention, {0.f, 0.f, 0.f, 1.f});
            if (pole_first)
                box.draw(view, projection, pole_lo, pole_hi, magenta);
            const ridge::FrameSummary frame = renderer.draw(hv, draw);
            EXPECT_GT(frame.patches, 0);
            if (!pole_first)
                box.draw(view, projection, pole_lo, pole_hi, magenta);
            ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));
            const std::vector<uint8_t> rgba = target.readRgba();
            // Along the pole's axis: the pole above the summit's pixel (row gy), terrain
            // below it. 1 px is about 21 m of the pole here; the pole's front face meets
            // the slope up to ~3 px below the summit's own pixel.
            const int x = int(gx), ground = int(gy), top_row = int(ty);
            ASSERT_GT(ground - top_row, 40);
            int above = 0, below = 0;
            for (int y = top_row + 2; y <= ground - 5; ++y)
                above += isColour(rgba, x, y, {255, 0, 255});
            for (int y = ground + 5; y <= std::min(kHeight - 1, ground + 40); ++y)
                below += isColour(rgba, x, y, {255, 0, 255});
            EXPECT_EQ(above, ground - 5 - (top_row + 2) + 1) << "pole hidden above the ground";
            EXPECT_EQ(below, 0) << "pole drawn through the mountain";
            // Terrain, not the host's black background, below the summit.
            EXPECT_FALSE(isColour(rgba, x, std::min(kHeight - 1, ground + 10), {0, 0, 0}));
        }
    }
}

TEST(HostScene, RidgesOwnMatricesThroughHostViewDrawTheSamePicture)
{
    // hostView() gives the matrices draw(pose) uses; drawn as a host's, they make the same
    // picture (the LOD camera rebuilt from the matrices selects the same patches).
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    ridge::RendererParameters rp;
    rp.streaming = false;
    ridge::Renderer renderer(path, rp);
    host::Framebuffer target(kWidth, kHeight);
    const ridge::CameraPose pose = renderer.defaultCamera(kWidth, kHeight);
    const ridge::FrameSummary own = renderer.draw(pose, kWidth, kHeight);
    const std::vector<uint8_t> a = target.readRgba();
    const ridge::HostView hv = renderer.hostView(pose, kWidth, kHeight);
    EXPECT_EQ(hv.depth, ridge::DepthConvention::ReverseZ);
    EXPECT_EQ(hv.projection[11], -1.0);
    const ridge::FrameSummary as_host = renderer.draw(hv);
    const std::vector<uint8_t> b = target.readRgba();
    EXPECT_EQ(own.patches, as_host.patches);
    size_t differ = 0;
    for (size_t i = 0; i < a.size(); ++i)
        differ += a[i] != b[i];
    EXPECT_EQ(differ, 0u);
}

TEST(HostScene, PickReturnsTheSummitWithinTheDrawnError)
{
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    const ridge::Terrain terrain(path);
    const Summit summit = findSummit(terrain);
    // The data's summit: SRTM's 3" sample at 86.925 E, 27.9883 N, 8840 m (Everest is
    // 86.9250 E, 27.9881 N, 8848.86 m: the 90 m sample is a little below the peak).
    std::printf("summit sample: %.6f E, %.6f N, %.1f m\n", summit.lon_lat[0], summit.lon_lat[1],
                summit.height);
    EXPECT_NEAR(summit.lon_lat[0], 86.925, 1.0 / 2400);
    EXPECT_NEAR(summit.lon_lat[1], 27.988, 1.0 / 2400);
    EXPECT_NEAR(summit.height, 8848.0, 10.0);

    // Every registered scheme with its default options (ridge::lodSchemes()).
    ridge::RendererParameters rp;
    rp.streaming = false;
    rp.schemes = ridge::lodSchemes();
    ridge::Renderer renderer(path, rp);
    EXPECT_EQ(renderer.schemes(), ridge::lodSchemes());
    host::Framebuffer target(kWidth, kHeight);
    EXPECT_THROW(renderer.pick(10.0, 10.0), ridge::Error); // nothing drawn yet

    const int finest = terrain.info().levels - 1;
    for (const std::string& scheme : renderer.schemes())
        for (const double epsilon : {1.0, 40.0}) {
            SCOPED_TRACE(scheme + ", epsilon " + std::to_string(epsilon));
            ridge::CameraParameters cp;
            cp.position_lonlat = {86.90, 27.95, 13000.0};
            cp.look_at = std::array<double, 3>{summit.local.x, summit.local.y, summit.height};
            cp.fov_y_degrees = 40.0;
            const ridge::CameraPose pose = terrain.cameraPose(cp);
            ridge::DrawParameters draw;
            draw.scheme = scheme;
            draw.max_screen_error_px = epsilon;
            draw.texel_size_px = 0.0; // geometry alone decides the level
            renderer.draw(pose, kWidth, kHeight, draw);

            // Straight down onto the summit sample: its lon/lat exactly, its height within
            // the drawn patch's bound of the source sample.
            const std::optional<ridge::TerrainHit> down =
                renderer.pick({summit.local.x, summit.local.y, 20000.0}, {0.0, 0.0, -1.0});
            ASSERT_TRUE(down.has_value());
            EXPECT_NEAR(down->position[0], summit.local.x, 1e-6);
            EXPECT_NEAR(down->position[1], summit.local.y, 1e-6);
            ASSERT_TRUE(down->lon_lat.has_value());
            EXPECT_NEAR((*down->lon_lat)[0], summit.lon_lat[0], 1e-9);
            EXPECT_NEAR((*down->lon_lat)[1], summit.lon_lat[1], 1e-9);
            EXPECT_NEAR(down->distance, 20000.0 - down->height, 1e-6);
            ASSERT_TRUE(std::isfinite(down->error_bound));
            // Float rounding of camera-relative vertices ~13 km from the eye: a few mm.
            EXPECT_LE(std::abs(down->height - summit.height), down->error_bound + 0.01)
                << "level " << down->level << ", bound " << down->error_bound;
            EXPECT_GE(down->level, 0);
            EXPECT_LE(down->level, finest);
            // The default scheme follows ε: at 1 px the finest level, every sample a vertex,
            // exactly; at 40 px a coarser level. What each other scheme draws at a sample is
            // its own tests' (tests/render/schemes/: brute force's finest level whatever ε,
            // chunks' vertices on their level's samples; geomorphing moves them by design).
            if (scheme == ridge::lodSchemes().front()) {
                if (epsilon == 1.0) {
                    EXPECT_NEAR(down->height, summit.height, 0.01);
                    EXPECT_LT(down->error_bound, 0.01); // float vertices vs integer samples
                } else {
                    EXPECT_LT(down->level, finest) << "a coarse frame draws a coarser level";
                }
            }
            // Straight down onto every finest sample around the summit: each within the
            // bound measured under its triangle (lossless: the archive's samples are the
            // source's), and at a coarse ε the drawn level visibly departs from them.
            double worst = 0.0;
            const ridge::TerrainInfo& info = terrain.info();
            const double col = summit.local.x / info.spacing_x;
            const double row = double(info.height - 1) - summit.local.y / info.spacing_y;
            for (int dj = -12; dj <= 12; ++dj)
                for (int di = -12; di <= 12; ++di) {
                    const ridge::LocalPoint q =
                        terrain.localFromPixel(col + di + 0.5, row + dj + 0.5);
                    const double source = *terrain.height(q.x, q.y);
                    const std::optional<ridge::TerrainHit> hit =
                        renderer.pick({q.x, q.y, 20000.0}, {0.0, 0.0, -1.0});
                    ASSERT_TRUE(hit.has_value());
                    ASSERT_LE(std::abs(hit->height - source), hit->error_bound + 0.01)
                        << "sample " << di << "," << dj << " level " << hit->level;
                    worst = std::max(worst, std::abs(hit->height - source));
                }
            // A coarser level visibly departs from the samples.
            if (epsilon == 40.0 && down->level < finest) {
                EXPECT_GT(worst, 5.0) << "the coarse frame drew the finest surface";
            }
            std::printf("%s, ε %.0f: level %d at the summit, bound %.2f m; worst of 625 "
                        "samples around it %.2f m\n",
                        scheme.c_str(), epsilon, down->level, down->error_bound, worst);

            // Through the summit's pixel from the eye: a point of the drawn surface near the
            // summit, the same one a vertical ray through it finds (exact to the triangles).
            const ridge::HostView hv = renderer.hostView(pose, kWidth, kHeight);
            double px = 0, py = 0;
            ASSERT_TRUE(host::project(hv.view, hv.projection, kWidth, kHeight,
                                      {summit.local.x, summit.local.y, down->height}, px, py));
            const std::optional<ridge::TerrainHit> screen = renderer.pick(px, py);
            ASSERT_TRUE(screen.has_value());
            const double dx = screen->position[0] - summit.local.x,
                         dy = screen->position[1] - summit.local.y,
                         dz = screen->position[2] - down->height;
            EXPECT_LT(std::sqrt(dx * dx + dy * dy + dz * dz), 1.0) << "pixel centre ray";
            const std::optional<ridge::TerrainHit> again = renderer.pick(
                {screen->position[0], screen->position[1], 20000.0}, {0.0, 0.0, -1.0});
            ASSERT_TRUE(again.has_value());
            EXPECT_NEAR(again->height, screen->height, 0.01);
        }
    // Up into the sky: nothing. A zero direction or NaN: an error naming it.
    EXPECT_FALSE(renderer.pick({summit.local.x, summit.local.y, 20000.0}, {0.0, 0.0, 1.0}));
    EXPECT_THROW(renderer.pick({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}), ridge::Error);
    EXPECT_THROW(renderer.pick(std::nan(""), 1.0), ridge::Error);
}

TEST(HostScene, PicksOfAnExaggeratedFrameReportTrueHeights)
{
    // Drawn 2.5 times as tall: the hit lies on the drawn surface (z = 2.5 h) and reports the
    // terrain's own height h, within the bound measured against the true samples.
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    const ridge::Terrain terrain(path);
    const Summit summit = findSummit(terrain);
    ridge::RendererParameters rp;
    rp.streaming = false;
    ridge::Renderer renderer(path, rp);
    host::Framebuffer target(kWidth, kHeight);
    const double k = 2.5;
    ridge::CameraParameters cp;
    cp.position_lonlat = {86.90, 27.95, k * 13000.0};
    cp.look_at = std::array<double, 3>{summit.local.x, summit.local.y, k * summit.height};
    cp.fov_y_degrees = 40.0;
    cp.vertical_exaggeration = k;
    ridge::DrawParameters draw;
    draw.max_screen_error_px = 1.0;
    draw.texel_size_px = 0.0;
    draw.vertical_exaggeration = k;
    renderer.draw(terrain.cameraPose(cp), kWidth, kHeight, draw);
    const std::optional<ridge::TerrainHit> down =
        renderer.pick({summit.local.x, summit.local.y, 50000.0}, {0.0, 0.0, -1.0});
    ASSERT_TRUE(down.has_value());
    EXPECT_NEAR(down->position[2], k * summit.height, 0.05) << "the drawn surface";
    EXPECT_NEAR(down->height, summit.height, down->error_bound + 0.01) << "the terrain's height";
    EXPECT_LT(down->error_bound, 0.05);
    EXPECT_NEAR(renderer.groundHeight(summit.local.x, summit.local.y, k),
                k * renderer.groundHeight(summit.local.x, summit.local.y), 1e-6);
    draw.vertical_exaggeration = 0.0;
    EXPECT_THROW(renderer.draw(terrain.cameraPose(cp), kWidth, kHeight, draw), ridge::Error);
}

TEST(HostScene, DrawAndPickLeaveTheHostsGlStateAsTheyFoundIt)
{
    // A host mid-frame: its own conventions, program, buffers and textures bound, even a
    // pixel-unpack buffer and row length that would wreck ridge's texture uploads. ridge
    // draws the same picture as from a clean state and leaves every one of them in place.
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    host::Framebuffer target(kWidth, kHeight);
    ridge::RendererParameters rp;
    rp.streaming = false;
    std::vector<uint8_t> clean;
    {
        ridge::Renderer renderer(path, rp);
        const ridge::CameraPose pose = renderer.defaultCamera(kWidth, kHeight);
        renderer.draw(pose, kWidth, kHeight);
        clean = target.readRgba();
    }
    GLuint texture2d = 0, array = 0, ssbo = 0, pbo = 0, vao = 0, sampler = 0;
    glCreateSamplers(1, &sampler); // linear filtering: integer textures under it are incomplete
    glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glCreateTextures(GL_TEXTURE_2D, 1, &texture2d);
    glTextureStorage2D(texture2d, 1, GL_RGBA8, 4, 4);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &array);
    glTextureStorage3D(array, 1, GL_R8, 4, 4, 2);
    glCreateBuffers(1, &ssbo);
    glNamedBufferStorage(ssbo, 1024, nullptr, 0);
    glCreateBuffers(1, &pbo);
    glNamedBufferStorage(pbo, 64, nullptr, 0);
    glCreateVertexArrays(1, &vao);
    const host::Box box; // its program
    GLint program = 0;
    box.draw(host::lookAt({0, 0, 10}, {0, 1, 0}),
             host::perspective(60, 1, 1, 100, ridge::DepthConvention::Standard), {0, 5, 0},
             {1, 6, 1}, {1, 1, 1});
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);

    auto setHostState = [&] {
        glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glEnable(GL_CULL_FACE);
        glDisable(GL_DEPTH_TEST);
        glDepthFunc(GL_GEQUAL);
        glDepthMask(GL_FALSE);
        glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
        glClearDepth(0.25);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glUseProgram(GLuint(program));
        glBindVertexArray(vao);
        glBindTextureUnit(0, texture2d);
        glBindTextureUnit(2, array);
        glBindSampler(0, sampler);
        glBindSampler(1, sampler);
        glActiveTexture(GL_TEXTURE3);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, ssbo, 256, 512);
        // The highest binding and unit ridge's terrain uses: the shading map, water maps.
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 4, ssbo, 0, 256);
        glBindTextureUnit(6, array);
        glBindBuffer(GL_PIXEL_UNPACK_BUFFER, pbo);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 7);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 8);
        glPatchParameteri(GL_PATCH_VERTICES, 4);
    };
    auto expectHostState = [&](const char* after) {
        SCOPED_TRACE(after);
        GLint v = 0;
        glGetIntegerv(GL_CLIP_DEPTH_MODE, &v);
        EXPECT_EQ(v, GL_ZERO_TO_ONE);
        EXPECT_TRUE(glIsEnabled(GL_BLEND));
        EXPECT_TRUE(glIsEnabled(GL_CULL_FACE));
        EXPECT_FALSE(glIsEnabled(GL_DEPTH_TEST));
        glGetIntegerv(GL_DEPTH_FUNC, &v);
        EXPECT_EQ(v, GL_GEQUAL);
        GLboolean mask = GL_TRUE;
        glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
        EXPECT_EQ(mask, GL_FALSE);
        GLfloat colour[4];
        glGetFloatv(GL_COLOR_CLEAR_VALUE, colour);
        EXPECT_FLOAT_EQ(colour[2], 0.3f);
        GLdouble depth = 0;
        glGetDoublev(GL_DEPTH_CLEAR_VALUE, &depth);
        EXPECT_EQ(depth, 0.25);
        GLint mode[2] = {0, 0};
        glGetIntegerv(GL_POLYGON_MODE, mode);
        EXPECT_EQ(mode[0], GL_LINE);
        glGetIntegerv(GL_CURRENT_PROGRAM, &v);
        EXPECT_EQ(v, program);
        glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &v);
        EXPECT_EQ(GLuint(v), vao);
        glGetIntegerv(GL_ACTIVE_TEXTURE, &v);
        EXPECT_EQ(v, GL_TEXTURE3);
        glActiveTexture(GL_TEXTURE0);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &v);
        EXPECT_EQ(GLuint(v), texture2d);
        glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &v);
        EXPECT_EQ(v, 0);
        glGetIntegerv(GL_SAMPLER_BINDING, &v);
        EXPECT_EQ(GLuint(v), sampler);
        glActiveTexture(GL_TEXTURE2);
        glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &v);
        EXPECT_EQ(GLuint(v), array);
        glActiveTexture(GL_TEXTURE3);
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 0, &v);
        EXPECT_EQ(GLuint(v), ssbo);
        GLint64 start = 0, size = 0;
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, 0, &start);
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, 0, &size);
        EXPECT_EQ(start, 256);
        EXPECT_EQ(size, 512);
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, 4, &v);
        EXPECT_EQ(GLuint(v), ssbo);
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, 4, &size);
        EXPECT_EQ(size, 256);
        glActiveTexture(GL_TEXTURE6);
        glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &v);
        EXPECT_EQ(GLuint(v), array);
        glActiveTexture(GL_TEXTURE3);
        glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &v);
        EXPECT_EQ(GLuint(v), pbo);
        glGetIntegerv(GL_UNPACK_ROW_LENGTH, &v);
        EXPECT_EQ(v, 7);
        glGetIntegerv(GL_UNPACK_ALIGNMENT, &v);
        EXPECT_EQ(v, 8);
        glGetIntegerv(GL_PATCH_VERTICES, &v);
        EXPECT_EQ(v, 4);
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    };

    target.bind();
    setHostState();
    {
        // Construction uploads the root patch: under the host's state too.
        ridge::Renderer renderer(path, rp);
        expectHostState("construction");
        const ridge::CameraPose pose = renderer.defaultCamera(kWidth, kHeight);
        renderer.draw(pose, kWidth, kHeight);
        expectHostState("draw");
        glDisable(GL_BLEND); // only to read the picture back unblended: nothing is drawn
        EXPECT_EQ(target.readRgba(), clean) << "the host's state changed ridge's picture";
        glEnable(GL_BLEND);
        glActiveTexture(GL_TEXTURE3);
        EXPECT_TRUE(renderer.pick(kWidth / 2.0, kHeight / 2.0).has_value());
        expectHostState("pick");

        // A GL error the host left pending is named as the host's, not taken for ridge's.
        glBindTexture(GL_TEXTURE_2D, 123456789); // not a name: GL_INVALID_OPERATION
        try {
            renderer.draw(pose, kWidth, kHeight);
            ADD_FAILURE() << "drew over a pending GL error";
        } catch (const ridge::Error& e) {
            EXPECT_NE(std::string(e.what()).find("pending"), std::string::npos) << e.what();
        }
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    }
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glPatchParameteri(GL_PATCH_VERTICES, 3);
    glActiveTexture(GL_TEXTURE0);
    glBindVertexArray(0);
    glUseProgram(0);
    glDeleteTextures(1, &texture2d);
    glDeleteTextures(1, &array);
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &pbo);
    glDeleteVertexArrays(1, &vao);
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glDeleteSamplers(1, &sampler);
}

TEST(HostScene, ARolledOffCentreHostFrustumIsDrawnToItsCorners)
{
    // A host camera that rolls 35° and whose frustum is shifted off its axis (as a stereo eye
    // or a jittered frame is), looking down from above the terrain's middle so that terrain
    // fills the whole view: LOD (culling included) is decided for a frustum that contains
    // this one, so no corner of the picture is left as the host's background.
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    const ridge::Terrain terrain(path);
    ridge::RendererParameters rp;
    rp.streaming = false;
    ridge::Renderer renderer(path, rp);
    host::Framebuffer target(kWidth, kHeight);
    const double cx = 0.5 * double(terrain.info().width) * terrain.info().spacing_x;
    const double cy = 0.5 * double(terrain.info().height) * terrain.info().spacing_y;
    const host::Mat4 look = host::lookAt({cx, cy - 1500.0, 9500.0}, {cx, cy, 5400.0});
    const double roll = 35.0 * M_PI / 180.0;
    const host::Mat4 rotate_eye_z{std::cos(roll),
                                  std::sin(roll),
                                  0,
                                  0,
                                  -std::sin(roll),
                                  std::cos(roll),
                                  0,
                                  0,
                                  0,
                                  0,
                                  1,
                                  0,
                                  0,
                                  0,
                                  0,
                                  1};
    ridge::HostView hv;
    hv.view = host::multiply(rotate_eye_z, look);
    hv.projection = host::perspective(50.0, double(kWidth) / kHeight, 5.0, 1e5,
                                      ridge::DepthConvention::ZeroToOne);
    hv.projection[8] = 0.3;  // off-centre: x_ndc += 0.3 at every depth
    hv.projection[9] = -0.2; // and y_ndc −= 0.2
    hv.width = kWidth;
    hv.height = kHeight;
    hv.depth = ridge::DepthConvention::ZeroToOne;
    host::beginHostFrame(hv.depth, {1.f, 0.f, 1.f, 1.f});
    ridge::DrawParameters draw;
    draw.clear = false;
    draw.sky = false;
    draw.fog = false;
    renderer.draw(hv, draw);
    const std::vector<uint8_t> rgba = target.readRgba();
    int background = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            background += isColour(rgba, x, y, {255, 0, 255});
    EXPECT_EQ(background, 0) << "pixels of the view without terrain";
    // Each corner pixel picks a terrain point, on the ray through it.
    for (const auto& [x, y] :
         {std::pair{0.5, 0.5}, std::pair{kWidth - 0.5, 0.5}, std::pair{0.5, kHeight - 0.5},
          std::pair{kWidth - 0.5, kHeight - 0.5}})
        EXPECT_TRUE(renderer.pick(x, y).has_value()) << x << "," << y;
}

TEST(HostScene, HostViewsThatAreNotACameraAreRefusedByName)
{
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    ridge::RendererParameters rp;
    rp.streaming = false;
    ridge::Renderer renderer(path, rp);
    host::Framebuffer target(kWidth, kHeight);
    ridge::HostView good;
    good.view = host::lookAt({1000, 1000, 9000}, {12000, 9000, 5000});
    good.projection = host::perspective(50, 4.0 / 3, 1, 1e5, ridge::DepthConvention::Standard);
    good.width = kWidth;
    good.height = kHeight;
    EXPECT_NO_THROW(renderer.draw(good));
    auto refused = [&](ridge::HostView v, const char* what) {
        try {
            renderer.draw(v);
            ADD_FAILURE() << "drew with " << what;
        } catch (const ridge::Error& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    ridge::HostView v = good;
    v.view[0] = 2.0; // a scale
    refused(v, "rigid");
    v = good;
    v.projection[11] = 0.0; // orthographic
    refused(v, "perspective");
    v = good;
    v.depth = ridge::DepthConvention::ReverseZ; // a standard matrix
    refused(v, "ReverseZ");
    v = good;
    v.projection[5] = std::nan("");
    refused(v, "projection");
    v = good;
    v.width = 0;
    refused(v, "width");
}

TEST(HostScene, WaitForStreamingHonoursItsTimeout)
{
    REQUIRE_GL();
    ScratchDir dir;
    const std::string path = everestArchive(dir);
    host::Framebuffer target(kWidth, kHeight);
    {
        ridge::RendererParameters rp;
        rp.streaming = false;
        ridge::Renderer synchronous(path, rp);
        EXPECT_TRUE(synchronous.waitForStreaming(0.0)); // nothing ever waits
    }
    // Streaming a larger archive (the crop resampled to 4x its samples, JPEG 2000): a fine
    // frame after a coarse one requests dozens of patches at once, milliseconds each to
    // decode.
    const std::string large_source = dir.path("everest_x4.tif");
    ASSERT_EQ(ridge::test::runShell("gdal_translate -q -outsize 400% 400% -r bilinear '" +
                                    dataPath("everest_crop.tif") + "' '" + large_source + "'")
                  .exit_code,
              0);
    ridge::BuildParameters bp;
    bp.codec = "jpeg2000"; // OpenJPEG decodes a patch in milliseconds: the workers lag
    bp.max_error = 1.0;
    bp.patch_size = 65;
    const std::string large = dir.path("everest_x4.ridge");
    ridge::build(large_source, large, bp);
    ridge::Renderer renderer(large); // streaming
    EXPECT_THROW(renderer.waitForStreaming(-1.0), ridge::Error);
    EXPECT_THROW(renderer.waitForStreaming(std::nan("")), ridge::Error);
    EXPECT_THROW(renderer.waitForStreaming(INFINITY), ridge::Error);
    const ridge::CameraPose pose = renderer.defaultCamera(kWidth, kHeight);
    ridge::DrawParameters draw;
    draw.max_screen_error_px = 0.25;
    // A first frame at a coarse ε needs the resident root alone (and compiles the programs).
    ridge::DrawParameters coarse;
    coarse.max_screen_error_px = 1000.0;
    coarse.texel_size_px = 0.0;
    EXPECT_EQ(renderer.draw(pose, kWidth, kHeight, coarse).missing, 0);
    ridge::FrameSummary frame = renderer.draw(pose, kWidth, kHeight, draw);
    EXPECT_GT(frame.missing, 100) << "this frame requests what the coarse one did not need";
    // Just after the requests the decoders are busy for tens of milliseconds (about 30 ms
    // beyond draw() on llvmpipe at ε 0.25, 145 patches; at ε 0.5 only 15-20 ms once parents
    // delivered to the GPU were finished on the CPU instead of decoded again, which a loaded CI
    // machine once lost entirely): a zero timeout says so at once, a long one waits.
    EXPECT_FALSE(renderer.waitForStreaming(0.0));
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_TRUE(renderer.waitForStreaming(60.0));
    std::printf(
        "%d patches missing; decoded %.1f ms after draw() returned\n", frame.missing,
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    EXPECT_TRUE(renderer.waitForStreaming(0.0)); // idle, nothing new requested
    for (int k = 0; k < 200 && frame.missing > 0; ++k) {
        frame = renderer.draw(pose, kWidth, kHeight, draw);
        renderer.waitForStreaming(60.0);
    }
    EXPECT_EQ(frame.missing, 0);
}

} // namespace
