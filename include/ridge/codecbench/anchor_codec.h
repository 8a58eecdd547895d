#pragma once
// Anchor codecs of `ridge codec-bench`: the strongest published error-bounded raster codecs,
// each driven through its own library to code one tile of 16-bit height codes so that every
// decoded sample is within a given L-inf bound (in code units) of the original.
//
// An anchor codes the finest level only; it knows nothing of ridge's pyramid. The bench (not
// the anchor) checks the bound on every sample, so an anchor whose library overshoots is
// reported, not trusted.
//
// Thread safety: anchors hold no mutable state; encode/decode may run concurrently. Every
// anchor configures its library single-threaded (the bench reports throughput per core).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ridge::codecbench {

class AnchorCodec {
  public:
    virtual ~AnchorCodec() = default;

    // Short name for tables and plot legends, e.g. "JPEG-LS".
    virtual std::string name() const = 0;
    // How the library is configured, e.g. "CharLS, NEAR = e, 16-bit grey".
    virtual std::string description() const = 0;
    // Name and version of the library, e.g. "CharLS 2.4.1" (as the library reports it where
    // it can, else as its headers state it).
    virtual std::string libraryVersion() const = 0;
    // False when decode(encode(x, e)) may leave [x - e, x + e] even though the library was
    // asked for e (ZFP's accuracy mode is a target, not a guarantee).
    virtual bool guaranteesBound() const { return true; }
    // True when the stream is itself a pyramid, coarse levels first (JPEG XL's responsive
    // mode): the bench gives such an anchor no "+ overviews" row.
    virtual bool progressive() const { return false; }

    // Codes codes[width * height] (row-major) so that decoding is within max_error codes of
    // every sample; max_error = 0 is lossless. The stream holds what the library writes
    // (its own header included); width, height and max_error travel outside it, as in a
    // container. Throws ridge::Error naming the anchor when the library fails.
    virtual std::vector<uint8_t> encode(const uint16_t* codes, int width, int height,
                                        int max_error) const = 0;

    // Decodes `size` untrusted bytes into codes[width * height]; width, height and max_error
    // as given to encode. Throws ridge::Error naming the anchor when the library rejects the
    // stream, when it is truncated, or when what it describes does not match width x height.
    // Never reads or writes outside the given buffers.
    virtual void decode(const uint8_t* bytes, size_t size, int width, int height, int max_error,
                        uint16_t* codes) const = 0;
};

// LERC 4 (Esri), maxZErr = e on uint16 tiles.
std::unique_ptr<AnchorCodec> makeLercAnchor();
// JPEG-LS near-lossless (CharLS 2), NEAR = e, one grey component.
std::unique_ptr<AnchorCodec> makeJpegLsAnchor();
// Uniform quantization to step 2e+1, then lossless JPEG 2000 (OpenJPEG, reversible 5/3).
std::unique_ptr<AnchorCodec> makeJpeg2000Anchor();
// Uniform quantization to step 2e+1, then lossless JPEG XL (libjxl, modular) at `effort`
// (libjxl's 1..9; 7 is cjxl's default, 9 the strongest in libjxl 0.7), named "JPEG XL e<effort>";
// `progressive`: responsive (the squeeze pyramid, coarse levels first in the codestream), named
// "JPEG XL e<effort> progressive". Throws ridge::Error for an effort outside 1..9.
std::unique_ptr<AnchorCodec> makeJpegXlAnchor(int effort, bool progressive = false);
// Uniform quantization to step 2e+1, LOCO-I median edge prediction, zstd level 19.
std::unique_ptr<AnchorCodec> makeMedZstdAnchor();
// ZFP fixed-accuracy mode, tolerance = e, on the tile as float (reversible mode for e = 0).
std::unique_ptr<AnchorCodec> makeZfpAnchor();

// All anchors, in table order.
std::vector<std::unique_ptr<AnchorCodec>> makeAnchorCodecs();

} // namespace ridge::codecbench
