// `ridge bench ARCHIVE`: a renderer flown along a camera path, headless; prints the summary,
// writes the optional JSON and frame-time plot.
#include "commands.h"
#include "range_check.h"
#include "render_args.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/pipeline/terrain_georeference.h"
#include "ridge/renderbench/render_bench.h"

#include <fmt/core.h>

#include <numbers>

#include <memory>

namespace ridge::cli {

void BenchCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "bench",
        "Fly a renderer along a camera path headless and report fps, frame times, triangles");
    command_->add_option("archive", archive_, "Archive (.ridge)")->required();
    command_->add_option("--lod", renderer_, lodSchemeHelp())
        ->capture_default_str()
        ->check(lodSpecCheck("--lod"));
    // --renderer: the name before the schemes were unified with render's --lod; hidden, kept
    // for scripts (docs/PERF.md's runs use it).
    command_->add_option("--renderer", renderer_, "Same as --lod")
        ->group("")
        ->check(lodSpecCheck("--lod"));
    command_
        ->add_option("--path", path_,
                     "flyover, orbit, teleport, or a file of 'x y z look-x look-y look-z' lines")
        ->capture_default_str();
    command_
        ->add_option("--speed", speed_,
                     "Camera speed along the path, m/s (60 frames per simulated s)")
        ->capture_default_str()
        ->check(inRange("--speed", lod::CameraPathSettings::kSpeedMpsRange));
    command_
        ->add_option("--height-above-ground", height_above_ground_,
                     "Metres above the ground (flyover, teleport): below the highest peak, the "
                     "hole count judges a frame from the surface drawn under the camera")
        ->capture_default_str()
        ->check(inRange("--height-above-ground", lod::CameraPathSettings::kHeightAboveGroundRange));
    command_->add_option("--frames", frames_, "Frames to render")
        ->capture_default_str()
        ->check(inIntegerRange("--frames", 1, lod::CameraPathSettings::kMaxFrames));
    command_->add_option("--size", size_, "Frame size WIDTHxHEIGHT")->capture_default_str();
    command_->add_option("--error", error_, "Screen-space error threshold ε, pixels")
        ->capture_default_str()
        ->check(inRange("--error", render::RenderSettings::kEpsilonPxRange));
    addTexelSizeOption(*command_, texel_px_);
    addExaggerationOption(*command_, exaggeration_);
    addStreamingOptions(*command_, renderer_options_);
    addFrameOption(*command_, frame_);
    addLodRuleOptions(*command_, rules_);
    command_->add_flag("--popping", popping_,
                       "Measure popping per frame (the surface's displacement from LOD changes "
                       "alone, px; two extra captures a frame, so time a run without it)");
    command_->add_flag("--no-cull", no_cull_, "Disable view-frustum culling");
    command_->add_flag(
        "--table", table_,
        "Run every registered scheme with its default options, with and without frustum "
        "culling, and print the fractal-rings paper's Table 1, each frame loaded in full "
        "first (--lod, --no-cull and streaming are then ignored); with a fractal archive, "
        "also each scheme's \"incremental\" row (the paper's Base incremental: streamed, "
        "decoded on the GPU, far patches with fewer iterations refined as they near)");
    command_->add_flag(
        "--bytes-per-view", bytes_per_view_,
        "Render nothing (no GL): for each frame of the path, the bytes a cold cache reads to "
        "draw and shade it (the tessellation scheme's selection at --error and its texture "
        "detail at --texel-size; with a progressive archive every ancestor too); "
        "near/mid/far = first/middle/last frame, "
        "min/median/max, and the whole path's patches together (--plot is not written)");
    command_->add_flag("--json", json_,
                       "Print every frame's figures as JSON on stdout (the summary then goes to "
                       "stderr)");
    command_->add_option("--json-file", json_path_,
                         "Write every frame's figures as JSON to a file");
    command_->add_option("--plot", plot_path_, "Write the frame times as a PNG");
}

