// `ridge render ARCHIVE -o OUT.png`: one frame of the tessellation renderer, headless (EGL).
#include "commands.h"
#include "range_check.h"
#include "render_args.h"
#include "usage_error.h"

#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/render/headless_render.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <glm/matrix.hpp>

#include <cmath>
#include <cstdio>

namespace ridge::cli {

void RenderCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "render",
        "Render a view of an archive to a PNG without a window (EGL; hardware tessellation)");
    command_->add_option("archive", archive_, "Archive (.ridge)")->required();
    command_->add_option("-o,--output", output_, "Output PNG")->required();
    addCameraOptions(*command_, camera_args_, "an oblique view of the whole terrain");
    using Headless = render::HeadlessRenderOptions;
    command_->add_option("--fov", fov_, "Vertical field of view, degrees")
        ->capture_default_str()
        ->check(inRange("--fov", Headless::kFovYDegreesRange));
    command_->add_option("--size", size_, "Image size WIDTHxHEIGHT")->capture_default_str();
    command_->add_option("--error", error_, "Screen-space error threshold ε, pixels")
        ->capture_default_str()
        ->check(inRange("--error", render::RenderSettings::kEpsilonPxRange));
    addTexelSizeOption(*command_, texel_px_);
    addModeOption(*command_, mode_);
    command_
        ->add_option("--lod", lod_,
                     lodSchemeHelp() + "\n(every scheme shares selection, data and shading)")
        ->capture_default_str()
        ->check(lodSpecCheck("--lod"));
    command_->add_flag("--wireframe", wireframe_, "Draw triangle edges over the shading");
    command_->add_flag("--no-cull", no_cull_, "Disable view-frustum culling");
    command_->add_flag("--no-skirts", no_skirts_, "Disable the vertical skirts between patches");
    command_->add_flag("--no-fog", no_fog_, "Disable distance fog");
    command_->add_flag("--no-sky", no_sky_, "Plain background instead of the sky gradient");
    command_->add_option("--samples", samples_, "MSAA samples")
        ->capture_default_str()
        ->check(inIntegerRange("--samples", 1, Headless::kMaxSamples));
    command_
        ->add_option(
            "--sun", sun_,
            "Sun azimuth (degrees clockwise from north) and altitude (degrees), e.g. 315,45")
        ->delimiter(',')
        ->expected(2)
        ->capture_default_str()
        ->check(
            inRange("--sun", render::kSunAzimuthDegreesRange, "the azimuth").application_index(0))
        ->check(inRange("--sun", render::kSunAltitudeDegreesRange, "the altitude")
                    .application_index(1));
    command_
        ->add_option("--vram", vram_mb_,
                     "Texture memory for resident patches, MB (ε is raised when a view needs more)")
        ->capture_default_str()
        ->check(inRange("--vram", render::RendererOptions::kVramBudgetMbRange));
    addExaggerationOption(*command_, exaggeration_);
    addFrameOption(*command_, frame_);
    command_->add_flag("--json", json_, "Print the camera and frame statistics as JSON");
    command_->add_flag("-q,--quiet", quiet_, "Print nothing on success");
}

int RenderCommand::run()
{
    render::HeadlessRenderOptions options;
    CameraPlacement placement = camera_args_.placement();
    placement.exaggeration = exaggeration_;
    options.frame = parseFrameChoice(frame_);
    // The frame the renderer will draw in: cameras are given and reported in it.
    const lod::TerrainFrame frame =
        lod::terrainFrameOf(archive::ArchiveReader(archive_), options.frame, archive_);
    if (!placement.empty()) {
        HeightQuery query(archive_); // GL-free: PROJ and the ground height under the camera
        const ResolvedCamera camera = resolveCameraPlacement(query, placement, &frame);
        options.camera = camera.position;
        options.look_at = camera.look_at;
    }
    options.fov_y_degrees = fov_;
    options.viewport = parseSize(size_);
    options.samples = samples_;
    options.vram_budget_mb = vram_mb_;
    options.settings.epsilon_px = error_;
    options.settings.texel_px = texel_px_;
    options.settings.mode = parseDebugMode(mode_);
    options.settings.scheme = parseLodSpec(lod_, "--lod").scheme();
    options.scheme_spec = lod_;
    options.settings.wireframe = wireframe_;
    options.settings.cull = !no_cull_;
    options.settings.skirts = !no_skirts_;
    options.settings.fog = !no_fog_;
    options.settings.sky = !no_sky_;
    options.settings.sun_direction = render::sunDirection(sun_[0], sun_[1]);
    options.settings.exaggeration = exaggeration_;
    const render::HeadlessRenderResult r = render::renderToPng(archive_, options, output_);
    const glm::dvec3 p = r.camera.position(), f = r.camera.forward();
    // Heading and pitch in the local frame at the camera (true north and the horizon there
    // on a globe).
    const glm::dvec3 grid = frame.gridOf(p);
    const lod::HeadingPitch angles =
        lod::headingPitchOf(glm::transpose(frame.basisAt(grid.x, grid.y).matrix()) * f);
    if (json_) {
        nlohmann::json j = {{"output", output_},
                            {"gl_renderer", r.gl_renderer},
                            {"camera", {p.x, p.y, p.z}},
                            {"forward", {f.x, f.y, f.z}},
                            {"frame", std::string(lod::surfaceName(frame.surface()))},
                            {"heading_deg", angles.heading_deg},
                            {"pitch_deg", angles.pitch_deg},
                            {"fov_y_degrees", fov_},
                            {"size", {options.viewport.width, options.viewport.height}},
                            {"epsilon_px", r.stats.epsilon_px},
                            {"texel_px", r.stats.texel_px},
                            {"patches", r.stats.patches},
                            {"detail_patches", r.stats.detail},
                            {"culled_subtrees", r.stats.culled},
                            {"triangles", r.stats.triangles},
                            {"gpu_ms", std::isfinite(r.stats.gpu_ms)
                                           ? nlohmann::json(r.stats.gpu_ms)
                                           : nlohmann::json()},
                            {"gpu_upload_ms", std::isfinite(r.stats.gpu_upload_ms)
                                                  ? nlohmann::json(r.stats.gpu_upload_ms)
                                                  : nlohmann::json()},
                            {"cpu_select_ms", r.stats.cpu_select_ms},
                            {"cpu_load_ms", r.stats.cpu_load_ms}};
        fmt::print("{}\n", jsonText(j));
    } else if (!quiet_) {
        fmt::print("{}: {}x{}, camera {:.1f},{:.1f},{:.1f}, ε {:.2g} px: {} patches, {} triangles, "
                   "GPU {:.2f} ms ({})\n",
                   output_, options.viewport.width, options.viewport.height, p.x, p.y, p.z,
                   r.stats.epsilon_px, r.stats.patches, r.stats.triangles, r.stats.gpu_ms,
                   r.gl_renderer);
    }
    return 0;
}

} // namespace ridge::cli
