// The public API's rendering (<ridge/ridge.h>): headless PNGs and a Renderer that draws into
// the caller's GL context, over render::TerrainRenderer.
#include "ridge/ridge.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/vec3.hpp>

namespace ridge {
namespace {

glm::dvec3 toGlm(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }
std::array<double, 3> fromGlm(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

render::RenderSettings settingsFrom(const DrawParameters& p)
{
    render::RenderSettings s;
    s.scheme = p.scheme;
    s.epsilon_px = p.max_screen_error_px;
    s.texel_px = p.texel_size_px;
    s.skirts = p.skirts;
    s.sky = p.sky;
    s.fog = p.fog;
    return s;
}

FrameSummary summaryOf(const render::FrameStats& stats)
{
    FrameSummary f;
    f.patches = stats.patches;
    f.triangles = stats.triangles;
    f.screen_error_px = stats.epsilon_px;
    f.missing = stats.missing;
    return f;
}

} // namespace

FrameSummary renderPng(const std::string& archive_path, const std::string& png_path,
                       const RenderParameters& parameters)
{
    render::HeadlessRenderOptions options;
    options.viewport = {parameters.width, parameters.height};
    options.samples = parameters.samples;
    options.settings = settingsFrom(parameters.draw);
    if (parameters.camera) {
        options.camera = toGlm(parameters.camera->position);
        options.look_at = toGlm(parameters.camera->look_at);
        options.fov_y_degrees = parameters.camera->fov_y_degrees;
    }
    return summaryOf(render::renderToPng(archive_path, options, png_path).stats);
}

struct Renderer::Impl {
    archive::ArchiveReader reader;
    render::TerrainRenderer renderer;

    Impl(const std::string& path, const render::RendererOptions& options)
        : reader(path), renderer(reader, options)
    {
    }
};

Renderer::Renderer(const std::string& archive_path, const RendererParameters& parameters)
{
    render::RendererOptions options;
    options.vram_budget_mb = parameters.vram_budget_mb;
    options.ram_budget_mb = parameters.ram_budget_mb;
    options.streaming = parameters.streaming;
    options.schemes = parameters.schemes;
    options.validate();
    impl_ = std::make_unique<Impl>(archive_path, options);
}

Renderer::~Renderer() = default;

FrameSummary Renderer::draw(const CameraPose& pose, int width, int height,
                            const DrawParameters& parameters)
{
    render::HeadlessRenderOptions options; // validates the pose and viewport like renderPng
    options.camera = toGlm(pose.position);
    options.look_at = toGlm(pose.look_at);
    options.fov_y_degrees = pose.fov_y_degrees;
    options.viewport = {width, height};
    options.settings = settingsFrom(parameters);
    const lod::Camera camera = render::cameraFor(impl_->renderer, options);
    return summaryOf(impl_->renderer.draw(camera, options.settings));
}

void Renderer::waitForStreaming() { impl_->renderer.waitForStreaming(); }

CameraPose Renderer::defaultCamera(int width, int height, double fov_y_degrees) const
{
    const lod::Camera c = impl_->renderer.defaultCamera({width, height}, fov_y_degrees);
    CameraPose pose;
    pose.position = fromGlm(c.position());
    // Any point along the view direction: the camera looks the same.
    pose.look_at = fromGlm(c.position() + c.forward() * 1000.0);
    pose.fov_y_degrees = fov_y_degrees;
    return pose;
}

double Renderer::groundHeight(double x, double y) const
{
    return impl_->renderer.groundHeight(x, y);
}

} // namespace ridge
