// `ridge build INPUT -o OUT.ridge`: the options, the checks that come before any work (codec,
// band, vertical datum), the build, and what it says about the archive it wrote.
#include "command_text.h"
#include "commands.h"
#include "range_check.h"
#include "terminal.h"
#include "usage_error.h"

#include "ridge/codec/codec_registry.h"
#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/io/crs_summary.h"
#include "ridge/pipeline/info.h"
#include "ridge/pyramid/pyramid_geometry.h"
#include "ridge/pyramid/tessellation_block_errors.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdlib>

namespace ridge::cli {

namespace {

// --max-memory, MB: positive, and within what a byte count holds (1 PB).
constexpr ValueRange kMaxMemoryMbRange = ValueRange::openClosed(0.0, 1e9);

// A library message without its leading "NAME 'VALUE': " (the flag names it instead).
std::string afterColon(const std::string& message)
{
    const size_t colon = message.find(": ");
    return colon == std::string::npos ? message : message.substr(colon + 2);
}

// "Red, Green, Blue".
std::string joined(const std::vector<std::string>& names)
{
    std::string out;
    for (const std::string& name : names)
        out += (out.empty() ? "" : ", ") + name;
    return out;
}

} // namespace

void Commands::registerBuild(CLI::App& app)
{
    build_ =
        app.add_subcommand("build", "Build a .ridge archive from any elevation raster GDAL reads");
    build_->add_option("input", input_,
                       "Input raster (GeoTIFF, SRTM .hgt, PNG, ASCII grid, netCDF, ...); not "
                       "with --plan");
    build_
        ->add_option("-o,--output", output_,
                     "Output archive (.ridge), or the step's file with --plan")
        ->required();
    addBuildOptions(build_);
    registerShardSteps(build_); // shard_commands.cpp
    build_->add_flag("--json", json_, "Print the build's figures as JSON on stdout");
    addCommonFlags(build_, quiet_);
}

// The options of an archive's build, shared by `build` and `plan`.
void Commands::addBuildOptions(CLI::App* command)
{
    // Integers here; whether they are 2^n+1 and a power of two is validateBuildOptions'.
    command
        ->add_option("--patch", build_options_.patch_size,
                     "Patch size, 2^n+1 samples (65, 129, 257)")
        ->capture_default_str()
        ->check(inIntegerRange("--patch", 5, 4097));
    command
        ->add_option("--block", build_options_.block_cells,
                     "Tessellation block size in cells (power of two)")
        ->capture_default_str()
        ->check(inIntegerRange("--block", 2, 4096));
    command
        ->add_option("--codec", build_options_.codec,
                     "Patch codec, NAME[,KEY=VALUE...]:\n" + codecUsage())
        ->capture_default_str();
    command
        ->add_option("--criterion", criterion_,
                     "For codecs with a criterion option (jpeg2000): the compression criterion "
                     "every patch's rate search meets with E = --max-error: max (max-abs error, "
                     "default), rms (RMS error, with every sample also within 32 E), lossless "
                     "(D quantized, reversible wavelet)")
        ->check(CLI::IsMember({"max", "rms", "lossless"}));
    command
        ->add_option_function<std::string>(
            "--filter",
            [this](const std::string& name) { build_options_.filter = parseFilter(name.c_str()); },
            "Level filter: decimate (default), neville")
        ->check(CLI::IsMember({"decimate", "neville"}));
    command->add_flag(
        "--store-block-errors", build_options_.store_block_errors,
        "Store tessellation block errors in the archive (default: readers derive them "
        "from the decoded heights)");
    io::IngestOptions& ingest = build_options_.ingest;
    using Ingest = io::IngestOptions;
    command
        ->add_option_function<double>(
            "--max-error", [&ingest](double v) { ingest.max_error = v; },
            "Largest allowed height error in metres at the finest level, end to end "
            "(progressive codecs); with lossless codecs, the quantization step of non-integer "
            "input")
        ->check(inRange("--max-error", BuildOptions::kMaxErrorRange));
    command
        ->add_option_function<double>(
            "--spacing", [&ingest](double v) { ingest.spacing = v; },
            "Ground spacing in metres for rasters without georeferencing (default 1)")
        ->check(inRange("--spacing", Ingest::kSpacingRange));
    command
        ->add_option_function<double>(
            "--z-scale", [&ingest](double v) { ingest.z_scale = v; },
            "metres = value * z-scale + z-offset (replaces the band's own scale/unit)")
        ->check(magnitudeInRange("--z-scale", Ingest::kZScaleMagnitudeRange));
    command
        ->add_option_function<double>(
            "--z-offset", [&ingest](double v) { ingest.z_offset = v; }, "See --z-scale")
        ->check(inRange("--z-offset", Ingest::kZOffsetRange));
    command
        ->add_option_function<std::string>(
            "--fill-voids",
            [&ingest](const std::string& mode) { ingest.fill_voids = io::parseVoidFill(mode); },
            "Which nodata becomes terrain: interior (default: holes enclosed by data are "
            "filled, nodata connected to the raster border stays nodata), all, none")
        ->check(CLI::IsMember({"all", "interior", "none"}));
    command
        ->add_option_function<std::string>(
            "--sea-level",
            [&ingest](const std::string& text) {
                ingest.sea_level.reset();
                if (text != "none")
                    ingest.sea_level = *cli::detail::parseNumber(text); // checked below
            },
            "Water: valid samples at or below this height (metres, default 0) are water, decided "
            "on the source's exact values and stored per sample; 'none' for land below sea "
            "level (Death Valley, the Dead Sea) or a DEM whose 0 m is not the sea")
        ->check(CLI::Validator(
            [](std::string& text) -> std::string {
                if (text != "none")
                    (void)inRange("--sea-level", Ingest::kSeaLevelRange,
                                  "the height or 'none'")(text);
                return {};
            },
            "METRES|none"));
    command
        ->add_option("--water", ingest.water_layer,
                     "Water layer: any raster GDAL reads (samples other than 0 are water) or any "
                     "vector OGR reads (its features are water: lakes, reservoirs, rivers), "
                     "placed on the grid and added to --sea-level's water")
        ->type_name("FILE");
    command
        ->add_option_function<double>(
            "--max-memory",
            [this](double mb) {
                build_options_.memory_limit_bytes = uint64_t(mb * 1024.0 * 1024.0);
            },
            "Memory the build may use, MB (default: what the system has available); a raster "
            "whose estimated needs exceed it is refused before anything is allocated")
        ->check(inRange("--max-memory", kMaxMemoryMbRange));
    command
        ->add_option_function<int>(
            "-b,--band",
            [this, &ingest](int band) {
                ingest.band = band;
                band_given_ = true;
            },
            "The band that holds the heights, from 1 (gdal_translate's -b; default 1, with a "
            "warning naming it when the raster has several)")
        ->check(inIntegerRange("-b", 1, Ingest::kMaxBand));
    command
        ->add_option_function<std::string>(
            "--vertical-datum",
            [&ingest](const std::string& datum) {
                try {
                    io::resolveVerticalDatum(datum);
                } catch (const Error& e) {
                    throw UsageError("--vertical-datum " + datum + ": " + afterColon(e.what()));
                }
                ingest.vertical_datum = datum;
            },
            "What the heights are measured from, recorded in the archive and shown by info: an "
            "EPSG code of a vertical CRS (EPSG:5773 EGM96 height, EPSG:3855 EGM2008 height) or "
            "a name (default: the vertical part of the source's CRS, if it has one)")
        ->type_name("NAME_OR_EPSG");
    // gdalwarp's names: the target is always the ellipsoid, the default follows the datum.
    CLI::Option* vshift = command->add_flag_callback(
        "--vshift", [&ingest] { ingest.vertical_shift = io::VerticalShift::Ellipsoid; },
        "Shift heights above a geoid to heights above the ellipsoid through PROJ (h = H + N; "
        "default when the heights' vertical datum is a registered vertical CRS such as "
        "EPSG:5773 EGM96 height); an error when the datum is unknown or its grid is missing");
    command
        ->add_flag_callback(
            "--novshift", [&ingest] { ingest.vertical_shift = io::VerticalShift::None; },
            "Keep the heights as the source gives them, whatever their vertical datum")
        ->excludes(vshift);
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

io::RasterProbe Commands::checkBuildBeforeWork() const
{
    const std::string& codec = build_options_.codec;
    if (const std::string problem = codecSpecProblem(codec); !problem.empty())
        throw UsageError("--codec " + codec + ": " + problem);
    if (isLossyCodec(codec) && !build_options_.ingest.max_error)
        throw UsageError("--codec " + codec +
                         " needs --max-error METRES: the largest height error it may make, "
                         "end to end (e.g. --max-error 1)");
    if (const CodecInfo* info = findCodec(codec); info->unavailable)
        if (const std::string why = info->unavailable(codec); !why.empty())
            throw UsageError("--codec " + codec + " " + why);

    // The raster's bands, read without a sample (band 1 exists in any raster).
    io::IngestOptions first = build_options_.ingest;
    first.band = 1;
    io::RasterProbe probe = io::probeRaster(input_, first);
    const int bands = int(probe.band_names.size());
    const int band = build_options_.ingest.band;
    if (band > bands)
        throw UsageError(fmt::format(
            "-b {}: {} has {} (1..{})", band, input_,
            bands == 1 ? std::string("1 band") : fmt::format("{} bands", bands), bands));
    if (bands > 1 && !band_given_)
        fmt::print(stderr,
                   "ridge: warning: {} has {} bands ({}); the heights are read from band {} "
                   "({}); -b BAND chooses another\n",
                   input_, bands, joined(probe.band_names), band, probe.band_names[band - 1]);
    return probe;
}

// --criterion into the codec spec, the checks before any work, --max-error to the codec.
void Commands::settleBuildOptions()
{
    if (!criterion_.empty()) {
        // The codec's own option: a codec without one refuses the spec (an unknown codec is
        // refused below, by its own name).
        const std::string spec = build_options_.codec + ",criterion=" + criterion_;
        if (codecSpecProblem(build_options_.codec).empty()) {
            if (const std::string problem = codecSpecProblem(spec); !problem.empty())
                throw UsageError("--criterion " + criterion_ + ": " + problem);
            build_options_.codec = spec;
        }
    }
    validateBuildOptions();
    checkBuildBeforeWork();
    if (isLossyCodec(build_options_.codec)) {
        // One budget: the codec gets what the ingest quantization leaves of --max-error.
        build_options_.max_error = build_options_.ingest.max_error;
        build_options_.ingest.max_error.reset();
    }
}

int Commands::runBuild()
{
    if (!plan_path_.empty())
        return runShardStep(); // shard_commands.cpp
    if (input_.empty())
        throw UsageError("build: an INPUT raster is required (or --plan PLAN for a shard step)");
    settleBuildOptions();
    build_options_.progress = terminalProgress(quiet_ || json_);
    const BuildReport r = buildArchive(input_, output_, build_options_);
    // What the archive holds, as info reads it back: the source band's type and the code step
    // its heights were quantized to.
    const ArchiveInfo info = readArchiveInfo(output_);
    if (json_) {
        nlohmann::json j = {{"output", output_},
                            {"width", r.width},
                            {"height", r.height},
                            {"level_count", r.level_count},
                            {"patch_count", r.patch_count},
                            {"archive_bytes", r.archive_bytes},
                            {"band", info.band},
                            {"data_type", info.data_type},
                            {"voids_filled", r.voids_filled},
                            {"voids_kept", r.voids_kept},
                            {"fill_voids", io::voidFillName(build_options_.ingest.fill_voids)},
                            {"exact", info.exact},
                            {"quantization_step", info.quantization_step},
                            {"quantization_error", r.quantization_error},
                            {"vertical_datum", nullptr},
                            {"streamed", r.streamed},
                            {"seconds_total", r.seconds_total},
                            {"seconds_ingest", r.seconds_ingest},
                            {"seconds_errors", r.seconds_errors},
                            {"seconds_encode", r.seconds_encode}};
        if (info.vertical_datum)
            j["vertical_datum"] = info.vertical_datum->name;
        fmt::print("{}\n", jsonText(j));
        return 0;
    }
    if (quiet_)
        return 0;
    fmt::print("{}: {}x{} samples, {} levels, {} patches, {} ({:.2f} bits/sample), "
               "{} voids filled, {} kept as nodata, quantization error {:g} m\n",
               output_, r.width, r.height, r.level_count, r.patch_count,
               humanBytes(r.archive_bytes),
               8.0 * double(r.archive_bytes) / (double(r.width) * r.height), r.voids_filled,
               r.voids_kept, r.quantization_error);
    if (!info.exact)
        fmt::print("heights: {} band {} quantized to 16-bit codes, a step of {} (each height "
                   "within {} of the source; --max-error sets what is allowed)\n",
                   info.data_type, info.band, humanMetres(info.quantization_step),
                   humanMetres(r.quantization_error));
    fmt::print("time: {:.2f} s{}\n", r.seconds_total,
               r.streamed
                   ? " (streamed)"
                   : fmt::format(" (ingest {:.2f} s, error bounds {:.2f} s, encode+write {:.2f} s)",
                                 r.seconds_ingest, r.seconds_errors, r.seconds_encode));
    return 0;
}

} // namespace ridge::cli
