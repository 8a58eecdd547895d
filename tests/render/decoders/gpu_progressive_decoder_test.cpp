// The GPU reconstruction of the progressive codec equals the CPU decoder, bit for bit, on
// every patch of real archives (both predictors, two patch sizes).
#include "decoders/gpu_progressive_decoder.h"
#include "fixture_archives.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/gpu/context.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/patch_context.h"
#include "ridge/stream/patch_loader.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace ridge;

namespace {

void expectGpuEqualsCpu(const std::string& path)
{
    const archive::ArchiveReader reader(path);
    const auto* codec = dynamic_cast<const ProgressiveCodec*>(&reader.codec());
    ASSERT_NE(codec, nullptr);
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize();
    render::GpuProgressiveDecoder decoder(n);
    // Layer 0: the parent's codes (from the CPU decoder), layer 1: the GPU's child.
    gpu::GlTexture heights(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(heights.id(), 1, GL_R16UI, n, n, 2);
    glTextureParameteri(heights.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST); // complete: 1 level
    glTextureParameteri(heights.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    stream::PatchLoader cpu(reader, 4096);
    std::vector<int32_t> residuals(size_t(n) * n);
    std::vector<uint16_t> gpu_codes(size_t(n) * n);
    size_t patches = 0, narrow_patches = 0, samples_differing = 0, corrected = 0;
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        if (p.level == 0)
            continue;
        const PatchId parent = p.parent();
        const auto parent_codes = cpu.load(parent);
        const auto expected = cpu.load(p);
        glTextureSubImage3D(heights.id(), 0, 0, 0, 0, n, n, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                            parent_codes->codes.data());
        const std::vector<uint8_t> blob = reader.readBlob(p);
        const size_t skip = reader.payloadOffset(p, blob); // block errors and validity mask
        // v4's CPU half reads the parent's codes (its contexts), v2's and v3's never do.
        const PatchContext ctx = patchContext(
            g, p,
            codec->capabilities().gpu.cpu_half_reads_parent ? parent_codes->codes.data() : nullptr);
        ASSERT_EQ(
            codec->decodeResiduals(blob.data() + skip, blob.size() - skip, ctx, residuals.data()),
            kCodecOk);
        // From 32-bit residuals, and from 16-bit ones (the streamer's storage) where they fit.
        const bool narrow = std::all_of(residuals.begin(), residuals.end(),
                                        [](int32_t r) { return r >= -32768 && r <= 32767; });
        const std::vector<int16_t> residuals16(residuals.begin(), residuals.end());
        for (const int bits : {32, 16}) {
            if (bits == 16 && !narrow)
                continue;
            const render::GpuProgressiveDecoder::Child child{
                ctx.child_index, codec->quantizer(p.level), codec->variant().predictor,
                codec->codedRegion(ctx), codec->weights(p.level)};
            if (bits == 32)
                decoder.reconstruct(residuals.data(), heights.id(), 0, 1, child);
            else
                decoder.reconstruct(residuals16.data(), heights.id(), 0, 1, child);
            glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
            glGetTextureSubImage(heights.id(), 0, 0, 0, 1, n, n, 1, GL_RED_INTEGER,
                                 GL_UNSIGNED_SHORT, GLsizei(gpu_codes.size() * 2),
                                 gpu_codes.data());
            for (size_t k = 0; k < gpu_codes.size(); ++k)
                samples_differing += gpu_codes[k] != expected->codes[k];
            narrow_patches += bits == 16;
        }
        ++patches;
        corrected += codec->weights(p.level) != nullptr;
    }
    // v2..v4 archives of the fixture learn corrections at their finer levels: the GPU applies
    // them.
    if (reader.metadata().build.codec == "progressive") {
        EXPECT_GT(corrected, 0u) << path;
    }
    EXPECT_EQ(samples_differing, 0u) << path;
    EXPECT_GT(patches, 4u);
    EXPECT_GT(narrow_patches, patches / 2) << "most patches take the 16-bit path";
}

} // namespace

TEST(GpuProgressiveDecoder, ReconstructsEveryPatchBitForBitLikeTheCpuDecoder)
{
    auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    struct Case {
        int patch;
        const char* codec;
        double error;
    };
    // v4 (whole and clipped regions: the fixture's extent ends inside its last patches), the
    // hybrid schedule (refinements coded, so the parent class reads refined bins), v3, v2, v1
    // and the paper's variant.
    for (const Case c :
         {Case{33, "progressive", 1.0}, Case{65, "progressive", 4.0},
          Case{33, "progressive,corrections=0", 1.0}, Case{33, "progressive,nested=2", 1.0},
          Case{33, "progressive-v3", 1.0}, Case{33, "progressive-v2", 1.0},
          Case{33, "progressive-v1", 1.0}, Case{33, "progressive-paper", 2.0}}) {
        expectGpuEqualsCpu(test::buildEverestArchive(dir, c.codec, c.patch, c.error));
    }
}
