#pragma once
// One frame of an archive rendered without a window (EGL), written as a PNG: `ridge render`.
#include "ridge/render/terrain_renderer.h"

#include <optional>
#include <string>

namespace ridge::render {

struct HeadlessRenderOptions {
    // φ_v in degrees: narrower than 1° is a telescope, wider than 170° a fisheye that a
    // perspective projection stretches beyond use.
    static constexpr ValueRange kFovYDegreesRange = ValueRange::closed(1.0, 170.0);
    static constexpr int kMaxImageSide = 16384; // pixels: GL_MAX_RENDERBUFFER_SIZE on most GPUs
    static constexpr int kMaxSamples = 16;      // MSAA

    // Camera in the archive's terrain frame (see ridge/lod/terrain_frame.h). Without a
    // position: TerrainRenderer::defaultCamera. With a position but no look-at: the centre
    // of the terrain.
    std::optional<glm::dvec3> camera;
    std::optional<glm::dvec3> look_at;
    double fov_y_degrees = 60.0;
    lod::Viewport viewport{1920, 1080};
    int samples = 4;               // MSAA
    double vram_budget_mb = 256.0; // texture arrays of resident patches (RendererOptions)
    RenderSettings settings;
    // The scheme's own options: a spec of settings.scheme, "NAME[,KEY=VALUE...]"
    // (RendererOptions::schemes). Empty: settings.scheme with its module's defaults.
    std::string scheme_spec;
    // The terrain frame (RendererOptions::frame): the camera above is in it.
    lod::FrameChoice frame = lod::FrameChoice::Auto;

    // Throws ridge::Error naming the first field outside its range: camera and look-at within
    // lod::kCameraCoordinateRange, the field of view, image sides in [1, kMaxImageSide],
    // samples in [1, kMaxSamples], vram_budget_mb (RendererOptions), settings.validate(),
    // a scheme_spec that does not parse or names another scheme than settings.scheme.
    void validate() const;
};

struct HeadlessRenderResult {
    lod::Camera camera;
    FrameStats stats;
    std::string gl_renderer; // GL_RENDERER of the context used
};

// Renders `archive_path` and writes `png_path` atomically (nothing is left behind on
// failure). Throws ridge::Error naming the file and the problem; options are validated
// before the archive is opened.
HeadlessRenderResult renderToPng(const std::string& archive_path,
                                 const HeadlessRenderOptions& options, const std::string& png_path);

// Builds the camera `options` describe for `renderer` (validating them first).
lod::Camera cameraFor(const TerrainRenderer& renderer, const HeadlessRenderOptions& options);

} // namespace ridge::render
