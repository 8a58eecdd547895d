#include "ridge/archive/archive_metadata.h"
#include "ridge/archive/format.h"
#include "ridge/core/error.h"

#include <zstd.h>

#include <memory>

namespace ridge::archive {

namespace {

// Level 19: metadata is written once per archive and is a few KB at most.
constexpr int kMetadataLevel = 19;

struct CctxDeleter {
    void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
struct DctxDeleter {
    void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

} // namespace

std::vector<uint8_t> packMetadata(const std::string& json, uint32_t version)
{
    if (version < kFirstVersionWithPackedMetadata)
        return {json.begin(), json.end()};
    const std::unique_ptr<ZSTD_CCtx, CctxDeleter> cctx(ZSTD_createCCtx());
    if (!cctx)
        throw Error("cannot compress the metadata: out of memory");
    const auto check = [](size_t status) {
        if (ZSTD_isError(status))
            throw Error(std::string("cannot compress the metadata: ") + ZSTD_getErrorName(status));
        return status;
    };
    const std::string_view reference = metadataReference();
    check(ZSTD_CCtx_setParameter(cctx.get(), ZSTD_c_compressionLevel, kMetadataLevel));
    check(ZSTD_CCtx_refPrefix(cctx.get(), reference.data(), reference.size()));
    std::vector<uint8_t> out(ZSTD_compressBound(json.size()));
    const size_t size =
        check(ZSTD_compress2(cctx.get(), out.data(), out.size(), json.data(), json.size()));
    out.resize(size);
    return out;
}

std::string unpackMetadata(const uint8_t* data, size_t size, uint32_t version, std::string& json)
{
    if (version < kFirstVersionWithPackedMetadata) {
        json.assign(reinterpret_cast<const char*>(data), size);
        return {};
    }
    // The content size bounds the allocation before anything is decompressed.
    const unsigned long long content = ZSTD_getFrameContentSize(data, size);
    if (content == ZSTD_CONTENTSIZE_UNKNOWN || content == ZSTD_CONTENTSIZE_ERROR)
        return "metadata is not a zstd frame that states its content size";
    if (content < 2 || content > kMaxMetadataBytes)
        return "metadata frame holds " + std::to_string(content) + " bytes: must be 2.." +
               std::to_string(kMaxMetadataBytes);
    if (ZSTD_findFrameCompressedSize(data, size) != size)
        return "metadata is not exactly one zstd frame (" + std::to_string(size) +
               " bytes at metadata_offset)";
    const std::unique_ptr<ZSTD_DCtx, DctxDeleter> dctx(ZSTD_createDCtx());
    if (!dctx)
        throw Error("cannot decompress the metadata: out of memory");
    const std::string_view reference = metadataReference();
    std::string text(static_cast<size_t>(content), '\0');
    size_t got = ZSTD_DCtx_refPrefix(dctx.get(), reference.data(), reference.size());
    if (!ZSTD_isError(got))
        got = ZSTD_decompressDCtx(dctx.get(), text.data(), text.size(), data, size);
    if (ZSTD_isError(got) || got != text.size())
        return "metadata frame does not decompress to its " + std::to_string(content) +
               " bytes against the metadata reference";
    json = std::move(text);
    return {};
}

} // namespace ridge::archive
