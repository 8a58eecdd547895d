#pragma once
// Codec interface of the .ridge archive: one patch of 16-bit codes <-> one payload.
//
// API shape after meshoptimizer: the caller owns every buffer; encode returns the bytes
// written (0 = not enough room); decode returns 0 or a negative CodecStatus. Payload bytes
// are untrusted: decode checks every bound and never reads or writes outside its buffers.
//
// A codec may predict a patch from its parent's reconstruction (the progressive codec of
// the hardware-tessellation paper); PatchContext carries it. Codecs that do not need it
// ignore it. Decoding is a pure function of (context, payload).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace ridge {

enum class CodecId : uint32_t {
    Raw16 = 0,    // uncompressed little-endian codes (debugging, speed baseline)
    Lossless = 1, // MED prediction + zstd (default)
};

enum CodecStatus : int {
    kCodecOk = 0,
    kCodecBadHeader = -1,    // magic/version/parameters do not match
    kCodecTruncated = -2,    // payload ends early
    kCodecCorrupt = -3,      // inconsistent content (entropy stream, sizes)
    kCodecTrailingBytes = -4 // payload longer than its content
};

const char* codecStatusMessage(int status);

struct PatchContext {
    int patch_size = 0;                       // samples per side, 2^n + 1
    int level = 0;                            // quadtree level of the patch
    const uint16_t* parent = nullptr;         // parent reconstruction (may be null)
    int child_index = 0;                      // quadrant within the parent: 0..3 = (x&1)|(y&1)<<1
};

class HeightCodec {
public:
    virtual ~HeightCodec() = default;
    virtual CodecId id() const = 0;
    virtual const char* name() const = 0;
    // True when decode(encode(x)) == x for every patch.
    virtual bool lossless() const = 0;
    // δ_l in code units: bound on |decoded - input| at `level` (0 for lossless codecs).
    virtual double levelErrorBound(int level) const = 0;
    // Worst-case payload size for one patch.
    virtual size_t encodeBound(const PatchContext& ctx) const = 0;
    // Encodes patch_size^2 codes; returns bytes written, 0 if dst_capacity is too small.
    virtual size_t encode(uint8_t* dst, size_t dst_capacity, const uint16_t* codes,
                          const PatchContext& ctx) const = 0;
    // Decodes into dst[patch_size^2]; returns kCodecOk or a negative CodecStatus.
    virtual int decode(uint16_t* dst, const uint8_t* src, size_t src_size,
                       const PatchContext& ctx) const = 0;
};

// Codec by name ("lossless", "raw"); throws ridge::Error for an unknown name.
std::unique_ptr<HeightCodec> makeCodec(const std::string& name);
// Codec by stored id; returns null for an unknown id.
std::unique_ptr<HeightCodec> makeCodec(CodecId id);

} // namespace ridge
