#pragma once
// How band 1 becomes 16-bit codes, strip by strip: shared by ingestRaster (whole grid, then
// void filling) and CodeRowReader (rows on demand, no filling).
#include "source_band.h"

#include "ridge/core/height_grid.h"
#include "ridge/core/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace ridge::io::detail {

// Peak GDAL block cache and strip buffer during ingest. Strips are aligned to the band's
// blocks, so every block is decoded once and the cache only has to hold the blocks being
// decoded: 4 MB keeps GTiff's multi-threaded decoding going (1 MB does not) and the peak
// RSS of the 10801x4801 Int16 mosaic at 1.47x its 16-bit size (32 MB: 1.70x).
constexpr int64_t kIngestCacheBytes = int64_t{4} << 20;
constexpr int64_t kStripBytes = int64_t{8} << 20;

// What the valid samples of the rows read so far look like.
struct CodeStats {
    int64_t valid = 0;
    uint16_t min_code = UINT16_MAX;
    uint16_t max_code = 0;
    double min_metres = INFINITY;
    double max_metres = -INFINITY;
    double max_error = 0.0; // largest |toMetres(code) - metres|

    void addCodes(uint16_t lo, uint16_t hi)
    {
        min_code = std::min(min_code, lo);
        max_code = std::max(max_code, hi);
    }
};

class CodeSource {
  public:
    virtual ~CodeSource() = default;

    // metres = offset + scale * code, scale > 0 (codes are mirrored when z_scale < 0).
    // max_error is left at 0: it is measured by reading.
    const HeightQuantization& quantization() const { return quantization_; }
    // Every valid sample is represented exactly (max_error will be 0).
    bool exact() const { return exact_; }
    // How values become codes, for sources that are not 8/16-bit integers (max_error left 0).
    virtual std::optional<CodeMapping> mapping() const { return std::nullopt; }
    // Bytes per sample of the strip that readRows needs internally (for strip sizing).
    virtual int stripSampleBytes() const = 0;

    // Reads rows [y0, y0 + rows) as codes into out[rows * width]. Appends the indices (into
    // `out`) of void samples to `voids`, leaving their codes unspecified, and adds the valid
    // samples to `stats`. `water`, when given (rows * width bytes), receives 1 where a valid
    // sample's source height is at or below the sea level (setSeaLevel), decided on the
    // source's exact value, else 0.
    virtual void readRows(int y0, int rows, uint16_t* out, std::vector<int64_t>& voids,
                          CodeStats& stats, uint8_t* water = nullptr) = 0;

    // The height rule of the water flags (IngestOptions::sea_level): metres, or none.
    void setSeaLevel(std::optional<double> metres) { sea_level_ = metres; }
    // The largest code whose height is at or below the sea level (−1: none is): the rule on
    // codes, exact for exact sources, and what void-filled samples are judged by.
    int32_t seaLevelCode() const;

  protected:
    HeightQuantization quantization_;
    bool exact_ = false;
    std::optional<double> sea_level_;
};

// 8- and 16-bit integer bands: exact, no pre-pass (code = stored value - type minimum).
bool hasDirectCodes(const SourceBand& band);
std::unique_ptr<CodeSource> makeDirectCodes(const SourceBand& band);

// Any other type: a strip-wise pre-pass (reported through `survey_progress`) finds the
// valid range and whether every value is an integer. Integers spanning at most 65536 values
// are exact; otherwise codes step 2 * max_error (or range / 65535 when unset) metres, and the
// top code is kept free when the band has voids (see void_fill.cpp). Throws Error when all
// samples are nodata or the range cannot meet max_error in 16 bits.
// With `planned`, no survey: its mapping is used, and readRows fails naming the file on a
// value it does not hold within its max_error.
std::unique_ptr<CodeSource> makeQuantizedCodes(const SourceBand& band,
                                               const std::optional<double>& max_error,
                                               const Progress& survey_progress,
                                               const CodeMapping* planned = nullptr);

} // namespace ridge::io::detail
