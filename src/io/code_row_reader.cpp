// CodeRowReader: band 1 as codes, rows on demand, quantized exactly as ingestRaster does.
#include "ridge/io/raster_source.h"

#include "code_source.h"
#include "georeference.h"
#include "source_band.h"
#include "water_layer.h"

#include "ridge/core/error.h"
#include "ridge/core/sample_flag_bits.h"

#include <algorithm>
#include <memory>
#include <optional>

namespace ridge::io {

namespace {

// Share of construction that the pre-pass of non-16-bit types takes; the error measurement
// pass takes the rest.
constexpr double kSurveyShare = 0.5;

} // namespace

struct CodeRowReader::Impl {
    detail::SourceBand band;
    GeoReference geo;
    std::unique_ptr<detail::CodeSource> source;
    HeightQuantization quantization;
    bool exact = false;
    detail::CodeStats stats;   // rows read through readRows, each row once
    std::vector<bool> counted; // rows whose samples `stats` holds
    std::vector<int64_t> void_scratch;
    std::optional<double> sea_level;
    std::optional<detail::WaterLayer> layer; // IngestOptions::water_layer
    std::vector<uint8_t> layer_rows;
    int64_t water_samples = 0; // over the rows `stats` holds

    Impl(const std::string& path, const IngestOptions& options) : band(path, options)
    {
        geo = detail::readGeoReference(band.dataset(), band.width(), band.height(), options);
        band.describeHeights(geo);
        band.checkSpacing(geo);
        geo.vertical_units = band.verticalUnits();
    }

    // The cache limit for one call: the blocks of the row where two calls' strips meet must
    // survive from one call to the next, nothing more.
    int64_t cacheLimit() const
    {
        return std::max(detail::kIngestCacheBytes, 2 * band.blockRowBytes());
    }

