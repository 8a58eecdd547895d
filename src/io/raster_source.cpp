// ingestRaster: open the heights' band, read it strip by strip into codes, fill voids, record
// georeferencing. ReferenceRaster: the same source as exact metres with NaN voids.
#include "ridge/io/raster_source.h"

#include "border_voids.h"
#include "code_source.h"
#include "georeference.h"
#include "source_band.h"
#include "void_fill.h"
#include "water_layer.h"

#include "ridge/core/error.h"
#include "ridge/core/sample_flag_bits.h"

#include <algorithm>
#include <memory>
#include <optional>

namespace ridge::io {

namespace {

// Reading takes most of an ingest; filling (when there are voids) the rest.
constexpr double kReadShare = 0.9;
// Share of reading that the pre-pass of non-16-bit types takes.
constexpr double kSurveyShare = 0.5;

// Records voids in a 1 byte/sample mask (0 = void) allocated at the first void.
class VoidMask {
  public:
    explicit VoidMask(int64_t samples) : samples_(samples) {}

    void mark(int64_t index)
    {
        if (mask_.empty())
            mask_.assign(static_cast<size_t>(samples_), 255);
        mask_[static_cast<size_t>(index)] = 0;
        ++count_;
    }
    int64_t count() const { return count_; }
    std::vector<uint8_t>& mask() { return mask_; }

