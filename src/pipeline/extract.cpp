#include "ridge/pipeline/extract.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/parameter_check.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/level_decoder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace ridge {

namespace {

// The source's georeference as the archive recorded it (checked when the reader opened it).
io::GeoReference storedGeoReference(const archive::ArchiveReader& reader)
{
    const archive::GeoreferenceMetadata& stored = reader.metadata().georeference;
    io::GeoReference geo;
    geo.crs_wkt = stored.crs_wkt;
    geo.geographic = stored.geographic;
    geo.vertical_units = stored.vertical_units;
    geo.spacing_from_user = stored.spacing_from_user;
    if (stored.geotransform) {
        geo.has_geotransform = true;
        geo.geotransform = *stored.geotransform;
    }
    geo.spacing_x = reader.header().spacing_x;
    geo.spacing_y = reader.header().spacing_y;
    return geo;
}

// The geotransform of `level`'s sample grid: level pixel (i, j)'s centre is finest sample
// (i s, j s)'s centre, s the level's step.
std::array<double, 6> levelGeotransform(std::array<double, 6> gt, double s)
{
    const double a = 0.5 - 0.5 * s;
    gt[0] += a * gt[1] + a * gt[2];
    gt[3] += a * gt[4] + a * gt[5];
    for (int k : {1, 2, 4, 5})
        gt[k] *= s;
    return gt;
}

// `w` shifted to start at level pixel (x, y).
std::array<double, 6> shifted(std::array<double, 6> gt, int x, int y)
{
    gt[0] += x * gt[1] + y * gt[2];
    gt[3] += x * gt[4] + y * gt[5];
    return gt;
}

std::string describe(const ProjectionWindow& p)
{
    return "projwin " + formatNumber(p.ulx) + " " + formatNumber(p.uly) + " " +
           formatNumber(p.lrx) + " " + formatNumber(p.lry);
}

// gdal_translate's -projwin to -srcwin (nearest resampling, GDAL 3.6).
ExtractWindow projwinToWindow(const ProjectionWindow& p,
                              const std::optional<std::array<double, 6>>& level_gt)
{
    if (!level_gt)
        throw Error(describe(p) + ": the archive has no geotransform (its source was not "
                                  "georeferenced); give the window in samples");
    const std::array<double, 6>& gt = *level_gt;
    if (gt[2] != 0 || gt[4] != 0)
        throw Error(describe(p) + ": the archive's geotransform is rotated; give the window "
                                  "in samples");
    const double x = std::floor((p.ulx - gt[0]) / gt[1] + 0.001);
    const double y = std::floor((p.uly - gt[3]) / gt[5] + 0.001);
    const double w = std::floor((p.lrx - p.ulx) / gt[1] + 0.5);
    const double h = std::floor((p.lry - p.uly) / gt[5] + 0.5);
    const double limit = double(std::numeric_limits<int>::max());
    if (!(w >= 1 && h >= 1))
        throw Error(describe(p) + ": selects no whole pixel (" + formatNumber(w) + " x " +
                    formatNumber(h) + "; corners upper-left then lower-right)");
    if (!(std::abs(x) <= limit && std::abs(y) <= limit && w <= limit && h <= limit))
        throw Error(describe(p) + ": lies far outside the raster");
    return {int(x), int(y), int(w), int(h)};
}

// The type the heights are written in, and why; throws when a requested type cannot hold
// them. `values` are rounded to what the type stores.
io::SampleType chooseType(const ExtractOptions& options, const std::string& source_type,
                          const HeightQuantization& q, std::vector<double>& values,
                          ExtractReport& report)
{
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    const std::string heights = "heights [" + formatNumber(*lo) + ", " + formatNumber(*hi) + "] m";
    if (options.output_type) {
        const io::SampleType t = io::sampleType(*options.output_type);
        if (!(*lo >= t.lo && *hi <= t.hi) ||
            (t.integer && !(std::round(*lo) >= t.lo && std::round(*hi) <= t.hi)))
            throw Error("output_type " + t.name + " cannot hold the window's " + heights);
        report.type_reason = "requested";
        return t;
    }
    // Held without loss: an integer type stores each height exactly; a floating-point type
    // gives each archive code back unambiguously (within 1/1024 of the quantization step).
    const auto holds = [&](const io::SampleType& t) {
        for (const double v : values) {
            if (t.integer ? !t.holdsExactly(v) : !(v >= t.lo && v <= t.hi))
                return false;
            if (!t.integer && t.name == "Float32" &&
                std::abs(double(float(v)) - v) > q.scale / 1024)
                return false;
        }
        return true;
    };
    std::optional<io::SampleType> source;
    try {
        source = io::sampleType(source_type);
    } catch (const Error&) {
        // Not a type ridge writes (or none recorded): say so below.
    }
    // A floating-point source comes back in its own type, as gdal_translate writes it: the
    // heights to the source's own precision (Float32: within half a unit in the last place,
    // which max_rounding_error reports), not doubled in size as Float64.
    const bool in_range = source && std::all_of(values.begin(), values.end(), [&](double v) {
                              return v >= source->lo && v <= source->hi;
                          });
    if (source && ((!source->integer && in_range) || holds(*source))) {
        report.type_reason = "the source's type";
        return *source;
    }
    const io::SampleType fallback =
        holds(io::sampleType("Float32")) ? io::sampleType("Float32") : io::sampleType("Float64");
    report.type_reason = source ? "the source's " + source->name + " cannot hold the " + heights +
                                      (source->integer ? " exactly" : "")
                                : "the source's type '" + source_type + "' is not one ridge writes";
    return fallback;
}

} // namespace

