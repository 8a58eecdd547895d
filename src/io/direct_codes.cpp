// 8/16-bit integer bands: GDAL reads each strip straight into the caller's code buffer, then
// one pass turns stored bit patterns into codes in place. No second buffer, no pre-pass.
#include "code_source.h"

#include <gdal_version.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ridge::io::detail {

namespace {

// How a band's samples land in the uint16 buffer and what they mean:
// stored value = int(buffer ^ base_xor) + value_shift, within [type_min, type_max].
struct DirectLayout {
    GDALDataType buffer_type = GDT_UInt16;
    uint16_t base_xor = 0;
    int value_shift = 0;
    int type_min = 0;
    int type_max = 0;
};

std::optional<DirectLayout> directLayout(const SourceBand& band)
{
    switch (band.dataType()) {
    case GDT_UInt16:
        return DirectLayout{GDT_UInt16, 0, 0, 0, UINT16_MAX};
    case GDT_Int16:
        // Int16 read as such: the bit pattern ^ 0x8000 is value + 32768.
        return DirectLayout{GDT_Int16, 0x8000, INT16_MIN, INT16_MIN, INT16_MAX};
    case GDT_Byte:
        if (band.isSignedByte()) // raw bytes; ^ 0x80 is value + 128
            return DirectLayout{GDT_UInt16, 0x80, -128, -128, 127};
        return DirectLayout{GDT_UInt16, 0, 0, 0, 255};
#if GDAL_VERSION_NUM >= GDAL_COMPUTE_VERSION(3, 7, 0)
    case GDT_Int8:
        return DirectLayout{GDT_Int16, 0x8000, INT16_MIN, -128, 127};
#endif
    default:
        return std::nullopt;
    }
}

class DirectCodes final : public CodeSource {
  public:
    DirectCodes(const SourceBand& band, const DirectLayout& layout)
        : band_(band), layout_(layout), nodata_(nodataPattern(band, layout))
    {
        // Every code of the type is a height the archive can hold: check them all, before
        // anything is read.
        band.checkHeightRange(layout.type_min, layout.type_max,
                              "the " + band.dataTypeName() + " type's values");
        // code = code_base + code_sign * int(buffer ^ base_xor), exact in 16 bits. With a
        // negative z_scale the codes run from the type's maximum down, so that the code ->
        // metre scale stays positive (archives require it).
        const bool mirrored = band.z().scale < 0;
        code_base_ =
            mirrored ? layout.type_max - layout.value_shift : layout.value_shift - layout.type_min;
        code_sign_ = mirrored ? -1 : 1;
        quantization_.scale = std::abs(band.z().scale);
        quantization_.offset = band.z().toMetres(mirrored ? layout.type_max : layout.type_min);
        exact_ = true;
    }

    int stripSampleBytes() const override { return sizeof(uint16_t); }

    void readRows(int y0, int rows, uint16_t* out, std::vector<int64_t>& voids, CodeStats& stats,
                  uint8_t* water) override
    {
        const int64_t count = int64_t{rows} * band_.width();
        band_.readRows(y0, rows, layout_.buffer_type, out);
        const uint8_t* mask = nullptr;
        if (band_.hasMaskBand()) {
            mask_strip_.resize(static_cast<size_t>(count));
            band_.readMaskRows(y0, rows, mask_strip_.data());
            mask = mask_strip_.data();
        }
        uint16_t lo = UINT16_MAX;
        uint16_t hi = 0;
        const size_t voids_before = voids.size();
        for (int64_t i = 0; i < count; ++i) {
            const uint16_t raw = out[i];
            if ((nodata_ && raw == *nodata_) || (mask && mask[i] == 0)) {
                voids.push_back(i);
                continue;
            }
            const auto code =
                static_cast<uint16_t>(code_base_ + code_sign_ * int(raw ^ layout_.base_xor));
            out[i] = code;
            lo = std::min(lo, code);
            hi = std::max(hi, code);
        }
        if (water) { // exact codes: the rule on codes is the rule on the source's values
            const int32_t sea = seaLevelCode();
            for (int64_t i = 0; i < count; ++i)
                water[i] = int32_t{out[i]} <= sea;
            for (size_t k = voids_before; k < voids.size(); ++k)
                water[voids[k]] = 0;
        }
        const int64_t valid = count - int64_t(voids.size() - voids_before);
        if (valid == 0)
            return;
        stats.valid += valid;
        stats.addCodes(lo, hi);
        stats.min_metres = std::min(stats.min_metres, quantization_.toMetres(lo));
        stats.max_metres = std::max(stats.max_metres, quantization_.toMetres(hi));
    }

  private:
    // The buffer pattern of the declared nodata value, if a sample can have it.
    static std::optional<uint16_t> nodataPattern(const SourceBand& band, const DirectLayout& layout)
    {
        const std::optional<double>& nodata = band.nodata();
        if (!nodata || !std::isfinite(*nodata) || std::floor(*nodata) != *nodata ||
            *nodata < layout.type_min || *nodata > layout.type_max)
            return std::nullopt;
        const int value = static_cast<int>(*nodata);
        return static_cast<uint16_t>(static_cast<uint16_t>(value - layout.value_shift) ^
                                     layout.base_xor);
    }

    const SourceBand& band_;
    DirectLayout layout_;
    std::optional<uint16_t> nodata_;
    int code_base_ = 0;
    int code_sign_ = 1;
    std::vector<uint8_t> mask_strip_;
};

} // namespace

bool hasDirectCodes(const SourceBand& band)
{
    // Shifted heights are no longer the stored integers.
    if (band.geoidShift())
        return false;
    return directLayout(band).has_value();
}

std::unique_ptr<CodeSource> makeDirectCodes(const SourceBand& band)
{
    return std::make_unique<DirectCodes>(band, *directLayout(band));
}

} // namespace ridge::io::detail
