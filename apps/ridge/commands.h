#pragma once
// The subcommands of `ridge` and their options.
#include "render_args.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/extract.h"
#include "ridge/pipeline/hillshade.h"
#include "ridge/render/terrain_renderer.h"
#include "ridge/renderbench/render_bench.h"
#include "ridge/renderbench/view_bytes_bench.h"
#include "ridge/web/http_server.h"
#include "ridge/web/tile_writer.h"

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ridge::cli {

// `ridge codec-bench` (codec_bench_command.cpp): ridge's codec against the anchor codecs.
class CodecBenchCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string input_;
    std::vector<double> max_errors_{0.5, 1.0, 4.0, 16.0};
    int tile_size_ = 256;
    std::vector<std::string> ridge_codecs_{"progressive"}; // "all": every lossy codec
    bool overviews_ = false;                               // --overviews: anchors' pyramids too
    bool json_ = false;                                    // --json: the report on stdout
    std::string json_path_;                                // --json-file
    std::string plot_path_;
    bool quiet_ = false;
};

// `ridge bench` (bench_command.cpp): a renderer along a camera path, headless, with figures.
class BenchCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string archive_;
    std::string renderer_ = render::defaultLodScheme(); // --lod: a scheme spec
    std::string path_ = "flyover";
    double speed_ = 250.0;
    double height_above_ground_ = 300.0;
    int frames_ = 600;
    std::string size_ = "1920x1080";
    double error_ = 2.0;
    std::string frame_ = "auto"; // --frame
    double exaggeration_ = 1.0;  // --exaggeration
    double texel_px_ = render::RenderSettings{}.texel_px;
    render::RendererOptions renderer_options_ = render::RendererOptions::streamingDefaults();
    bool no_cull_ = false;
    bool popping_ = false;
    render::RenderSettings rules_; // --tess-rule, --on-axis-bound
    bool table_ = false;
    bool bytes_per_view_ = false; // GL-free: cold-cache bytes per frame, no rendering
    bool json_ = false;           // --json: the report on stdout
    std::string json_path_;       // --json-file
    std::string plot_path_;

    void writeOutputs(const renderbench::RenderBenchReport& report) const;
    int runBytesPerView(const renderbench::RenderBenchOptions& options) const;
};

// `ridge render` (render_command.cpp): one headless frame of an archive as a PNG.
class RenderCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string archive_;
    std::string output_;
    CameraArgs camera_args_;
    double fov_ = 60.0;
    std::string size_ = "1920x1080";
    double error_ = 2.0;
    double texel_px_ = render::RenderSettings{}.texel_px;
    std::string mode_ = "shaded";
    std::string lod_ = render::defaultLodScheme(); // --lod: a scheme spec
    bool wireframe_ = false;
    bool no_cull_ = false;
    bool no_skirts_ = false;
    bool no_fog_ = false;
    bool no_sky_ = false;
    int samples_ = 4;
    std::vector<double> sun_{315.0, 45.0};
    double vram_mb_ = 256.0;
    std::string frame_ = "auto"; // --frame
    double exaggeration_ = 1.0;  // --exaggeration
    bool json_ = false;
    bool quiet_ = false;
};

// `ridge view` (view_command.cpp): the interactive fly-through of an archive with the
// hardware-tessellation renderer and a Dear ImGui stats overlay. Needs a display; run() throws
// ridge::Error when there is none, or when the build has no viewer (RIDGE_HAVE_VIEWER=0).
class ViewCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string archive_;
    std::string size_ = "1600x900"; // window, screen coordinates
    double fov_y_degrees_ = 60.0;
    double epsilon_px_ = 2.0;
    double texel_px_ = render::RenderSettings{}.texel_px;
    double exaggeration_ = 1.0; // --exaggeration
    bool vsync_ = true;
    int frames_ = 0;               // > 0: render this many frames, then exit (smoke tests)
    std::string screenshot_;       // PNG of the last frame, read back before the final swap
    CameraArgs camera_args_;       // the starting camera, as `ridge render` takes it
    std::string mode_ = "shaded";  // --mode, as `ridge render` takes it
    std::vector<std::string> lod_; // --lod: the schemes L cycles through (specs)
    bool no_overlay_ = false;      // start with the overlay hidden (O shows it)
    bool orbit_ = false;           // start orbiting the globe (M switches)
    std::string frame_ = "auto";   // --frame, as `ridge render` takes it
    render::RendererOptions renderer_options_ = render::RendererOptions::streamingDefaults();
};