void ExtractOptions::validate() const
{
    checkParameter("level", int64_t{level}, -1, kMaxLevel);
    if (window && projwin)
        throw Error("window and projwin: give one of them, not both");
    if (window) {
        checkParameter("window x", int64_t{window->x}, 0, INT32_MAX);
        checkParameter("window y", int64_t{window->y}, 0, INT32_MAX);
        checkParameter("window width", int64_t{window->width}, 1, INT32_MAX);
        checkParameter("window height", int64_t{window->height}, 1, INT32_MAX);
    }
    if (projwin) {
        const double corners[4] = {projwin->ulx, projwin->uly, projwin->lrx, projwin->lry};
        checkParameters("projwin", corners, 4, ValueRange::any());
        if (projwin->ulx == projwin->lrx || projwin->uly == projwin->lry)
            throw Error(describe(*projwin) + ": the window is empty");
    }
    if (nodata_value && !std::isnan(*nodata_value)) // NaN: floating-point types' nodata
        checkParameter("nodata_value", *nodata_value, ValueRange::any());
    if (output_format.empty())
        throw Error("output_format is empty: name a GDAL driver (GTiff, PNG, COG, ...)");
}

ExtractReport extractLevel(const std::string& archive_path, const std::string& output,
                           const ExtractOptions& options)
{
    options.validate();
    refuseOutputOverInput(output, {archive_path});
    // The driver and its options, before the work (with the type when it is known; the
    // nodata value is checked against the type chosen).
    io::checkRasterFormat({options.output_format, options.creation_options, {}},
                          io::sampleType(options.output_type.value_or("Float32")));
    checkOutputWritable(output); // before the work, not after it
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    ExtractReport report;
    report.level = resolveLevel(reader, options.level);
    const int level = report.level;
    if (level >= g.levelCount())
        throw Error("level " + std::to_string(level) + ": the archive has levels 0.." +
                    std::to_string(g.finestLevel()));
    io::GeoReference geo = storedGeoReference(reader);
    std::optional<std::array<double, 6>> level_gt;
    if (geo.has_geotransform)
        level_gt = levelGeotransform(geo.geotransform, double(g.step(level)));

    const int level_w = g.validLevelWidth(level), level_h = g.validLevelHeight(level);
    ExtractWindow w = options.window.value_or(ExtractWindow{0, 0, level_w, level_h});
    if (options.projwin)
        w = projwinToWindow(*options.projwin, level_gt);
    if (w.x < 0 || w.y < 0 || int64_t{w.x} + w.width > level_w || int64_t{w.y} + w.height > level_h)
        throw Error((options.projwin ? describe(*options.projwin) + " (samples " : "window (") +
                    std::to_string(w.x) + " " + std::to_string(w.y) + " " +
                    std::to_string(w.width) + " " + std::to_string(w.height) +
                    ") reaches outside level " + std::to_string(level) + "'s " +
                    std::to_string(level_w) + " x " + std::to_string(level_h) + " samples");
    report.window = w;

    std::vector<uint8_t> valid; // empty: every sample is data (validity masks, io::VoidFill)
    const CodeGrid grid = decodeLevelWindow(reader, level, w.x, w.y, w.width, w.height,
                                            subProgress(options.progress, 0.0, 0.8), &valid);
    const HeightQuantization q = reader.quantization();
    std::vector<double> metres(grid.codes.size());
    for (size_t i = 0; i < metres.size(); ++i)
        metres[i] = q.toMetres(grid.codes[i]);
    const auto isData = [&valid](size_t i) { return valid.empty() || valid[i] != 0; };
    // The type must hold the heights, not the filled codes under kept nodata.
    std::vector<double> heights;
    if (valid.empty()) {
        heights = metres;
    } else {
        for (size_t i = 0; i < metres.size(); ++i)
            if (isData(i))
                heights.push_back(metres[i]);
    }
    const bool has_nodata = heights.size() < metres.size();
    if (heights.empty())
        heights.push_back(0.0); // all nodata: any type holds the (absent) heights

    const io::SampleType type =
        chooseType(options, reader.metadata().source.data_type, q, heights, report);
    report.output_type = type.name;
    for (size_t i = 0; i < metres.size(); ++i) {
        double& v = metres[i];
        const double stored = type.integer             ? std::round(v)
                              : type.name == "Float32" ? double(float(v))
                                                       : v;
        if (isData(i))
            report.max_rounding_error = std::max(report.max_rounding_error, std::abs(stored - v));
        v = stored;
    }
    // Where the archive keeps nodata: the value asked for, else the source's declared one,
    // else NaN (floating-point types) or the type's lowest value (integer types).
    std::optional<double> nodata = options.nodata_value;
    if (!nodata && has_nodata) {
        nodata = reader.metadata().source.nodata;
        if (nodata && !(type.integer ? type.holdsExactly(*nodata)
                                     : (*nodata >= type.lo && *nodata <= type.hi)))
            nodata.reset(); // the source's value does not fit this type
        if (!nodata)
            nodata = type.integer ? type.lo : std::numeric_limits<double>::quiet_NaN();
    }
    if (nodata) {
        size_t clashes = 0;
        for (size_t i = 0; i < metres.size(); ++i) {
            if (!isData(i))
                metres[i] = *nodata;
            else
                clashes += metres[i] == *nodata; // never for NaN
        }
        if (clashes)
            throw Error("nodata_value " + formatNumber(*nodata) + " is the height of " +
                        std::to_string(clashes) +
                        " extracted samples; choose a value no height has");
    }
    if (level_gt) {
        geo.geotransform = shifted(*level_gt, w.x, w.y);
        report.geotransform = geo.geotransform;
    }
    io::writeRaster(output, metres, grid.width, grid.height, type, geo,
                    {options.output_format, options.creation_options, nodata}, {archive_path});
    reportDone(options.progress); // published: too late to cancel
    return report;
}

} // namespace ridge
