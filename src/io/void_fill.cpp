#include "void_fill.h"

#include "gdal_support.h"

#include "ridge/core/error.h"

#include <cpl_string.h>
#include <gdal_alg.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <exception>
#include <filesystem>
#include <optional>

namespace ridge::io::detail {

namespace {

// GDALFillNodata keeps three full-size work rasters (5 bytes per sample for 16-bit codes).
// Up to this many samples they stay in memory; above, they go to compressed temporary
// GeoTIFFs so that filling a huge raster does not double its memory.
constexpr int64_t kInMemoryWorkSamples = int64_t{16} << 20;

// Inverse distance weighting from four quadrants leaves creases where the nearest valid
// sample of a quadrant switches between neighbouring void samples; two 3x3 averaging passes
// over the filled samples remove them (they would show in hillshades and cost codec bits)
// without flattening large voids, and averaging cannot leave the range of the void's border.
constexpr int kSmoothingIterations = 2;

// How far (in samples) one GDALFillNodata pass looks for valid samples. GDAL scans this far
// for every void sample that has an empty quadrant, so a raster-wide distance makes a void
// along an edge (sea, a clipping collar) cost O(voids x width): 264 s for the 10801x4801
// SRTM mosaic with its sea as nodata, 9 s with 128 and passes over the remaining voids'
// bounding box. Voids farther than this from valid data are filled by further passes that
// start from the samples filled before. SRTM voids are mostly far smaller, so for them one
// pass does it all, and the weight 1/d of anything farther would be small anyway.
constexpr int kSearchDistance = 128;

// Share of the fill's progress the first pass reports; later passes split what remains.
constexpr double kFirstPassShare = 0.9;

// A code no valid sample has, written into voids so that voids GDAL left unfilled show.
// None exists when the valid codes use the whole 16-bit range.
std::optional<uint16_t> unusedCode(uint16_t min_valid_code, uint16_t max_valid_code)
{
    if (min_valid_code > 0)
        return uint16_t{0};
    if (max_valid_code < UINT16_MAX)
        return uint16_t{UINT16_MAX};
    return std::nullopt;
}

// Forwards GDAL's progress to ridge's; cancellation and exceptions are recorded and turned
// into GDAL's "stop" answer, since nothing may unwind through GDAL's C frames.
struct ProgressBridge {
    Progress progress;
    bool cancelled = false;
    std::exception_ptr error;

    static int CPL_STDCALL call(double fraction, const char*, void* arg)
    {
        auto* self = static_cast<ProgressBridge*>(arg);
        if (!self->progress)
            return TRUE;
        try {
            if (!self->progress(fraction)) {
                self->cancelled = true;
                return FALSE;
            }
        } catch (...) {
            self->error = std::current_exception();
            return FALSE;
        }
        return TRUE;
    }
};

// A rectangle of the grid: columns [x0, x1), rows [y0, y1).
struct Window {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    int64_t samples() const { return int64_t{width()} * height(); }
};

// Where the remaining voids are, and how many: the next pass only needs their bounding box
// plus the search distance, since GDAL looks no farther for valid samples.
struct VoidExtent {
    int64_t count = 0;
    Window box{INT_MAX, INT_MAX, -1, -1};

