#include "commands.h"

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

namespace {

void addCommonFlags(CLI::App* cmd, bool& quiet)
{
    cmd->add_flag("-q,--quiet", quiet, "No progress output");
}

std::string humanBytes(uint64_t bytes)
{
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 4) {
        v /= 1024.0;
        ++u;
    }
    return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, units[u]);
}

// gdalinfo's "Corner Coordinates:" block: CRS numbers as it formats them, then DMS lon/lat.
void printCorners(const ArchiveInfo& info)
{
    if (info.corners.empty())
        return;
    fmt::print("Corner Coordinates:\n");
    for (const CornerInfo& c : info.corners) {
        const bool degrees = std::abs(c.x) < 181 && std::abs(c.y) < 91;
        std::string line = degrees ? fmt::format("{:<11} ({:12.7f},{:12.7f})", c.name, c.x, c.y)
                                   : fmt::format("{:<11} ({:12.3f},{:12.3f})", c.name, c.x, c.y);
        if (c.has_lon_lat)
            line += fmt::format(" ({},{})", io::formatDms(c.longitude, true),
                                io::formatDms(c.latitude, false));
        fmt::print("{}\n", line);
    }
    if (!info.lon_lat_note.empty())
        fmt::print("(no longitude/latitude: {})\n", info.lon_lat_note);
}

// gdalinfo -json's cornerCoordinates (CRS) and wgs84Extent, plus ridge's lon/lat per corner.
void addCornersJson(const ArchiveInfo& info, nlohmann::json& j)
{
    if (info.corners.empty())
        return;
    const char* keys[] = {"upperLeft", "lowerLeft", "upperRight", "lowerRight", "center"};
    nlohmann::json crs = nlohmann::json::object(), lon_lat = nlohmann::json::object();
    for (size_t k = 0; k < info.corners.size() && k < 5; ++k) {
        const CornerInfo& c = info.corners[k];
        crs[keys[k]] = {c.x, c.y};
        if (c.has_lon_lat)
            lon_lat[keys[k]] = {c.longitude, c.latitude};
    }
    j["cornerCoordinates"] = crs;
    if (lon_lat.size() == info.corners.size())
        j["cornerLonLat"] = lon_lat;
}

// --max-memory, MB: positive, and within what a byte count holds (1 PB).
constexpr ValueRange kMaxMemoryMbRange = ValueRange::openClosed(0.0, 1e9);

} // namespace

