#pragma once
// One frame of an archive rendered without a window (EGL), written as a PNG: `ridge render`.
#include "ridge/render/terrain_renderer.h"

#include <optional>
#include <string>

namespace ridge::render {

struct HeadlessRenderOptions {
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
};

struct HeadlessRenderResult {
    lod::Camera camera;
    FrameStats stats;
    std::string gl_renderer; // GL_RENDERER of the context used
};

// Renders `archive_path` and writes `png_path` atomically (nothing is left behind on
// failure). Throws ridge::Error naming the file and the problem.
HeadlessRenderResult renderToPng(const std::string& archive_path,
                                 const HeadlessRenderOptions& options, const std::string& png_path);

// Builds the camera `options` describe for `renderer`.
lod::Camera cameraFor(const TerrainRenderer& renderer, const HeadlessRenderOptions& options);

} // namespace ridge::render
