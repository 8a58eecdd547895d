#pragma once
// The GPU half of a codec's decoding (internal to ridge_render), one interface for every
// codec that has one: the CPU half (HeightCodec::decodeForGpu) hands a GpuPayload of the
// codec's type, the decoder registered for that codec writes the patch's codes into a layer of
// the resident height-map array. What a decoder needs (the parent resident, refinement in
// place) is the codec's declaration (GpuDecoding); the planner and PatchTextures read that,
// never the codec's type.
//
// A decoder is one module under src/render/decoders/ plus one line in gpu_decoder_registry.cpp.
// Needs a current GL 4.5 context.
#include "ridge/codec/height_codec.h"
#include "ridge/gpu/gl_objects.h"

#include <memory>
#include <string>

namespace ridge::render {

class GpuPatchDecoder {
  public:
    virtual ~GpuPatchDecoder() = default;

    // Where a patch is decoded: `heights` is the resident GL_TEXTURE_2D_ARRAY of R16UI codes
    // (patch_size² per layer, GL_NEAREST), `layer` the patch's slot, `parent_layer` its
    // parent's (−1 when the codec does not read it). `child_index` is the patch's quadrant in
    // its parent (0..3, (x&1)|(y&1)<<1). Call glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT)
    // before sampling the codes written.
    struct Target {
        GLuint heights = 0;
        int layer = 0;
        int parent_layer = -1;
        int child_index = 0;
        int level = 0;
    };
    // Decodes `payload` (the codec's own GpuPayload type) into target.layer. `steps`: for a
    // refinable codec, how many of the payload's steps to apply (clamped to its full count);
    // others decode fully.
    virtual void decode(const GpuPayload& payload, const Target& target, int steps) = 0;
    // Refinable codecs: applies steps to the patch decoded in target.layer until it has
    // `steps` of them (no-op when it has as many), from what the decoder kept of it.
    virtual void refine(const Target& /*target*/, int /*steps*/) {}
};

// What the registry knows of a codec's GPU decoder.
struct GpuDecoderInfo {
    const char* codec = ""; // the codec's name (HeightCodec::name())
    // Builds the decoder for `codec` (throws ridge::Error when it is not that codec) with room
    // for `slots` resident patches of `patch_size` samples a side.
    std::unique_ptr<GpuPatchDecoder> (*make)(const HeightCodec& codec, int patch_size,
                                             int slots) = nullptr;
    // GPU memory the decoder keeps per slot, bytes (refinable state; 0 for most).
    double (*bytes_per_slot)(int patch_size) = nullptr;
};

// The decoder registered for `codec`, or null when it has none.
const GpuDecoderInfo* findGpuDecoder(const HeightCodec& codec);

} // namespace ridge::render