void Commands::registerAll(CLI::App& app)
{
    build_ =
        app.add_subcommand("build", "Build a .ridge archive from any elevation raster GDAL reads");
    build_
        ->add_option("input", input_,
                     "Input raster (GeoTIFF, SRTM .hgt, PNG, ASCII grid, netCDF, ...)")
        ->required();
    build_->add_option("-o,--output", output_, "Output archive (.ridge)")->required();
    // Integers here; whether they are 2^n+1 and a power of two is validateBuildOptions'.
    build_
        ->add_option("--patch", build_options_.patch_size,
                     "Patch size, 2^n+1 samples (65, 129, 257)")
        ->capture_default_str()
        ->check(inIntegerRange("--patch", 5, 4097));
    build_
        ->add_option("--block", build_options_.block_cells,
                     "Tessellation block size in cells (power of two)")
        ->capture_default_str()
        ->check(inIntegerRange("--block", 2, 4096));
    build_
        ->add_option(
            "--codec", build_options_.codec,
            "Patch codec: lossless, raw, progressive (lossy v2, needs --max-error), progressive-v1, "
            "progressive-paper, progressive,nested=K, jpeg2000 (the JPEG2000 paper's model, needs "
            "--max-error; jpeg2000,encoding=direct, jpeg2000,library=htj2k)")
        ->capture_default_str();
    build_
        ->add_option("--criterion", criterion_,
                     "jpeg2000 only: the compression criterion every patch's rate search meets "
                     "with E = --max-error: max (max-abs error, default), rms (RMS error, with "
                     "every sample also within 32 E), lossless (D quantized, reversible wavelet)")
        ->check(CLI::IsMember({"max", "rms", "lossless"}));
    build_
        ->add_option_function<std::string>(
            "--filter",
            [this](const std::string& name) { build_options_.filter = parseFilter(name.c_str()); },
            "Level filter: decimate (default), neville")
        ->check(CLI::IsMember({"decimate", "neville"}));
    build_->add_flag("--store-block-errors", build_options_.store_block_errors,
                     "Store tessellation block errors in the archive (default: readers derive them "
                     "from the decoded heights)");
    io::IngestOptions& ingest = build_options_.ingest;
    using Ingest = io::IngestOptions;
    build_
        ->add_option_function<double>(
            "--max-error", [&ingest](double v) { ingest.max_error = v; },
            "Largest allowed height error in metres at the finest level, end to end "
            "(progressive codecs); with lossless codecs, the quantization step of non-integer "
            "input")
        ->check(inRange("--max-error", BuildOptions::kMaxErrorRange));
    build_
        ->add_option_function<double>(
            "--spacing", [&ingest](double v) { ingest.spacing = v; },
            "Ground spacing in metres for rasters without georeferencing (default 1)")
        ->check(inRange("--spacing", Ingest::kSpacingRange));
    build_
        ->add_option_function<double>(
            "--z-scale", [&ingest](double v) { ingest.z_scale = v; },
            "metres = value * z-scale + z-offset (replaces the band's own scale/unit)")
        ->check(magnitudeInRange("--z-scale", Ingest::kZScaleMagnitudeRange));
    build_
        ->add_option_function<double>(
            "--z-offset", [&ingest](double v) { ingest.z_offset = v; }, "See --z-scale")
        ->check(inRange("--z-offset", Ingest::kZOffsetRange));
    build_
        ->add_option_function<std::string>(
            "--fill-voids",
            [&ingest](const std::string& mode) { ingest.fill_voids = io::parseVoidFill(mode); },
            "Which nodata becomes terrain: interior (default: holes enclosed by data are "
            "filled, nodata connected to the raster border stays nodata), all, none")
        ->check(CLI::IsMember({"all", "interior", "none"}));
    build_
        ->add_option_function<double>(
            "--max-memory",
            [this](double mb) {
                build_options_.memory_limit_bytes = uint64_t(mb * 1024.0 * 1024.0);
            },
            "Memory the build may use, MB (default: what the system has available); a raster "
            "whose estimated needs exceed it is refused before anything is allocated")
        ->check(inRange("--max-memory", kMaxMemoryMbRange));
    build_->add_flag("--json", json_, "Print the build's figures as JSON on stdout");
    addCommonFlags(build_, quiet_);

    info_ =
        app.add_subcommand("info", "Describe an archive: geometry, levels, codec, georeference");
    info_->add_option("archive", archive_, "Archive (.ridge)")->required();
    info_->add_flag("--json", json_, "Machine-readable output");

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
                    throw UsageError("--ot " + name + ": " +
                                     (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
                }
                return {};
            },
            "TYPE"));
    extract_->add_option("--of", extract_options_.output_format,
                         "Output format (GDAL's -of): a GDAL driver that writes")
        ->capture_default_str();
    extract_->add_option("--co", extract_options_.creation_options,
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
    extract_->add_option_function<double>(
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
}

int Commands::run()
{
    if (build_->parsed())
        return runBuild();
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
    return runHillshade();
}

// Checks the geometry options up front so the message names the option, not the input.
void Commands::validateBuildOptions() const
{
    try {
        const PyramidGeometry probe(2, 2, build_options_.patch_size);
    } catch (const Error& e) {
        throw UsageError(fmt::format("--patch {}: {}", build_options_.patch_size, e.what()));
    }
    const TessellationBlockLayout layout{build_options_.patch_size, build_options_.block_cells};
    if (!layout.valid())
        throw UsageError(
            fmt::format("--block {}: must be a power of two >= 2 dividing the patch's {} cells",
                        build_options_.block_cells, build_options_.patch_size - 1));
}

int Commands::runBuild()
{
    if (!criterion_.empty()) {
        if (build_options_.codec.rfind("jpeg2000", 0) != 0)
            throw UsageError("--criterion applies to --codec jpeg2000 only (the codec is " +
                             build_options_.codec + ")");
        build_options_.codec += ",criterion=" + criterion_;
    }
    validateBuildOptions();
    if (isLossyCodec(build_options_.codec)) {
        // One budget: the codec gets what the ingest quantization leaves of --max-error.
        build_options_.max_error = build_options_.ingest.max_error;
        build_options_.ingest.max_error.reset();
    }
    build_options_.progress = terminalProgress(quiet_ || json_);
    const BuildReport r = buildArchive(input_, output_, build_options_);
    if (json_) {
        const nlohmann::json j = {{"output", output_},
                                  {"width", r.width},
                                  {"height", r.height},
                                  {"level_count", r.level_count},
                                  {"patch_count", r.patch_count},
                                  {"archive_bytes", r.archive_bytes},
                                  {"voids_filled", r.voids_filled},
                                  {"voids_kept", r.voids_kept},
                                  {"fill_voids", io::voidFillName(build_options_.ingest.fill_voids)},
                                  {"quantization_error", r.quantization_error},
                                  {"streamed", r.streamed},
                                  {"seconds_total", r.seconds_total},
                                  {"seconds_ingest", r.seconds_ingest},
                                  {"seconds_errors", r.seconds_errors},
                                  {"seconds_encode", r.seconds_encode}};
        fmt::print("{}\n", jsonText(j));
    } else if (!quiet_)
        fmt::print(
            "{}: {}x{} samples, {} levels, {} patches, {} ({:.2f} bits/sample), "
            "{} voids filled, {} kept as nodata, quantization error {:g} m\n"
            "time: {:.2f} s{}\n",
            output_, r.width, r.height, r.level_count, r.patch_count, humanBytes(r.archive_bytes),
            8.0 * double(r.archive_bytes) / (double(r.width) * r.height), r.voids_filled,
            r.voids_kept, r.quantization_error, r.seconds_total,
            r.streamed
                ? " (streamed)"
                : fmt::format(" (ingest {:.2f} s, error bounds {:.2f} s, encode+write {:.2f} s)",
                              r.seconds_ingest, r.seconds_errors, r.seconds_encode));
    return 0;
}

int Commands::runInfo()
{
    const ArchiveInfo info = readArchiveInfo(archive_);
    if (json_) {
        nlohmann::json j = {
            {"path", info.path},
            {"format_version", info.format_version},
            {"file_bytes", info.file_bytes},
            {"width", info.width},
            {"height", info.height},
            {"patch_size", info.patch_size},
            {"level_count", info.level_count},
            {"block_cells", info.block_cells},
            {"block_levels", info.block_levels},
            {"patch_count", info.patch_count},
            {"codec", info.codec},
            {"filter", info.filter},
            {"height_scale", info.height_scale},
            {"height_offset", info.height_offset},
            {"quantization_error", info.quantization_error},
            {"spacing_x", info.spacing_x},
            {"spacing_y", info.spacing_y},
            {"min_height", info.min_height},
            {"max_height", info.max_height},
            {"metadata", nlohmann::json::parse(info.metadata_json)}, // checked by the reader
        };
        addCornersJson(info, j);
        for (const LevelInfo& l : info.levels)
            j["levels"].push_back({{"level", l.level},
                                   {"step", l.step},
                                   {"width", l.width},
                                   {"height", l.height},
                                   {"patches_x", l.patches_x},
                                   {"patches_y", l.patches_y},
                                   {"bytes", l.bytes},
                                   {"max_err", l.max_err},
                                   {"max_err_appr", l.max_err_appr},
                                   {"level_bound", l.level_bound}});
        fmt::print("{}\n", jsonText(j));
        return 0;
    }
    const archive::SourceMetadata& source = info.metadata.source;
    const archive::GeoreferenceMetadata& geo = info.metadata.georeference;
    fmt::print("Archive: {} (ridge format v{}, {})\n", info.path, info.format_version,
               humanBytes(info.file_bytes));
    fmt::print("Source: {} ({}, {} voids filled, {} kept as nodata, --fill-voids {})\n",
               source.path, source.data_type, source.voids_filled, source.voids_kept,
               source.fill_voids);
    fmt::print("Grid: {} x {} samples, spacing {:.3f} x {:.3f} m{}\n", info.width, info.height,
               info.spacing_x, info.spacing_y,
               geo.spacing_from_user ? " (given with --spacing or default 1, no georeferencing)"
                                     : "");
    fmt::print(
        "Heights: {:.2f} .. {:.2f} m, metres = {:g} + {:g} * code, quantization error {:g} m\n",
        info.min_height, info.max_height, info.height_offset, info.height_scale,
        info.quantization_error);
    fmt::print("Patches: {}x{} samples, {} levels, {} patches, tessellation blocks {}x{} cells (λ "
               "for d = 1..{})\n",
               info.patch_size, info.patch_size, info.level_count, info.patch_count,
               info.block_cells, info.block_cells, info.block_levels);
    fmt::print("Codec: {}, level filter: {}\n", info.codec, info.filter);
    if (geo.geotransform) {
        const std::array<double, 6>& gt = *geo.geotransform;
        fmt::print("Geotransform: ({:.9g}, {:.9g}, {:.9g}, {:.9g}, {:.9g}, {:.9g})\n", gt[0],
                   gt[1], gt[2], gt[3], gt[4], gt[5]);
    }
    const std::string& wkt = geo.crs_wkt;
    const auto name_start = wkt.find('"');
    const auto name_end =
        name_start == std::string::npos ? name_start : wkt.find('"', name_start + 1);
    fmt::print("CRS: {}\n",
               wkt.empty() ? "none" : wkt.substr(name_start + 1, name_end - name_start - 1));
    printCorners(info);
    fmt::print("\n{:>5} {:>6} {:>13} {:>11} {:>11} {:>12} {:>12}\n", "level", "step", "samples",
               "patches", "bytes", "max Err(P)", "δ_l");
    for (const LevelInfo& l : info.levels)
        fmt::print("{:>5} {:>6} {:>13} {:>11} {:>11} {:>10.3f} m {:>10.3f} m\n", l.level, l.step,
                   fmt::format("{}x{}", l.width, l.height),
                   fmt::format("{}x{}", l.patches_x, l.patches_y), humanBytes(l.bytes), l.max_err,
                   l.level_bound);
    return 0;
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
        nlohmann::json j = {{"output", output_},
                            {"format", options.output_format},
                            {"level", r.level},
                            {"srcwin", {r.window.x, r.window.y, r.window.width, r.window.height}},
                            {"type", r.output_type},
                            {"type_reason", r.type_reason},
                            {"max_rounding_error", r.max_rounding_error},
                            {"geotransform", r.geotransform ? nlohmann::json(*r.geotransform)
                                                            : nlohmann::json()}};
        fmt::print("{}\n", jsonText(j));
    } else if (!quiet_) {
        fmt::print("{}: {} {}x{} of level {} at {},{}, {} ({}){}\n", output_,
                   options.output_format, r.window.width, r.window.height, r.level, r.window.x,
                   r.window.y, r.output_type, r.type_reason,
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
