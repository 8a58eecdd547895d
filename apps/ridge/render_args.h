#pragma once
// Command-line values shared by `ridge render`, `ridge view` and `ridge bench`.
#include "range_check.h"
#include "usage_error.h"

#include "ridge/core/error.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/camera_orientation.h"
#include "ridge/pipeline/camera_placement.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/stream/upload_planner.h"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

namespace ridge::cli {

// "WIDTHxHEIGHT", as --size takes it, each side in [1, max_side] pixels.
inline lod::Viewport parseSize(const std::string& text,
                               int max_side = render::HeadlessRenderOptions::kMaxImageSide)
{
    // Two decimal integers around one 'x' (the command line's one spelling of numbers).
    const size_t x = text.find_first_of("xX");
    const std::optional<int64_t> w =
        x == std::string::npos ? std::nullopt : detail::parseInteger(text.substr(0, x));
    const std::optional<int64_t> h =
        x == std::string::npos ? std::nullopt : detail::parseInteger(text.substr(x + 1));
    if (!w || !h)
        throw UsageError("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1920x1080");
    if (*w < 1 || *h < 1 || *w > max_side || *h > max_side)
        throw UsageError("--size " + text + ": each side must be an integer in [1, " +
                         std::to_string(max_side) + "]");
    return {int(*w), int(*h)};
}

// The camera options `ridge render` and `ridge view` share, as given.
struct CameraArgs {
    std::vector<double> camera, look_at, camera_lonlat, look_at_lonlat;
    std::optional<double> heading, pitch;
    bool above_ground = false;

    // Throws UsageError for a view direction without a camera position (CLI11's needs()
    // cannot say "one of --camera, --camera-lonlat").
    CameraPlacement placement() const
    {
        const bool positioned = !camera.empty() || !camera_lonlat.empty();
        if (!positioned && !look_at.empty())
            throw UsageError("--look-at requires --camera or --camera-lonlat");
        if (!positioned && !look_at_lonlat.empty())
            throw UsageError("--look-at-lonlat requires --camera or --camera-lonlat");
        if (!positioned && heading)
            throw UsageError("--heading and --pitch require --camera or --camera-lonlat");
        CameraPlacement p;
        if (!camera.empty())
            p.position = glm::dvec3(camera[0], camera[1], camera[2]);
        if (!look_at.empty())
            p.look_at = glm::dvec3(look_at[0], look_at[1], look_at[2]);
        if (!camera_lonlat.empty())
            p.position_lonlat = glm::dvec3(camera_lonlat[0], camera_lonlat[1], camera_lonlat[2]);
        if (!look_at_lonlat.empty())
            p.look_at_lonlat =
                glm::dvec3(look_at_lonlat[0], look_at_lonlat[1],
                           look_at_lonlat.size() > 2 ? look_at_lonlat[2]
                                                     : std::numeric_limits<double>::quiet_NaN());
        p.heading_deg = heading;
        p.pitch_deg = pitch;
        p.above_ground = above_ground;
        return p;
    }
};

// --camera, --look-at (local metres), --camera-lonlat, --look-at-lonlat (WGS 84), --heading,
// --pitch, --above-ground; the combinations resolveCameraPlacement refuses are refused here
// first where CLI11 can say so.
inline void addCameraOptions(CLI::App& command, CameraArgs& args, const std::string& default_view)
{
    auto* camera =
        command
            .add_option("--camera", args.camera,
                        "Camera position X,Y,Z in metres: x east of the first column, y north "
                        "of the last row, z elevation (default: " +
                            default_view + ")")
            ->delimiter(',')
            ->expected(3)
            ->check(inRange("--camera", lod::kCameraCoordinateRange, "each coordinate"));
    auto* camera_lonlat =
        command
            .add_option("--camera-lonlat", args.camera_lonlat,
                        "Camera position LON,LAT,H: WGS 84 degrees and metres in the terrain's "
                        "vertical datum (absolute; see --above-ground), through PROJ")
            ->delimiter(',')
            ->expected(3)
            ->check(inRange("--camera-lonlat", ValueRange::any(), "each value"));
    camera->excludes(camera_lonlat);
    auto* look_at =
        command
            .add_option("--look-at", args.look_at,
                        "Point the camera looks at, X,Y,Z (default: terrain centre)")
            ->delimiter(',')
            ->expected(3)
            ->check(inRange("--look-at", lod::kCameraCoordinateRange, "each coordinate"));
    auto* look_at_lonlat =
        command
            .add_option("--look-at-lonlat", args.look_at_lonlat,
                        "Point the camera looks at, LON,LAT[,H] (WGS 84; without H the ground "
                        "there)")
            ->delimiter(',')
            ->expected(2, 3)
            ->check(inRange("--look-at-lonlat", ValueRange::any(), "each value"));
    look_at->excludes(look_at_lonlat);
    auto* heading =
        command
            .add_option("--heading", args.heading,
                        "View direction instead of a look-at point: degrees clockwise from grid "
                        "north (the raster's up; true north for lon/lat rasters), with --pitch")
            ->check(inRange("--heading", lod::kHeadingDegreesRange));
    auto* pitch = command
                      .add_option("--pitch", args.pitch,
                                  "Degrees above the horizon (negative looks down), with --heading")
                      ->check(inRange("--pitch", lod::kPitchDegreesRange));
    heading->needs(pitch);
    pitch->needs(heading);
    heading->excludes(look_at)->excludes(look_at_lonlat);
    pitch->excludes(look_at)->excludes(look_at_lonlat);
    command.add_flag("--above-ground", args.above_ground,
                     "The camera's height (Z or H) is metres above the terrain under it");
}

// --mode as `render` and `view` take it: shaded, lod (level colours), tess (tessellation
// factors).
inline render::DebugMode parseDebugMode(const std::string& mode)
{
    if (mode == "shaded")
        return render::DebugMode::Shaded;
    if (mode == "lod")
        return render::DebugMode::LodLevels;
    if (mode == "tess")
        return render::DebugMode::TessellationFactors;
    throw UsageError("--mode " + mode + ": expected shaded, lod or tess");
}

inline void addModeOption(CLI::App& command, std::string& mode)
{
    command
        .add_option("--mode", mode,
                    "shaded, lod (level colours) or tess (tessellation-factor heat map)")
        ->capture_default_str()
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                parseDebugMode(text); // throws UsageError naming --mode
                return {};
            },
            "shaded|lod|tess"));
}

