// The fractal codec's GPU decoder (the fractal-rings paper's iterations, §7) equals the CPU
// decoder bit for bit on every patch of three real archives — after every iteration count, not
// only the last, and when a patch decoded with few iterations is refined in place to more
// (Base incremental).
#include "decoders/gpu_fractal_decoder.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/fractal_codec.h"
#include "ridge/gpu/context.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/patch_context.h"

#include <gtest/gtest.h>

using namespace ridge;

namespace {

std::string buildFractal(const test::ScratchDir& dir, const std::string& source, int patch_size,
                         double max_error)
{
    BuildOptions options;
    options.patch_size = patch_size;
    options.codec = "fractal";
    options.max_error = max_error;
    options.progress = {};
    const std::string path = dir.path(source + ".ridge");
    buildArchive(test::dataPath(source), path, options);
    return path;
}

struct Seen {
    size_t patches = 0, partial_differs = 0;
};

Seen expectGpuEqualsCpu(const std::string& path)
{
    Seen seen;
    const archive::ArchiveReader reader(path);
    const auto* codec = dynamic_cast<const FractalCodec*>(&reader.codec());
    EXPECT_NE(codec, nullptr);
    if (!codec)
        return seen;
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize(), slots = 2;
    render::GpuFractalDecoder decoder(n, slots);
    gpu::GlTexture heights(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(heights.id(), 1, GL_R16UI, n, n, slots);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    std::vector<uint16_t> gpu_codes(size_t(n) * n), cpu_codes(size_t(n) * n), full(size_t(n) * n);
    const auto read = [&](int layer) {
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
        glGetTextureSubImage(heights.id(), 0, 0, 0, layer, n, n, 1, GL_RED_INTEGER,
                             GL_UNSIGNED_SHORT, GLsizei(gpu_codes.size() * 2), gpu_codes.data());
        return gpu_codes;
    };
    size_t differing = 0;
    for (int64_t i = 0; i < g.patchCount(); ++i) {
        const PatchId p = g.patchAt(i);
        const std::vector<uint8_t> blob = reader.readBlob(p);
        const size_t skip = reader.payloadOffset(p, blob);
        const PatchContext ctx = patchContext(g, p, nullptr);
        std::shared_ptr<const GpuPayload> payload;
        EXPECT_EQ(codec->decodeForGpu(blob.data() + skip, blob.size() - skip, ctx, &payload),
                  kCodecOk);
        const auto& f = static_cast<const FractalPayload&>(*payload);
        EXPECT_EQ(f.iterations, codec->variant().iterations);
        reader.decodePatch(p, full.data());
        const render::GpuPatchDecoder::Target t1{heights.id(), 1, -1, p.childIndex(), p.level};
        for (int k = 0; k <= f.iterations; ++k) {
            // From the start image to k iterations.
            decoder.decode(*payload, {heights.id(), 0, -1, p.childIndex(), p.level}, k);
            EXPECT_EQ(codec->decodePartial(cpu_codes.data(), blob.data() + skip, blob.size() - skip,
                                           ctx, k),
                      kCodecOk);
            const std::vector<uint16_t> got = read(0);
            for (size_t s = 0; s < got.size(); ++s)
                differing += got[s] != cpu_codes[s];
            // The stored bound of a partial decode holds.
            double worst = 0;
            for (size_t s = 0; s < got.size(); ++s)
                worst = std::max(worst, std::abs(double(got[s]) - double(full[s])));
            EXPECT_LE(worst, f.stepBound(k)) << reader.describe(p) << " after " << k;
            seen.partial_differs += k < f.iterations && worst > 0;
        }
        // Refined in place: 2 iterations, then the rest, equals the full decode.
        decoder.decode(*payload, t1, 2);
        decoder.refine(t1, f.iterations);
        EXPECT_EQ(decoder.steps(1), f.iterations);
        const std::vector<uint16_t> refined = read(1);
        for (size_t s = 0; s < refined.size(); ++s)
            differing += refined[s] != full[s];
        ++seen.patches;
    }
    EXPECT_EQ(differing, 0u) << path;
    return seen;
}

} // namespace

TEST(GpuFractalDecoder, IterationsEqualTheCpuDecoderOnEveryPatchOfThreeRealArchives)
{
    auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    // The Himalaya (SRTM), a coast with sea (SRTM) and a global grid (ETOPO5), at two patch
    // sizes (clipped edge patches included) and three bounds.
    for (const auto& [source, n, bound] :
         {std::tuple{"everest_crop.tif", 33, 2.0}, std::tuple{"sfbay_coast.tif", 17, 4.0},
          std::tuple{"etopo5_540x270.tif", 33, 16.0}}) {
        const Seen s = expectGpuEqualsCpu(buildFractal(dir, source, n, bound));
        EXPECT_GT(s.patches, 10u) << source;
        EXPECT_GT(s.partial_differs, 0u) << source << ": partial decodes differ from the full one";
    }
}

TEST(GpuFractalDecoder, ThePapersModeIteratesUnpinnedBitForBitLikeTheCpu)
{
    // No archive holds the paper's mode (it bounds nothing): its payloads, coded from real
    // patches, decode on the GPU as on the CPU at every iteration count.
    auto context = gpu::HeadlessContext::create();
    test::ScratchDir dir;
    const archive::ArchiveReader reader(buildFractal(dir, "everest_crop.tif", 33, 2.0));
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize();
    FractalVariant v;
    v.paper = true;
    const FractalCodec paper(0.0, g.levelCount(), v);
    render::GpuFractalDecoder decoder(n, 1);
    gpu::GlTexture heights(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(heights.id(), 1, GL_R16UI, n, n, 1);
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    std::vector<uint16_t> codes(size_t(n) * n), cpu(codes.size()), got(codes.size());
    size_t differing = 0, patches = 0;
    for (int64_t i = 0; i < g.patchCount(); i += 3) {
        const PatchId p = g.patchAt(i);
        reader.decodePatch(p, codes.data());
        const PatchContext ctx = patchContext(g, p, nullptr);
        std::vector<uint8_t> payload(paper.encodeBound(ctx));
        payload.resize(paper.encode(payload.data(), payload.size(), codes.data(), ctx));
        std::shared_ptr<const GpuPayload> gpu_payload;
        ASSERT_EQ(paper.decodeForGpu(payload.data(), payload.size(), ctx, &gpu_payload), kCodecOk);
        for (const int k : {0, 3, 8}) {
            decoder.decode(*gpu_payload, {heights.id(), 0, -1, 0, p.level}, k);
            ASSERT_EQ(paper.decodePartial(cpu.data(), payload.data(), payload.size(), ctx, k),
                      kCodecOk);
            glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT);
            glGetTextureSubImage(heights.id(), 0, 0, 0, 0, n, n, 1, GL_RED_INTEGER,
                                 GL_UNSIGNED_SHORT, GLsizei(got.size() * 2), got.data());
            for (size_t s = 0; s < got.size(); ++s)
                differing += got[s] != cpu[s];
        }
        ++patches;
    }
    EXPECT_GT(patches, 5u);
    EXPECT_EQ(differing, 0u);
}
