#pragma once
// Private GDAL plumbing shared by src/io: RAII handles, error capture, scoped settings.
// Never included from a public header.
#include <gdal.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ridge::io::detail {

// Registers GDAL's drivers once per process.
void ensureGdalRegistered();

struct DatasetCloser {
    void operator()(void* dataset) const
    {
        if (dataset)
            GDALClose(static_cast<GDALDatasetH>(dataset));
    }
};
// Owns a GDALDatasetH (which is a void*).
using DatasetPtr = std::unique_ptr<void, DatasetCloser>;

// Collects GDAL's error messages on this thread instead of letting GDAL print them, so that
// they can be folded into a ridge::Error. Handlers nest (CPLPushErrorHandlerEx is a
// per-thread stack); keep instances on the stack so that pushes and pops stay LIFO.
class GdalErrorCapture {
  public:
    GdalErrorCapture();
    ~GdalErrorCapture();
    GdalErrorCapture(const GdalErrorCapture&) = delete;
    GdalErrorCapture& operator=(const GdalErrorCapture&) = delete;

    bool hasFailure() const { return !failures_.empty(); }
    // The failures collected so far, joined with "; " (empty when there were none).
    std::string failures() const;

  private:
    static void CPL_STDCALL handle(CPLErr error_class, CPLErrorNum number, const char* message);
    std::vector<std::string> failures_;
};

// "problem" or "problem: <GDAL's messages>" when GDAL reported any.
std::string withGdalDetail(const std::string& problem, const GdalErrorCapture& capture);

// Lowers GDAL's global block cache to at most `max_bytes` for the object's lifetime. The
// cache is process-wide: concurrent ingests in one process share (and restore) one limit.
class ScopedCacheLimit {
  public:
    explicit ScopedCacheLimit(int64_t max_bytes);
    ~ScopedCacheLimit();
    ScopedCacheLimit(const ScopedCacheLimit&) = delete;
    ScopedCacheLimit& operator=(const ScopedCacheLimit&) = delete;

  private:
    int64_t previous_;
};

// Sets a GDAL configuration option for this thread only, restoring the previous value.
class ScopedThreadConfig {
  public:
    ScopedThreadConfig(const char* key, const char* value);
    ~ScopedThreadConfig();
    ScopedThreadConfig(const ScopedThreadConfig&) = delete;
    ScopedThreadConfig& operator=(const ScopedThreadConfig&) = delete;

  private:
    std::string key_;
    std::optional<std::string> previous_;
};

// A MEM dataset over `data` (row-major, `bands` samples interleaved per pixel, rows
// `row_stride` pixels apart, default `width`) that reads and writes it in place, without a
// copy, through the MEM driver's documented DATAPOINTER band option. A stride wider than
// `width` views a window of a larger buffer. `data` must outlive the dataset.
DatasetPtr wrapInMemDataset(void* data, GDALDataType type, int width, int height, int bands = 1,
                            int64_t row_stride = 0);

} // namespace ridge::io::detail
