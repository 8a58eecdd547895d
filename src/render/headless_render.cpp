#include "ridge/render/headless_render.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/gpu/context.h"
#include "ridge/gpu/render_target.h"
#include "ridge/io/raster_writer.h"
#include "ridge/render/legend.h"
#include "ridge/render/scheme_options.h"

#include <glm/geometric.hpp>

namespace ridge::render {

void HeadlessRenderOptions::validate() const
{
    if (camera)
        checkParameters("camera position", &camera->x, 3, lod::kCameraCoordinateRange);
    if (look_at)
        checkParameters("camera look-at point", &look_at->x, 3, lod::kCameraCoordinateRange);
    checkParameter("fov_y_degrees", fov_y_degrees, kFovYDegreesRange);
    checkParameter("image width", int64_t{viewport.width}, 1, kMaxImageSide);
    checkParameter("image height", int64_t{viewport.height}, 1, kMaxImageSide);
    checkParameter("samples", int64_t{samples}, 1, kMaxSamples);
    checkParameter("vram_budget_mb", vram_budget_mb, RendererOptions::kVramBudgetMbRange);
    settings.validate();
    if (!scheme_spec.empty()) {
        const std::string name = parseSchemeSpec(scheme_spec).scheme();
        if (name != settings.scheme)
            throw Error("scheme_spec '" + scheme_spec + "' is not of settings.scheme '" +
                        settings.scheme + "'");
    }
}

lod::Camera cameraFor(const TerrainRenderer& renderer, const HeadlessRenderOptions& options)
{
    options.validate();
    if (!options.camera) {
        if (options.look_at)
            throw Error("look_at needs a camera position (HeadlessRenderOptions::camera)");
        return renderer.defaultCamera(options.viewport, options.fov_y_degrees,
                                      options.settings.exaggeration);
    }
    // Positions are in the drawn space: heights times the exaggeration.
    const double k = options.settings.exaggeration;
    glm::dvec3 target;
    if (options.look_at) {
        target = *options.look_at;
    } else if (const lod::TerrainFrame& f = renderer.quadtree().frame(); f.onEllipsoid()) {
        // The ground at the grid's centre.
        const double c = 0.5 * (f.geometry().width() - 1), r = 0.5 * (f.geometry().height() - 1);
        target = f.worldOf(c, r, renderer.groundUnder(f.worldOf(c, r, 0.0), k));
    } else {
        const double x = 0.5 * f.extentX(), y = 0.5 * f.extentY();
        target = glm::dvec3(x, y, renderer.groundHeight(x, y, k));
    }
    if (glm::length(target - *options.camera) <= 0.0)
        throw Error("render: the camera and the look-at point coincide");
    return renderer.cameraLookingAt(*options.camera, target, options.fov_y_degrees,
                                    options.viewport, k);
}

HeadlessRenderResult renderToPng(const std::string& archive_path,
                                 const HeadlessRenderOptions& options, const std::string& png_path)
{
    options.validate();
    refuseOutputOverInput(png_path, {archive_path});
    checkOutputWritable(png_path); // before the work, not after it
    const archive::ArchiveReader reader(archive_path);
    auto context = gpu::HeadlessContext::create();
    RendererOptions ro;
    ro.synchronous_stats = true;
    ro.vram_budget_mb = options.vram_budget_mb;
    ro.schemes = {options.scheme_spec.empty() ? options.settings.scheme : options.scheme_spec};
    ro.frame = options.frame;
    TerrainRenderer renderer(reader, ro);
    HeadlessRenderResult result{cameraFor(renderer, options), {}, context->rendererName()};
    const gpu::RenderTarget target(options.viewport.width, options.viewport.height,
                                   options.samples);
    target.bind();
    result.stats = renderer.draw(result.camera, options.settings);
    const std::vector<uint8_t> rgba = target.readRgba();
    std::vector<uint8_t> rgb(size_t(options.viewport.width) * options.viewport.height * 3);
    for (size_t i = 0, n = rgb.size() / 3; i < n; ++i)
        for (int c = 0; c < 3; ++c)
            rgb[i * 3 + c] = rgba[i * 4 + c];
    // The debug colour modes carry their key in the picture.
    drawLegend(rgb.data(), options.viewport.width, options.viewport.height, 3,
               legendEntries(options.settings.mode, renderer.quadtree().geometry().finestLevel(),
                             renderer.blockCells()));
    io::writePng(png_path, rgb.data(), options.viewport.width, options.viewport.height, 3);
    return result;
}

} // namespace ridge::render