int BenchCommand::run()
{
    // Before the run, not after minutes of it.
    for (const std::string& out : {json_path_, plot_path_})
        if (!out.empty()) {
            refuseOutputOverInput(out, {archive_, path_}); // path_: maybe a pose file
            checkOutputWritable(out);
        }
    // --json: the document alone on stdout, the human summary on stderr.
    std::FILE* human = json_ ? stderr : stdout;
    renderbench::RenderBenchOptions options;
    options.renderer = renderer_options_;
    options.renderer.frame = parseFrameChoice(frame_);
    options.scheme = renderer_; // a spec, checked by --lod's validator
    options.path.kind = path_;
    // "lonlat" poses in a path file: WGS 84 through the archive's CRS (PROJ) on a plane,
    // on the globe straight onto its ellipsoid.
    const archive::ArchiveReader reader(archive_);
    auto geo = std::make_shared<const TerrainGeoreference>(reader);
    const lod::TerrainFrame frame = lod::terrainFrameOf(reader, options.renderer.frame, archive_);
    if (frame.onEllipsoid())
        options.path.from_lon_lat = [geo, frame](double lon, double lat, double height) {
            (void)geo->toLocal({lon, lat}, PointSpace::LonLat); // ranges checked by name
            constexpr double kDeg = std::numbers::pi / 180.0;
            return lod::geodeticToEcef(frame.geodetic().ellipsoid, lon * kDeg, lat * kDeg, height);
        };
    else if (geo->hasCrs())
        options.path.from_lon_lat = [geo](double lon, double lat, double height) {
            const glm::dvec2 local = geo->toLocal({lon, lat}, PointSpace::LonLat);
            return glm::dvec3(local.x, local.y, height);
        };
    options.path.speed_mps = speed_;
    options.path.height_above_ground = height_above_ground_;
    options.frames = frames_;
    options.viewport = parseSize(size_);
    options.epsilon_px = error_;
    options.texel_px = texel_px_;
    options.exaggeration = exaggeration_;
    options.cull = !no_cull_;
    options.measure_popping = popping_;
    options.tessellation_rule = rules_.tessellation_rule;
    options.side_on_bound = rules_.side_on_bound;
    if (bytes_per_view_)
        return runBytesPerView(options);
    if (table_) {
        std::vector<renderbench::RenderBenchReport> reports;
        std::string refused; // schemes that cannot draw this archive (rings: small patches)
        for (const std::string& scheme : render::lodSchemeNames())
            for (const bool cull : {true, false}) {
                renderbench::RenderBenchOptions o = options;
                o.scheme = scheme;
                o.cull = cull;
                // Like the paper's table: every patch at its full detail before its frame, so
                // the rows compare the schemes, not how far streaming got.
                o.renderer.streaming = false;
                try {
                    reports.push_back(renderbench::runRenderBench(archive_, o));
                } catch (const Error& e) {
                    if (!cull)
                        continue;
                    refused += fmt::format("{}: not run: {}\n", scheme, e.what());
                }
            }
        // The paper's "Base incremental" row, for an archive whose codec refines in place
        // (the fractal codec): each scheme streamed with GPU decoding, far patches decoded with
        // fewer iterations and refined as the camera approaches. Schemes that need codes on
        // the CPU decode fully there: no row.
        if (reader.codec().capabilities().gpu.refinable)
            for (const std::string& scheme : render::lodSchemeNames()) {
                renderbench::RenderBenchOptions o = options;
                o.scheme = scheme;
                o.cull = true;
                o.renderer.streaming = true;
                o.renderer.gpu_reconstruction = true;
                try {
                    renderbench::RenderBenchReport r = renderbench::runRenderBench(archive_, o);
                    if (r.reconstructed > 0)
                        reports.push_back(std::move(r));
                    else
                        refused +=
                            fmt::format("{} incremental: not run: it decodes on the CPU\n", scheme);
                } catch (const Error& e) {
                    refused += fmt::format("{} incremental: not run: {}\n", scheme, e.what());
                }
            }
        if (reports.empty())
            throw Error(archive_ + ": no LOD scheme could draw it\n" + refused);
        fmt::print(human, "{}: path {}, {} frames at {}x{}, ε {} px, {}\n{}{}", archive_, path_,
                   frames_, options.viewport.width, options.viewport.height, error_,
                   reports.front().gl_renderer, renderbench::formatRenderBenchTable(reports),
                   refused);
        writeOutputs(reports.front());
        return 0;
    }
    const renderbench::RenderBenchReport report = renderbench::runRenderBench(archive_, options);
    fmt::print(human, "{}", renderbench::formatRenderBenchSummary(report));
    writeOutputs(report);
    return 0;
}

int BenchCommand::runBytesPerView(const renderbench::RenderBenchOptions& options) const
{
    const renderbench::ViewBytesBenchReport report =
        renderbench::runViewBytesBench(archive_, options);
    fmt::print(json_ ? stderr : stdout, "{}", renderbench::formatViewBytesSummary(report));
    if (json_)
        fmt::print("{}", renderbench::formatViewBytesJson(report));
    if (!json_path_.empty())
        renderbench::writeViewBytesJson(report, json_path_);
    return 0;
}

void BenchCommand::writeOutputs(const renderbench::RenderBenchReport& report) const
{
    if (json_)
        fmt::print("{}", renderbench::formatRenderBenchJson(report));
    if (!json_path_.empty())
        renderbench::writeRenderBenchJson(report, json_path_);
    if (!plot_path_.empty())
        renderbench::writeRenderBenchPlot(report, plot_path_);
}

} // namespace ridge::cli
