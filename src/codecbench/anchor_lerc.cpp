// LERC (Limited Error Raster Compression, Esri) as an anchor: the codec GDAL, MRF and COG
// writers offer for error-bounded elevation. LERC splits the tile into micro-blocks, and per
// block either stores a constant, or quantizes (z - zMin) with step 2 maxZErr and bit-stuffs
// the result; for integer types it floors maxZErr and treats 0 as lossless (0.5).
#include "ridge/codecbench/anchor_codec.h"

#include "uniform_quantizer.h"

#include <Lerc_c_api.h>
#include <Lerc_types.h>

#include <fmt/core.h>

namespace ridge::codecbench {

namespace {

constexpr unsigned kLercUShort = static_cast<unsigned>(LercNS::DataType::dt_ushort);

class LercAnchor final : public AnchorCodec {
  public:
    std::string name() const override { return "LERC"; }
    std::string description() const override
    {
        return "maxZErr = e on uint16 tiles (lossless for e = 0), codec v2.6";
    }
    std::string libraryVersion() const override
    {
        return fmt::format("lerc {}.{}.{}", LERC_VERSION_MAJOR, LERC_VERSION_MINOR,
                           LERC_VERSION_PATCH);
    }

    std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                int max_error) const override
    {
        unsigned size = 0;
        lerc_status status = lerc_computeCompressedSize(codes, kLercUShort, 1, width, height, 1, 0,
                                                        nullptr, double(max_error), &size);
        if (status != 0)
            anchorFail(name(),
                       fmt::format("lerc_computeCompressedSize failed (status {})", status));
        std::vector<uint8_t> blob(size);
        unsigned written = 0;
        status = lerc_encode(codes, kLercUShort, 1, width, height, 1, 0, nullptr, double(max_error),
                             blob.data(), size, &written);
        if (status != 0)
            anchorFail(name(), fmt::format("lerc_encode failed (status {})", status));
        blob.resize(written);
        return blob;
    }

    void decode(const uint8_t* bytes, size_t size, int width, int height, int /*max_error*/,
                uint16_t* codes) const override
    {
        // lerc_getBlobInfo checks the header and that the blob is not truncated before the
        // decoder is allowed to size anything from it.
        unsigned info[static_cast<int>(LercNS::InfoArrOrder::_last)] = {};
        double ranges[static_cast<int>(LercNS::DataRangeArrOrder::_last)] = {};
        if (size == 0 || size > 0xFFFFFFFFu)
            anchorFail(name(), fmt::format("invalid blob size {}", size));
        const unsigned blob_size = static_cast<unsigned>(size);
        lerc_status status =
            lerc_getBlobInfo(bytes, blob_size, info, ranges, static_cast<int>(std::size(info)),
                             static_cast<int>(std::size(ranges)));
        if (status != 0)
            anchorFail(name(),
                       fmt::format("lerc_getBlobInfo rejected the blob (status {})", status));
        using I = LercNS::InfoArrOrder;
        const auto at = [&](I i) { return info[static_cast<int>(i)]; };
        if (at(I::dataType) != kLercUShort || at(I::nDepth) != 1 || at(I::nBands) != 1 ||
            at(I::nCols) != unsigned(width) || at(I::nRows) != unsigned(height) ||
            at(I::blobSize) > blob_size)
            anchorFail(name(), fmt::format("blob describes {}x{} type {} depth {} bands {}, "
                                           "expected {}x{} uint16",
                                           at(I::nCols), at(I::nRows), at(I::dataType),
                                           at(I::nDepth), at(I::nBands), width, height));
        status = lerc_decode(bytes, blob_size, 0, nullptr, 1, width, height, 1, kLercUShort, codes);
        if (status != 0)
            anchorFail(name(), fmt::format("lerc_decode failed (status {})", status));
    }
};

} // namespace

std::unique_ptr<AnchorCodec> makeLercAnchor()
{
    return std::make_unique<LercAnchor>();
}

} // namespace ridge::codecbench