  private:
    int64_t samples_;
    int64_t count_ = 0;
    std::vector<uint8_t> mask_;
};

// Flags the voids that filling turns into terrain (not `kept`, 1 = kept as nodata; empty:
// none kept) as kSampleFilled; before fillVoids, which consumes the void mask (0 = void).
void flagFilledVoids(const std::vector<uint8_t>& void_mask, const std::vector<uint8_t>& kept,
                     std::vector<uint8_t>& flags)
{
    for (size_t k = 0; k < void_mask.size(); ++k)
        if (void_mask[k] == 0 && (kept.empty() || !kept[k]))
            flags[k] |= kSampleFilled; // keeps the layer's water
}

// Completes the flags once voids are filled: a filled sample is judged water by its filled
// code (the sea level's rule on codes, `sea_code`: CodeSource::seaLevelCode) unless the
// layer said so already; kept nodata has no flag at all (it is not terrain). Returns the
// water samples; drops the flags when none is set.
int64_t finishFlags(std::vector<uint8_t>& flags, const CodeGrid& grid,
                    const std::vector<uint8_t>& kept, int32_t sea_code)
{
    int64_t water = 0;
    bool any = false;
    for (size_t k = 0; k < flags.size(); ++k) {
        if (!kept.empty() && kept[k])
            flags[k] = 0;
        else if ((flags[k] & kSampleFilled) && int32_t{grid.codes[k]} <= sea_code)
            flags[k] |= kSampleWater;
        water += (flags[k] & kSampleWater) != 0;
        any = any || flags[k] != 0;
    }
    if (!any)
        flags = {};
    return water;
}

} // namespace

ElevationRaster ingestRaster(const std::string& path, const IngestOptions& options)
{
    // Declared first so that it also catches what GDAL says while closing the dataset.
    detail::GdalErrorCapture capture;
    detail::ScopedCacheLimit cache_limit(detail::kIngestCacheBytes);
    const detail::SourceBand band(path, options);

    ElevationRaster raster;
    raster.source_path = path;
    raster.geo = detail::readGeoReference(band.dataset(), band.width(), band.height(), options);
    band.describeHeights(raster.geo);
    band.checkSpacing(raster.geo);
    raster.geo.vertical_units = band.verticalUnits();

    const bool direct = detail::hasDirectCodes(band);
    const double survey_end = direct ? 0.0 : kReadShare * kSurveyShare;
    const std::unique_ptr<detail::CodeSource> source =
        direct ? detail::makeDirectCodes(band)
               : detail::makeQuantizedCodes(band, options.max_error,
                                            subProgress(options.progress, 0.0, survey_end));
    source->setSeaLevel(options.sea_level);
    std::optional<detail::WaterLayer> layer;
    if (!options.water_layer.empty())
        layer.emplace(options.water_layer, raster.geo, band.width(), band.height());

    const int width = band.width();
    const int height = band.height();
    CodeGrid& grid = raster.grid;
    grid.width = width;
    grid.height = height;
    grid.codes.resize(static_cast<size_t>(width) * height);
    detail::CodeStats stats;
    VoidMask voids(int64_t{width} * height);
    std::vector<int64_t> strip_voids;
    // Water, decided on the source's values as they are read (one byte per sample; dropped
    // below when no sample is water).
    std::vector<uint8_t>& flags = raster.flags;
    flags.assign(static_cast<size_t>(width) * height, 0);
    std::vector<uint8_t> layer_rows;
    const int strip_rows = band.stripRows(detail::kStripBytes, source->stripSampleBytes());
    for (int y0 = 0; y0 < height; y0 += strip_rows) {
        const int rows = std::min(strip_rows, height - y0);
        const int64_t first = int64_t{y0} * width;
        strip_voids.clear();
        uint8_t* strip_flags = flags.data() + first;
        source->readRows(y0, rows, grid.codes.data() + first, strip_voids, stats, strip_flags);
        if (layer) {
            layer_rows.resize(static_cast<size_t>(rows) * width);
            layer->readRows(y0, rows, layer_rows.data());
            for (size_t k = 0; k < layer_rows.size(); ++k)
                strip_flags[k] |= layer_rows[k];
        }
        for (int64_t i : strip_voids)
            voids.mark(first + i);
        reportProgress(options.progress,
                       survey_end + (kReadShare - survey_end) * double(y0 + rows) / height);
    }
    if (stats.valid == 0)
        band.fail("all samples are nodata");

    // Which voids stay nodata is decided before filling (fillVoids consumes the mask). Their
    // codes are filled all the same, so that the pyramid, codecs and bounds run unchanged.
    int64_t kept = 0;
    if (voids.count() > 0 && options.fill_voids == VoidFill::Interior) {
        raster.nodata = detail::borderConnectedVoids(voids.mask(), width, height, kept);
    } else if (voids.count() > 0 && options.fill_voids == VoidFill::None) {
        raster.nodata.resize(voids.mask().size());
        for (size_t i = 0; i < raster.nodata.size(); ++i)
            raster.nodata[i] = voids.mask()[i] == 0;
        kept = voids.count();
    }
    if (kept == 0)
        raster.nodata = {};
    if (voids.count() > 0) {
        flagFilledVoids(voids.mask(), raster.nodata, flags);
        detail::fillVoids(path, grid, voids.mask(), stats.min_code, stats.max_code,
                          subProgress(options.progress, kReadShare, 1.0));
        voids.mask() = {};
    }
    const int64_t water_samples = finishFlags(flags, grid, raster.nodata, source->seaLevelCode());
    reportProgress(options.progress, 1.0);

    raster.quantization = source->quantization();
    raster.quantization.max_error = stats.max_error;
    IngestStats& out = raster.stats;
    out.data_type = band.dataTypeName();
    out.valid_samples = stats.valid;
    out.voids_filled = voids.count() - kept;
    out.voids_kept = kept;
    out.fill_voids = options.fill_voids;
    out.nodata = band.nodata();
    out.min_metres = stats.min_metres;
    out.max_metres = stats.max_metres;
    out.exact = source->exact() || stats.max_error == 0.0;
    out.z_scale = band.z().scale;
    out.z_offset = band.z().offset;
    out.water_samples = water_samples;
    return raster;
}

RasterProbe probeRaster(const std::string& path, const IngestOptions& options)
{
    detail::GdalErrorCapture capture;
    const detail::SourceBand band(path, options);
    RasterProbe probe;
    probe.width = band.width();
    probe.height = band.height();
    probe.data_type = band.dataTypeName();
    probe.direct_codes = detail::hasDirectCodes(band);
    probe.has_mask_band = band.hasMaskBand();
    probe.declares_nodata = band.nodata().has_value();
    probe.strip_extra_bytes_per_sample =
        (probe.direct_codes ? 0 : int(sizeof(double))) + (probe.has_mask_band ? 1 : 0);
    probe.block_cache_bytes = std::max(detail::kIngestCacheBytes, 2 * band.blockRowBytes());
    probe.band_names = band.bandNames();
    return probe;
}

struct ReferenceRaster::Impl {
    detail::SourceBand band;
    std::vector<uint8_t> mask_scratch;
    std::vector<double> undulations;
};

ReferenceRaster::ReferenceRaster(const std::string& path, const IngestOptions& options)
{
    detail::GdalErrorCapture capture;
    auto impl = std::make_unique<Impl>(Impl{detail::SourceBand(path, options), {}, {}});
    width_ = impl->band.width();
    height_ = impl->band.height();
    impl_ = impl.release();
}

ReferenceRaster::~ReferenceRaster()
{
    detail::GdalErrorCapture capture; // closing must not print
    delete impl_;
}

void ReferenceRaster::readRows(int y0, int rows, double* out, double* source_heights)
{
    if (y0 < 0 || rows < 0 || rows > height_ - y0)
        impl_->band.fail("rows " + std::to_string(y0) + "+" + std::to_string(rows) +
                         " are outside the raster's " + std::to_string(height_) + " rows");
    if (rows == 0)
        return;
    impl_->band.readValues(y0, rows, out, impl_->mask_scratch);
    impl_->band.readUndulations(y0, rows, impl_->undulations);
    const std::vector<double>& n = impl_->undulations;
    const detail::ZTransform& z = impl_->band.z();
    const size_t count = static_cast<size_t>(rows) * width_;
    for (size_t i = 0; i < count; ++i) {
        out[i] = z.toMetres(out[i]); // NaN voids stay NaN
        if (source_heights)
            source_heights[i] = out[i];
        if (!n.empty())
            out[i] += n[i];
    }
}

} // namespace ridge::io