    // ingestRaster measures the quantization error while it reads; a reader that hands out
    // rows on demand has to measure it up front, in a pass of its own.
    double measureError(const Progress& progress)
    {
        const int width = band.width();
        const int height = band.height();
        const int strip_rows = band.stripRows(detail::kStripBytes, source->stripSampleBytes());
        std::vector<uint16_t> codes(static_cast<size_t>(strip_rows) * width);
        detail::CodeStats measured;
        for (int y0 = 0; y0 < height; y0 += strip_rows) {
            const int rows = std::min(strip_rows, height - y0);
            void_scratch.clear();
            source->readRows(y0, rows, codes.data(), void_scratch, measured);
            reportProgress(progress, double(y0 + rows) / height);
        }
        return measured.max_error;
    }
};

CodeRowReader::CodeRowReader(const std::string& path, const IngestOptions& options)
{
    detail::GdalErrorCapture capture;
    auto impl = std::make_unique<Impl>(path, options);
    detail::ScopedCacheLimit cache_limit(impl->cacheLimit());
    const detail::SourceBand& band = impl->band;
    if (detail::hasDirectCodes(band)) {
        impl->source = detail::makeDirectCodes(band);
    } else {
        impl->source = detail::makeQuantizedCodes(
            band, options.max_error, subProgress(options.progress, 0.0, kSurveyShare),
            options.code_mapping ? &*options.code_mapping : nullptr);
    }
    impl->quantization = impl->source->quantization();
    impl->exact = impl->source->exact();
    const bool planned = options.code_mapping && !detail::hasDirectCodes(band);
    if (planned) { // the whole raster's error, measured when the mapping was made
        impl->quantization.max_error = options.code_mapping->quantization.max_error;
        impl->exact = impl->quantization.max_error == 0.0;
    }
    impl->sea_level = options.sea_level;
    impl->source->setSeaLevel(options.sea_level);
    if (!options.water_layer.empty())
        impl->layer.emplace(options.water_layer, impl->geo, band.width(), band.height());
    if (!impl->exact && !planned) {
        impl->quantization.max_error =
            impl->measureError(subProgress(options.progress, kSurveyShare, 1.0));
        impl->exact = impl->quantization.max_error == 0.0;
    }
    reportProgress(options.progress, 1.0);
    impl_ = impl.release();
}

CodeRowReader::~CodeRowReader()
{
    detail::GdalErrorCapture capture; // closing must not print
    delete impl_;
}

int CodeRowReader::width() const
{
    return impl_->band.width();
}

int CodeRowReader::height() const
{
    return impl_->band.height();
}

const HeightQuantization& CodeRowReader::quantization() const
{
    return impl_->quantization;
}

std::optional<CodeMapping> CodeRowReader::codeMapping() const
{
    std::optional<CodeMapping> m = impl_->source->mapping();
    if (m)
        m->quantization.max_error = impl_->quantization.max_error;
    return m;
}

const GeoReference& CodeRowReader::geo() const
{
    return impl_->geo;
}

bool CodeRowReader::flagsWater() const
{
    return impl_->sea_level.has_value() || impl_->layer.has_value();
}

int64_t CodeRowReader::readRows(int y0, int rows, uint16_t* out, uint8_t* flags)
{
    const int height = impl_->band.height();
    if (y0 < 0 || rows < 0 || rows > height - y0)
        impl_->band.fail("rows " + std::to_string(y0) + "+" + std::to_string(rows) +
                         " are outside the raster's " + std::to_string(height) + " rows");
    if (rows == 0)
        return 0;
    detail::GdalErrorCapture capture;
    detail::ScopedCacheLimit cache_limit(impl_->cacheLimit());
    impl_->void_scratch.clear();
    // Strips that share a row (the streaming build's overlap) must not count it twice in
    // stats(): runs of rows already counted are read against a scratch tally.
    std::vector<bool>& counted = impl_->counted;
    counted.resize(static_cast<size_t>(height), false);
    const size_t width = static_cast<size_t>(impl_->band.width());
    int64_t voids = 0;
    for (int first = y0, end = y0 + rows; first < end;) {
        const bool seen = counted[static_cast<size_t>(first)];
        int last = first + 1;
        while (last < end && counted[static_cast<size_t>(last)] == seen)
            ++last;
        detail::CodeStats again;
        const size_t offset = static_cast<size_t>(first - y0) * width;
        const size_t count = static_cast<size_t>(last - first) * width;
        uint8_t* run_flags = flags ? flags + offset : nullptr;
        impl_->source->readRows(first, last - first, out + offset, impl_->void_scratch,
                                seen ? again : impl_->stats, run_flags);
        if (run_flags && impl_->layer) {
            impl_->layer_rows.resize(count);
            impl_->layer->readRows(first, last - first, impl_->layer_rows.data());
            for (size_t k = 0; k < count; ++k)
                run_flags[k] |= impl_->layer_rows[k];
            for (int64_t v : impl_->void_scratch) // voids are not terrain: no flag
                run_flags[v] = 0;
        }
        if (run_flags && !seen)
            impl_->water_samples += std::count(run_flags, run_flags + count, kSampleWater);
        voids += static_cast<int64_t>(impl_->void_scratch.size());
        impl_->void_scratch.clear();
        std::fill(counted.begin() + first, counted.begin() + last, true);
        first = last;
    }
    return voids;
}

IngestStats CodeRowReader::stats() const
{
    const detail::CodeStats& s = impl_->stats;
    IngestStats out;
    out.data_type = impl_->band.dataTypeName();
    out.valid_samples = s.valid;
    out.voids_filled = 0;
    out.nodata = impl_->band.nodata();
    out.min_metres = s.valid > 0 ? s.min_metres : 0.0;
    out.max_metres = s.valid > 0 ? s.max_metres : 0.0;
    out.exact = impl_->exact;
    out.z_scale = impl_->band.z().scale;
    out.z_offset = impl_->band.z().offset;
    out.water_samples = impl_->water_samples;
    return out;
}

} // namespace ridge::io