// `ridge query` (query_command.cpp): heights at points, GL-free (pipeline::HeightQuery).
class QueryCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string archive_;
    std::optional<double> x_, y_;
    bool lonlat_ = false, pixel_ = false, local_ = false;
    int level_ = -1;
    std::string resampling_ = "nearest";
    bool json_ = false;
};

// `ridge serve` (serve_command.cpp): archives as Cesium quantized-mesh tiles over HTTP, with
// the web pages, until SIGINT or SIGTERM.
class ServeCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::vector<std::string> archives_;
    web::HttpServerOptions http_;
    web::TileServiceOptions service_;
    std::string watermask_ = "nodata";
    double cache_mb_ = 64.0;
    std::string pages_; // --pages: empty, the bundled web/ when it exists
    bool no_pages_ = false;
    std::string heights_ = "ellipsoid";
    std::string vertical_datum_; // --vertical-datum EPSG:N
};

// `ridge tiles` (tiles_command.cpp): an archive's web tiles for static hosting, to a
// directory or a PMTiles file.
class TilesCommand {
  public:
    void registerWith(CLI::App& app);
    bool parsed() const { return command_ && command_->parsed(); }
    int run();

  private:
    CLI::App* command_ = nullptr;
    std::string archive_, output_;
    std::string format_ = "quantized-mesh";
    std::string image_ = "png";
    web::TileWriteOptions options_;
    std::string watermask_ = "nodata";
    bool quiet_ = false;
    bool json_ = false;
};

class Commands {
  public:
    // GDAL's single-dash spellings of extract's options ("-ot" for "--ot"): CLI11 takes one
    // letter after a single dash, so main rewrites these arguments before parsing.
    static constexpr const char* kGdalStyleFlags[] = {"-ot",       "-of",     "-co",
                                                      "-a_nodata", "-srcwin", "-projwin"};

    void registerAll(CLI::App& app);
    // Runs the subcommand that was parsed; returns the process exit code.
    int run();

  private:
    void registerBuild(CLI::App& app); // build_command.cpp
    void addBuildOptions(CLI::App* command);
    void settleBuildOptions();
    void registerInfo(CLI::App& app); // info_command.cpp
    // Sharded builds (shard_commands.cpp): `plan`, `build --plan` steps, `merge`.
    void registerShardSteps(CLI::App* build);
    void registerPlanAndMerge(CLI::App& app);
    int runShardStep();
    int runPlan();
    int runMerge();
    void validateBuildOptions() const;
    // What can be known wrong before reading a sample (UsageError): the codec's name and what
    // it needs (--max-error, RIDGE_ALLOW_HTJ2K), a band the raster lacks. Warns on stderr
    // when a raster of several bands is read without -b. Returns the raster's probe.
    io::RasterProbe checkBuildBeforeWork() const;
    int runBuild();
    int runInfo();
    int runVerify();
    int runExtract();
    int runHillshade();

    CLI::App* build_ = nullptr;
    CLI::App* info_ = nullptr;
    CLI::App* verify_ = nullptr;
    CLI::App* extract_ = nullptr;
    CLI::App* hillshade_ = nullptr;
    CLI::App* plan_ = nullptr;
    CLI::App* merge_ = nullptr;

    bool quiet_ = false;
    bool json_ = false;
    bool info_bytes_ = false; // info --bytes
    std::string criterion_;   // build --criterion (jpeg2000)
    std::string input_;
    std::string output_;
    std::string archive_;
    // build
    BuildOptions build_options_;
    bool band_given_ = false; // -b was given: no warning about other bands
    // plan, build --plan, merge
    std::vector<std::string> inputs_;
    std::string input_file_list_;
    int shard_level_ = -1;
    std::string plan_path_;
    int64_t shard_ = -1;
    bool shard_summary_ = false;
    bool coordinate_ = false;
    bool skip_unchanged_ = false;
    std::string observe_top_;
    std::string top_;
    std::vector<std::string> summaries_;
    std::vector<std::string> observations_;
    // verify
    std::string source_;
    // extract / hillshade
    int level_ = -1;
    std::vector<int> window_;
    std::vector<double> projwin_;
    std::string extract_type_;
    ExtractOptions extract_options_;
    HillshadeOptions hillshade_options_;
    CodecBenchCommand codec_bench_;
    ViewCommand view_;
    RenderCommand render_;
    BenchCommand bench_;
    QueryCommand query_;
    ServeCommand serve_;
    TilesCommand tiles_;
};

} // namespace ridge::cli