// --frame: the terrain frame (lod/archive_frame.h).
inline lod::FrameChoice parseFrameChoice(const std::string& text)
{
    if (const std::optional<lod::FrameChoice> c = lod::parseFrameChoice(text))
        return *c;
    throw UsageError("--frame " + text + ": expected auto, plane or ellipsoid");
}

inline void addFrameOption(CLI::App& command, std::string& frame)
{
    command
        .add_option("--frame", frame,
                    "Terrain frame: plane (the raster's own metric plane), ellipsoid (WGS 84: "
                    "a georeferenced raster, lon/lat or projected, on the globe in its place) or "
                    "auto (the ellipsoid for a raster that goes round the Earth, else the "
                    "plane)")
        ->capture_default_str()
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                parseFrameChoice(text); // throws UsageError naming --frame
                return {};
            },
            "auto|plane|ellipsoid"));
}

// A --lod spec, "NAME[,KEY=VALUE...]": a registered scheme (render::lodSchemeNames()) and
// its own options, checked against the options its module declares. `option` names the flag
// in the message: "--lod NAME: KEY=VALUE: must be ...".
inline render::SchemeOptions parseLodSpec(const std::string& spec, const std::string& option)
{
    try {
        return render::parseSchemeSpec(spec, option);
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

// CLI11's check for a --lod spec: refused while the command line is parsed (exit status 2).
inline CLI::Validator lodSpecCheck(const std::string& option)
{
    return CLI::Validator(
        [option](std::string& text) -> std::string {
            parseLodSpec(text, option); // throws UsageError naming the option
            return {};
        },
        "NAME[,KEY=VALUE...]");
}

// --help text listing every registered scheme with its description and its options, from the
// descriptors its module declares.
inline std::string lodSchemeHelp()
{
    std::string help = "LOD scheme and its options, NAME[,KEY=VALUE...]:";
    for (const std::string& name : render::lodSchemeNames()) {
        help += "\n  " + name + ": " + render::lodSchemeDescription(name);
        for (const render::SchemeOption& o : render::lodSchemeOptions(name)) {
            const bool number = o.kind == render::SchemeOption::Kind::Number ||
                                o.kind == render::SchemeOption::Kind::Integer;
            help += "\n    " + o.key + "=" + o.placeholder() + " (" +
                    (number ? o.describe() + ", " : "") + "default " + o.default_value +
                    "): " + o.help;
        }
    }
    return help;
}

// The memory, upload and decoding options `ridge view` and `ridge bench` share, bound to the
// renderer's options (whose values are the defaults shown).
inline void addStreamingOptions(CLI::App& command, render::RendererOptions& options)
{
    using Options = render::RendererOptions;
    command.add_option("--vram", options.vram_budget_mb, "Texture memory for resident patches, MB")
        ->capture_default_str()
        ->check(inRange("--vram", Options::kVramBudgetMbRange));
    command
        .add_option("--ram", options.ram_budget_mb,
                    "RAM caches of compressed and decoded patches, MB")
        ->capture_default_str()
        ->check(inRange("--ram", Options::kRamBudgetMbRange));
    command.add_option("--upload-mb", options.upload_budget_mb, "Per-frame upload budget, MB")
        ->capture_default_str()
        ->check(inRange("--upload-mb", Options::kUploadBudgetMbRange));
    command
        .add_option("--upload-ms", options.upload_budget_ms,
                    "Per-frame upload time budget, CPU ms: the floor of the adaptive budget")
        ->capture_default_str()
        ->check(inRange("--upload-ms", Options::kUploadBudgetMsRange));
    command
        .add_option("--upload-frame-fraction", options.upload_frame_fraction,
                    "Upload time budget as a fraction of the recent frame time (without "
                    "uploads), between --upload-ms and --upload-max-ms; 0: --upload-ms alone")
        ->capture_default_str()
        ->check(
            inRange("--upload-frame-fraction", stream::UploadTimeSettings::kFrameFractionRange));
    command
        .add_option("--upload-max-ms", options.upload_budget_max_ms,
                    "Ceiling of the adaptive upload time budget, ms")
        ->capture_default_str()
        ->check(inRange("--upload-max-ms", stream::UploadTimeSettings::kCeilingMsRange));
    command.add_flag_callback(
        "--cpu-decode", [&options] { options.gpu_reconstruction = false; },
        "Decode patches wholly on the CPU (default: codecs with a GPU half — progressive, "
        "jpeg2000, fractal — entropy-decode on the CPU and finish on the GPU)");
    command
        .add_option("--refine-steps", options.refine_steps_per_frame,
                    "Base incremental (fractal): iterations a frame that refine resident "
                    "patches decoded with fewer for their distance; 0: decode fully on arrival")
        ->capture_default_str()
        ->check(CLI::Range(0, Options::kMaxRefineStepsPerFrame));
    command
        .add_option("--arrival-frames", options.arrival_blend.max_frames,
                    "Longest fade of a patch that arrives over the ancestor that stood in for "
                    "it, frames; 0: it replaces the ancestor at once")
        ->capture_default_str()
        ->check(CLI::Range(0, lod::ArrivalBlendSettings::kMaxFrames));
    command
        .add_option("--arrival-px", options.arrival_blend.px_per_frame,
                    "How far a fading arrival may move on screen in a frame, pixels (its fade "
                    "lasts as many frames as its jump needs, up to --arrival-frames)")
        ->capture_default_str()
        ->check(inRange("--arrival-px", lod::ArrivalBlendSettings::kPxPerFrameRange));
    command.add_flag_callback(
        "--no-streaming", [&options] { options.streaming = false; },
        "Load every patch before drawing the frame that needs it (stalls)");
}

// --texel-size: the texture-detail criterion beside ε (render::RenderSettings::texel_px).
inline void addTexelSizeOption(CLI::App& command, double& texel_px)
{
    command
        .add_option("--texel-size", texel_px,
                    "Texture detail: shade from the finer levels under each drawn patch, down "
                    "to samples at most PX pixels apart on screen (colour and normals at about "
                    "one texel per pixel; fetched for shading, never drawn as triangles); 0 "
                    "disables it")
        ->capture_default_str()
        ->check(inRange("--texel-size", render::RenderSettings::kTexelPxRange));
}

// --exaggeration: render-time vertical exaggeration (render::RenderSettings::exaggeration).
inline void addExaggerationOption(CLI::App& command, double& exaggeration)
{
    command
        .add_option("--exaggeration", exaggeration,
                    "Vertical exaggeration: heights drawn this many times as tall (camera heights "
                    "are in the drawn space; ε holds on the exaggerated surface)")
        ->capture_default_str()
        ->check(inRange("--exaggeration", render::RenderSettings::kExaggerationRange));
}

// Which LOD rules: the tessellation rule and the coarse selection's bound.
inline void addLodRuleOptions(CLI::App& command, render::RenderSettings& settings)
{
    const std::map<std::string, lod::TessellationRule> rules = {
        {"conservative", lod::TessellationRule::Conservative},
        {"paper", lod::TessellationRule::Paper}};
    command
        .add_option("--tess-rule", settings.tessellation_rule,
                    "tess: conservative (ε on every sample, the default) or paper (Λ at edge "
                    "centres, interior the minimum of the edges)")
        ->transform(CLI::CheckedTransformer(rules, CLI::ignore_case))
        ->default_str("conservative");
    command.add_flag_callback(
        "--on-axis-bound", [&settings] { settings.side_on_bound = false; },
        "Coarse selection without the side-on factor (earlier releases' bound; with "
        "--tess-rule paper, their LOD)");
}

} // namespace ridge::cli
