// The GPU residual add of the jpeg2000 codec (the JPEG2000 paper's §4) equals the CPU decoder,
// bit for bit, on every patch below the root of real archives: 8-bit difference layers (R8),
// wider ones (R16), direct patches, clipped regions at the fixture's edge.
#include "decoders/gpu_jpeg2000_decoder.h"
#include "fixture_archives.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/jpeg2000_codec.h"
#include "ridge/core/sanitizer.h"
#include "ridge/gpu/context.h"
#include "ridge/pyramid/patch_context.h"
#include "ridge/stream/patch_loader.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

struct Seen {
    size_t patches = 0, wide = 0, direct = 0, clipped = 0;
};

Seen expectGpuEqualsCpu(const std::string& path)
{
    Seen seen;
    const archive::ArchiveReader reader(path);
    const auto* codec = dynamic_cast<const Jpeg2000Codec*>(&reader.codec());
    EXPECT_NE(codec, nullptr);
    if (!codec)
        return seen;
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize();
    render::GpuJpeg2000Decoder decoder(n);
    gpu::GlTexture heights(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(heights.id(), 1, GL_R16UI, n, n, 2);
    glTextureParameteri(heights.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(heights.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    stream::PatchLoader cpu(reader, 4096);
    std::vector<uint16_t> gpu_codes(size_t(n) * n);
    size_t differing = 0;
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        if (p.level == 0)
            continue;
        const auto parent = cpu.load(p.parent());
        const auto expected = cpu.load(p);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
        glTextureSubImage3D(heights.id(), 0, 0, 0, 0, n, n, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                            parent->codes.data());
        const std::vector<uint8_t> blob = reader.readBlob(p);
        const size_t skip = reader.payloadOffset(p, blob);
        const PatchContext ctx = patchContext(g, p, parent->codes.data());
        Jpeg2000Difference d;
        EXPECT_EQ(codec->decodeDifference(blob.data() + skip, blob.size() - skip, ctx, &d),
                  kCodecOk);
        decoder.reconstruct(d, ctx.child_index, heights.id(), 0, 1);
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glGetTextureSubImage(heights.id(), 0, 0, 0, 1, n, n, 1, GL_RED_INTEGER, GL_UNSIGNED_SHORT,
                             GLsizei(gpu_codes.size() * 2), gpu_codes.data());
        for (size_t k = 0; k < gpu_codes.size(); ++k)
            differing += gpu_codes[k] != expected->codes[k];
        ++seen.patches;
        seen.wide += d.bits > 8;
        seen.direct += d.kind == Jpeg2000Encoding::Direct;
        seen.clipped += d.width < n || d.height < n;
    }
    EXPECT_EQ(differing, 0u) << path;
    return seen;
}

} // namespace

TEST(GpuJpeg2000Decoder, ResidualAddEqualsTheCpuDecoderOnEveryPatch)
{
    auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    // Progressive 8-bit difference layers (the paper's), at two patch sizes and bounds.
    Seen s = expectGpuEqualsCpu(test::buildEverestArchive(dir, "jpeg2000", 33, 2.0));
    EXPECT_GT(s.patches, 4u);
    EXPECT_GT(s.clipped, 0u); // the fixture is 301 x 203: edge patches are clipped
    // Many small patches: the same paths again, so not under the sanitizers (4× the patches).
    if (!RIDGE_ADDRESS_SANITIZER) {
        s = expectGpuEqualsCpu(test::buildEverestArchive(dir, "jpeg2000", 17, 5.0));
        EXPECT_GT(s.patches, 20u);
    }
    // Direct encoding: 12-bit heights (R16), no prediction.
    s = expectGpuEqualsCpu(test::buildEverestArchive(dir, "jpeg2000,encoding=direct", 33, 2.0));
    EXPECT_EQ(s.direct, s.patches);
    EXPECT_GT(s.wide, 0u);
    // An exact bound: differences need more than 8 bits.
    s = expectGpuEqualsCpu(test::buildEverestArchive(dir, "jpeg2000,criterion=lossless", 33, 0.5));
    EXPECT_GT(s.wide, 0u);
}