    void add(int x, int y)
    {
        ++count;
        box.x0 = std::min(box.x0, x);
        box.y0 = std::min(box.y0, y);
        box.x1 = std::max(box.x1, x + 1);
        box.y1 = std::max(box.y1, y + 1);
    }
    Window searchWindow(const CodeGrid& grid, int distance) const
    {
        return {std::max(0, box.x0 - distance), std::max(0, box.y0 - distance),
                std::min(grid.width, box.x1 + distance), std::min(grid.height, box.y1 + distance)};
    }
};

// One GDALFillNodata pass over `window` of the grid, in place.
void fillPass(const std::string& path, CodeGrid& grid, std::vector<uint8_t>& void_mask,
              const Window& window, double search_distance, const Progress& progress)
{
    GdalErrorCapture capture;
    CPLStringList options;
    std::optional<ScopedThreadConfig> temp_dir;
    if (window.samples() <= kInMemoryWorkSamples) {
        options.SetNameValue("TEMP_FILE_DRIVER", "MEM");
    } else {
        // GDAL puts its work files in CPL_TMPDIR, or the current directory without it.
        temp_dir.emplace("CPL_TMPDIR", std::filesystem::temp_directory_path().string().c_str());
    }

    ProgressBridge bridge;
    bridge.progress = progress;
    CPLErr result;
    {
        const size_t origin = size_t(window.y0) * grid.width + window.x0;
        DatasetPtr target = wrapInMemDataset(grid.codes.data() + origin, GDT_UInt16, window.width(),
                                             window.height(), 1, grid.width);
        DatasetPtr mask = wrapInMemDataset(void_mask.data() + origin, GDT_Byte, window.width(),
                                           window.height(), 1, grid.width);
        result = GDALFillNodata(
            GDALGetRasterBand(target.get(), 1), GDALGetRasterBand(mask.get(), 1), search_distance,
            0, kSmoothingIterations, options.List(), &ProgressBridge::call, &bridge);
        // Closing the MEM datasets flushes anything GDAL still holds in its block cache.
    }
    if (bridge.error)
        std::rethrow_exception(bridge.error);
    if (bridge.cancelled)
        throw Cancelled();
    if (result != CE_None)
        throw Error(path + ": " + withGdalDetail("filling voids failed", capture));
}

// Marks the voids of `window` that now hold a code other than `sentinel` as valid; returns
// the voids that remain.
VoidExtent acceptFilled(const CodeGrid& grid, std::vector<uint8_t>& void_mask, const Window& window,
                        uint16_t sentinel)
{
    VoidExtent remaining;
    for (int y = window.y0; y < window.y1; ++y)
        for (int x = window.x0; x < window.x1; ++x) {
            const size_t i = size_t(y) * grid.width + x;
            if (void_mask[i] != 0)
                continue;
            if (grid.codes[i] == sentinel)
                remaining.add(x, y);
            else
                void_mask[i] = 255;
        }
    return remaining;
}

} // namespace

void fillVoids(const std::string& path, CodeGrid& grid, std::vector<uint8_t>& void_mask,
               uint16_t min_valid_code, uint16_t max_valid_code, const Progress& progress)
{
    const Window whole{0, 0, grid.width, grid.height};
    const std::optional<uint16_t> sentinel = unusedCode(min_valid_code, max_valid_code);
    if (!sentinel) {
        // Without a spare code unfilled voids cannot be told apart, so search the whole
        // raster (its diagonal) in one pass, which reaches a valid sample from every void.
        const double diagonal = std::ceil(std::hypot(grid.width, grid.height)) + 1;
        fillPass(path, grid, void_mask, whole, diagonal, progress);
        reportProgress(progress, 1.0);
        return;
    }

    VoidExtent voids;
    for (int y = 0; y < grid.height; ++y)
        for (int x = 0; x < grid.width; ++x) {
            const size_t i = size_t(y) * grid.width + x;
            if (void_mask[i] == 0) {
                grid.codes[i] = *sentinel;
                voids.add(x, y);
            }
        }
    double done = 0.0;
    double share = kFirstPassShare;
    while (voids.count > 0) {
        const Window window = voids.searchWindow(grid, kSearchDistance);
        fillPass(path, grid, void_mask, window, kSearchDistance,
                 subProgress(progress, done, done + share));
        const VoidExtent left = acceptFilled(grid, void_mask, window, *sentinel);
        if (left.count == voids.count)
            throw Error(path + ": " + std::to_string(left.count) + " voids could not be filled");
        voids = left;
        done += share;
        share = (1.0 - done) / 2;
    }
    reportProgress(progress, 1.0);
}

} // namespace ridge::io::detail
