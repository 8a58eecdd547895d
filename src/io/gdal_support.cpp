#include "gdal_support.h"

#include "ridge/core/error.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>

#include <mutex>

namespace ridge::io::detail {

namespace {

// Enough to explain a failure; GDAL can repeat one message per block.
constexpr size_t kMaxFailures = 4;

} // namespace

void ensureGdalRegistered()
{
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
}

GdalErrorCapture::GdalErrorCapture()
{
    CPLPushErrorHandlerEx(&GdalErrorCapture::handle, this);
}

GdalErrorCapture::~GdalErrorCapture()
{
    CPLPopErrorHandler();
}

void CPL_STDCALL GdalErrorCapture::handle(CPLErr error_class, CPLErrorNum, const char* message)
{
    // Warnings and debug output are dropped: a successful ingest must not print anything,
    // and a failed one is explained by its failures.
    if (error_class != CE_Failure && error_class != CE_Fatal)
        return;
    auto* self = static_cast<GdalErrorCapture*>(CPLGetErrorHandlerUserData());
    if (!self || self->failures_.size() >= kMaxFailures)
        return;
    try {
        std::string text = message ? message : "";
        while (!text.empty() && (text.back() == '\n' || text.back() == ' '))
            text.pop_back();
        for (const std::string& seen : self->failures_)
            if (seen == text)
                return;
        self->failures_.push_back(std::move(text));
    } catch (...) {
        // Out of memory while recording a message: losing the message is the lesser evil
        // (an exception must not unwind through GDAL's C frames).
    }
}

std::string GdalErrorCapture::failures() const
{
    std::string joined;
    for (const std::string& f : failures_) {
        if (!joined.empty())
            joined += "; ";
        joined += f;
    }
    return joined;
}

std::string withGdalDetail(const std::string& problem, const GdalErrorCapture& capture)
{
    const std::string detail = capture.failures();
    return detail.empty() ? problem : problem + ": " + detail;
}

ScopedCacheLimit::ScopedCacheLimit(int64_t max_bytes) : previous_(GDALGetCacheMax64())
{
    if (previous_ > max_bytes)
        GDALSetCacheMax64(max_bytes);
}

ScopedCacheLimit::~ScopedCacheLimit()
{
    if (GDALGetCacheMax64() != previous_)
        GDALSetCacheMax64(previous_);
}

ScopedThreadConfig::ScopedThreadConfig(const char* key, const char* value) : key_(key)
{
    if (const char* old = CPLGetThreadLocalConfigOption(key, nullptr))
        previous_ = old;
    CPLSetThreadLocalConfigOption(key, value);
}

ScopedThreadConfig::~ScopedThreadConfig()
{
    CPLSetThreadLocalConfigOption(key_.c_str(), previous_ ? previous_->c_str() : nullptr);
}

DatasetPtr wrapInMemDataset(void* data, GDALDataType type, int width, int height, int bands,
                            int64_t row_stride)
{
    if (row_stride == 0)
        row_stride = width;
    ensureGdalRegistered();
    GDALDriverH mem = GDALGetDriverByName("MEM");
    if (!mem)
        throw Error("GDAL's MEM driver is not available");
    DatasetPtr ds(GDALCreate(mem, "", width, height, 0, type, nullptr));
    if (!ds)
        throw Error("cannot create an in-memory GDAL dataset");
    const int sample_bytes = GDALGetDataTypeSizeBytes(type);
    const int pixel_bytes = sample_bytes * bands;
    for (int b = 0; b < bands; ++b) {
        char address[64] = {};
        CPLPrintPointer(address, static_cast<char*>(data) + b * sample_bytes, sizeof(address) - 1);
        CPLStringList options;
        options.SetNameValue("DATAPOINTER", address);
        options.SetNameValue("PIXELOFFSET", CPLSPrintf("%d", pixel_bytes));
        options.SetNameValue("LINEOFFSET",
                             CPLSPrintf("%lld", static_cast<long long>(pixel_bytes) * row_stride));
        if (GDALAddBand(ds.get(), type, options.List()) != CE_None)
            throw Error("cannot wrap a buffer in an in-memory GDAL band");
    }
    return ds;
}

} // namespace ridge::io::detail
