#include "commands.h"

#include "command_text.h"
#include "range_check.h"
#include "terminal.h"
#include "usage_error.h"

#include "ridge/codec/height_codec.h"
#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/io/geographic.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/info.h"
#include "ridge/pipeline/verify.h"
#include "ridge/pyramid/pyramid_geometry.h"
#include "ridge/pyramid/tessellation_block_errors.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace ridge::cli {

void Commands::registerAll(CLI::App& app)
{
    registerBuild(app);
    registerPlanAndMerge(app);
    registerInfo(app);

    verify_ =
        app.add_subcommand("verify", "Check checksums, decoding, shared borders and error bounds");
    verify_->add_option("archive", archive_, "Archive (.ridge)")->required();
    verify_->add_option("--source", source_,
                        "The raster the archive was built from: check the L-inf bound of every "
                        "level on every sample");
    verify_->add_flag("--json", json_, "Machine-readable output");
    addCommonFlags(verify_, quiet_);

    extract_ = app.add_subcommand(
        "extract", "Write a level (or a window of it) as a georeferenced raster, like "
                   "gdal_translate (-ot, -of, -co, -a_nodata, --srcwin, --projwin)");
    extract_->add_option("archive", archive_, "Archive (.ridge)")->required();
    extract_->add_option("-o,--output", output_, "Output raster")->required();
    extract_->add_option("--level", level_, "Level (default: finest)")
        ->check(inIntegerRange("--level", -1, ExtractOptions::kMaxLevel));
    const auto addWindow = [this](const std::string& name) {
        return extract_->add_option(name, window_, "XOFF YOFF XSIZE YSIZE in level samples")
            ->expected(4)
            ->type_name("XOFF YOFF XSIZE YSIZE")
            ->check(inIntegerRange("--srcwin", 0, INT32_MAX, "XOFF").application_index(0))
            ->check(inIntegerRange("--srcwin", 0, INT32_MAX, "YOFF").application_index(1))
            ->check(inIntegerRange("--srcwin", 1, INT32_MAX, "XSIZE").application_index(2))
            ->check(inIntegerRange("--srcwin", 1, INT32_MAX, "YSIZE").application_index(3));
    };
    CLI::Option* srcwin = addWindow("--srcwin");
    // --window: the name before the GDAL spelling, hidden, kept for scripts.
    CLI::Option* window = addWindow("--window")->group("")->excludes(srcwin);
    extract_
        ->add_option("--projwin", projwin_,
                     "ULX ULY LRX LRY in the archive's CRS (as gdal_translate -projwin)")
        ->expected(4)
        ->type_name("ULX ULY LRX LRY")
        ->check(inRange("--projwin", ValueRange::any(), "each coordinate"))
        ->excludes(srcwin)
        ->excludes(window);
    extract_
        ->add_option("--ot", extract_type_,
                     "Output data type (GDAL's -ot): Byte, UInt16, Int16, UInt32, Int32, "
                     "Float32, Float64 (default: the source's when it holds the heights without "
                     "loss, else Float32, else Float64; integer types round)")
        ->check(CLI::Validator(
            [](std::string& name) -> std::string {
                try {
                    name = io::sampleType(name).name;
                } catch (const Error& e) {
                    const std::string what = e.what(), prefix = "output_type '" + name + "': ";
                    throw UsageError(
                        "--ot " + name + ": " +
                        (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
                }
                return {};
            },
            "TYPE"));
    extract_
        ->add_option("--of", extract_options_.output_format,
                     "Output format (GDAL's -of): a GDAL driver that writes")
        ->capture_default_str();
    extract_
        ->add_option("--co", extract_options_.creation_options,
                     "NAME=VALUE creation option for the driver (GDAL's -co; repeatable)")
        ->expected(1)
        ->allow_extra_args(false) // one NAME=VALUE per -co, as GDAL has it
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->check(CLI::Validator(
            [](std::string& option) -> std::string {
                const size_t eq = option.find('=');
                if (eq == std::string::npos || eq == 0)
                    throw UsageError("--co " + option + ": expected NAME=VALUE");
                return {};
            },
            "NAME=VALUE"));
    extract_
        ->add_option_function<double>(
            "--a_nodata", [this](double v) { extract_options_.nodata_value = v; },
            "Nodata value of the output band (GDAL's -a_nodata)")
        ->check(inRange("--a_nodata", ValueRange::any()));
    extract_->add_flag("--json", json_,
                       "Print what was written (type, window, geotransform) as JSON on stdout");
    addCommonFlags(extract_, quiet_);

    hillshade_ = app.add_subcommand("hillshade", "Write a shaded-relief PNG of a level");
    hillshade_->add_option("archive", archive_, "Archive (.ridge)")->required();
    hillshade_->add_option("-o,--output", output_, "Output PNG")->required();
    hillshade_->add_option("--level", level_, "Level (default: finest)")
        ->check(inIntegerRange("--level", -1, HillshadeOptions::kMaxLevel));
    // --sun AZ,ALT as render has it; --azimuth and --altitude (gdaldem's words, the names
    // before) stay as hidden aliases for scripts.
    hillshade_
        ->add_option_function<std::vector<double>>(
            "--sun",
            [this](const std::vector<double>& sun) {
                hillshade_options_.azimuth = sun[0];
                hillshade_options_.altitude = sun[1];
            },
            "Sun azimuth (degrees clockwise from north) and altitude (degrees), e.g. 315,45 "
            "(default 315,45)")
        ->delimiter(',')
        ->expected(2)
        ->check(inRange("--sun", HillshadeOptions::kAzimuthDegreesRange, "the azimuth")
                    .application_index(0))
        ->check(inRange("--sun", HillshadeOptions::kAltitudeDegreesRange, "the altitude")
                    .application_index(1));
    hillshade_->add_option("--azimuth", hillshade_options_.azimuth, "Light azimuth, degrees")
        ->group("")
        ->check(inRange("--azimuth", HillshadeOptions::kAzimuthDegreesRange));
    hillshade_->add_option("--altitude", hillshade_options_.altitude, "Light altitude, degrees")
        ->group("")
        ->check(inRange("--altitude", HillshadeOptions::kAltitudeDegreesRange));
    hillshade_->add_option("-z,--z-factor", hillshade_options_.z_factor, "Vertical exaggeration")
        ->capture_default_str()
        ->check(inRange("--z-factor", HillshadeOptions::kZFactorRange));
    hillshade_->add_flag(
        "--grey", [this](int64_t) { hillshade_options_.colour = false; },
        "Grey shading only (like gdaldem)");
    addCommonFlags(hillshade_, quiet_);

    codec_bench_.registerWith(app);
    view_.registerWith(app);
    render_.registerWith(app);
    bench_.registerWith(app);
    query_.registerWith(app);
    serve_.registerWith(app);
    tiles_.registerWith(app);
}

int Commands::run()
{
    if (build_->parsed())
        return runBuild();
    if (plan_->parsed())
        return runPlan();
    if (merge_->parsed())
        return runMerge();
    if (info_->parsed())
        return runInfo();
    if (verify_->parsed())
        return runVerify();
    if (extract_->parsed())
        return runExtract();
    if (codec_bench_.parsed())
        return codec_bench_.run();
    if (view_.parsed())
        return view_.run();
    if (render_.parsed())
        return render_.run();
    if (bench_.parsed())
        return bench_.run();
    if (query_.parsed())
        return query_.run();
    if (serve_.parsed())
        return serve_.run();
    if (tiles_.parsed())
        return tiles_.run();
    return runHillshade();
}

int Commands::runVerify()
{
    VerifyOptions options;
    if (!source_.empty())
        options.source = source_;
    options.progress = terminalProgress(quiet_ || json_);
    const VerifyReport report = verifyArchive(archive_, options);
    if (json_) {
        nlohmann::json j = {{"archive", archive_},
                            {"ok", report.ok()},
                            {"patches_checked", report.patches_checked},
                            {"source_checked", report.source_checked},
                            {"source_voids", report.source_voids},
                            {"nodata_samples", report.nodata_samples},
                            {"problems", report.problems}};
        for (const LevelVerifyReport& l : report.levels)
            j["levels"].push_back({{"level", l.level},
                                   {"patches", l.patches},
                                   {"max_err_bound", l.max_err_bound},
                                   {"samples", l.samples},
                                   {"max_error", l.max_error},
                                   {"rms_error", l.rms_error},
                                   {"bound_violations", l.bound_violations},
                                   {"level_samples", l.level_samples},
                                   {"max_level_error", l.max_level_error},
                                   {"level_bound", l.level_bound},
                                   {"level_violations", l.level_violations}});
        fmt::print("{}\n", jsonText(j));
        return report.ok() ? 0 : 1;
    }
    if (!report.levels.empty()) {
        if (report.source_checked) {
            fmt::print("{:>5} {:>12} {:>12} {:>12} {:>12} {:>10} {:>14} {:>10}\n", "level",
                       "samples", "max |e| m", "RMS m", "max Err(P)", "over Err", "max |e| @lvl",
                       "δ_l");
            for (const LevelVerifyReport& l : report.levels)
                fmt::print("{:>5} {:>12} {:>12.4f} {:>12.4f} {:>12.4f} {:>10} {:>14} {:>10.4f}\n",
                           l.level, l.samples, l.max_error, l.rms_error, l.max_err_bound,
                           l.bound_violations,
                           l.level_samples ? fmt::format("{:.4f}", l.max_level_error) : "-",
                           l.level_bound);
            fmt::print("{} void samples of the source skipped (no measurement there), {} of "
                       "them kept as nodata by the archive\n",
                       report.source_voids, report.nodata_samples);
        } else {
            fmt::print("{:>5} {:>10} {:>12} {:>10}\n", "level", "patches", "max Err(P)", "δ_l");
            for (const LevelVerifyReport& l : report.levels)
                fmt::print("{:>5} {:>10} {:>10.4f} m {:>8.4f} m\n", l.level, l.patches,
                           l.max_err_bound, l.level_bound);
        }
    }
    for (const std::string& p : report.problems)
        fmt::print(stderr, "ridge: error: {}\n", p);
    if (!report.ok()) {
        fmt::print(stderr, "ridge: verify FAILED: {} problem(s)\n", report.problems.size());
        return 1;
    }
    fmt::print("{}: OK ({} patches{})\n", archive_, report.patches_checked,
               report.source_checked ? ", every error bound holds on every valid source sample"
                                     : "");
    return 0;
}

int Commands::runExtract()
{
    ExtractOptions options = extract_options_;
    options.level = level_;
    if (window_.size() == 4)
        options.window = ExtractWindow{window_[0], window_[1], window_[2], window_[3]};
    if (projwin_.size() == 4)
        options.projwin = ProjectionWindow{projwin_[0], projwin_[1], projwin_[2], projwin_[3]};
    if (!extract_type_.empty())
        options.output_type = extract_type_;
    options.progress = terminalProgress(quiet_ || json_);
    const ExtractReport r = extractLevel(archive_, output_, options);
    if (json_) {
        nlohmann::json j = {
            {"output", output_},
            {"format", options.output_format},
            {"level", r.level},
            {"srcwin", {r.window.x, r.window.y, r.window.width, r.window.height}},
            {"type", r.output_type},
            {"type_reason", r.type_reason},
            {"max_rounding_error", r.max_rounding_error},
            {"geotransform", r.geotransform ? nlohmann::json(*r.geotransform) : nlohmann::json()}};
        fmt::print("{}\n", jsonText(j));
    } else if (!quiet_) {
        fmt::print("{}: {} {}x{} of level {} at {},{}, {} ({}){}\n", output_, options.output_format,
                   r.window.width, r.window.height, r.level, r.window.x, r.window.y, r.output_type,
                   r.type_reason,
                   r.max_rounding_error > 0
                       ? fmt::format(", heights rounded by up to {:g} m", r.max_rounding_error)
                       : "");
    }
    return 0;
}

int Commands::runHillshade()
{
    hillshade_options_.level = level_;
    hillshade_options_.progress = terminalProgress(quiet_);
    writeHillshade(archive_, output_, hillshade_options_);
    return 0;
}

} // namespace ridge::cli
