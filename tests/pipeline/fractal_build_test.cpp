// The fractal codec on a real DEM (tests/data/everest_crop.tif, SRTM): the paper's
// iterations-against-error curve, measured on every finest patch of an archive — the
// attractor alone (no corrections) after 0..10 applications of T, against the source — and
// the bound the corrections add on top (verify --source holds every codec to it in
// codec_registry_test). docs/PERF.md quotes the printed curve.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/codec/fractal_codec.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pyramid/patch_context.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

using namespace ridge;

TEST(FractalBuild, IterationsApproachTheSourceOnARealDem)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    const std::string out = dir.path("everest_fractal.ridge");
    BuildOptions options;
    options.patch_size = 65;
    options.codec = "fractal,iterations=10,search=0";
    options.max_error = 2.0;
    buildArchive(source, out, options);

    const archive::ArchiveReader reader(out);
    const auto* codec = dynamic_cast<const FractalCodec*>(&reader.codec()); // its own test
    ASSERT_NE(codec, nullptr);
    const io::ElevationRaster raster = io::ingestRaster(source);
    const PyramidGeometry& g = reader.geometry();
    const int level = g.finestLevel(), n = g.patchSize();
    const double scale = reader.quantization().scale;

    constexpr int kMaxIterations = 10;
    std::vector<double> squares(kMaxIterations + 1, 0.0), worst(kMaxIterations + 1, 0.0);
    // What a renderer that stops after i iterations draws (the corrections added: Base
    // incremental), and the largest stored partial bound plus E, which must cover it.
    std::vector<double> partial_worst(kMaxIterations + 1, 0.0), promised(kMaxIterations + 1, 0.0);
    double samples = 0.0;
    std::vector<uint16_t> attractor(size_t(n) * n), partial(size_t(n) * n);
    for (int64_t k = 0; k < g.patchCount(level); ++k) {
        const PatchId p = g.patchAt(g.firstPatchIndex(level) + k);
        const std::vector<uint8_t> blob = reader.readBlob(p);
        const size_t at = reader.payloadOffset(p, blob);
        const PatchContext ctx = patchContext(g, p, nullptr);
        std::shared_ptr<const GpuPayload> gpu;
        ASSERT_EQ(codec->decodeForGpu(blob.data() + at, blob.size() - at, ctx, &gpu), kCodecOk);
        const auto& steps = dynamic_cast<const RefinablePayload&>(*gpu);
        for (int i = 0; i <= kMaxIterations; ++i) {
            ASSERT_EQ(codec->decodeAttractor(attractor.data(), blob.data() + at, blob.size() - at,
                                             ctx, i),
                      kCodecOk);
            ASSERT_EQ(
                codec->decodePartial(partial.data(), blob.data() + at, blob.size() - at, ctx, i),
                kCodecOk);
            promised[i] = std::max(promised[i], (steps.stepBound(i) + codec->bound()) * scale);
            // Over the samples inside the raster (the patch's padding repeats them).
            for (int y = 0; y <= g.coveredCellsY(p); ++y)
                for (int x = 0; x <= g.coveredCellsX(p); ++x) {
                    const int sx = int(p.x) * (n - 1) + x, sy = int(p.y) * (n - 1) + y;
                    const double e = (double(attractor[size_t(y) * n + x]) -
                                      raster.grid.codes[size_t(sy) * raster.grid.width + sx]) *
                                     scale;
                    squares[i] += e * e;
                    worst[i] = std::max(worst[i], std::abs(e));
                    const double pe = (double(partial[size_t(y) * n + x]) -
                                       raster.grid.codes[size_t(sy) * raster.grid.width + sx]) *
                                      scale;
                    partial_worst[i] = std::max(partial_worst[i], std::abs(pe));
                    if (i == 0)
                        samples += 1.0;
                }
        }
    }
    std::printf("iterations  RMS m    max m   (attractor alone, %zu finest patches of %d², "
                "full codebook) | corrected max m, stored bound + E m\n",
                size_t(g.patchCount(level)), n);
    std::vector<double> rms(kMaxIterations + 1);
    for (int i = 0; i <= kMaxIterations; ++i) {
        rms[i] = std::sqrt(squares[i] / samples);
        std::printf("%10d %7.2f %8.1f | %8.1f %8.1f\n", i, rms[i], worst[i], partial_worst[i],
                    promised[i]);
        EXPECT_LE(partial_worst[i], promised[i] + 1e-9)
            << i << " iterations: the stored partial bound covers what is drawn";
    }
    EXPECT_LE(partial_worst[kMaxIterations], 2.0) << "the full decode holds E";
    EXPECT_LT(rms[8], 0.5 * rms[0]) << "the iteration approaches the terrain";
    EXPECT_LE(rms[10], rms[8] * 1.05) << "and settles by about 8 (the paper's observation)";
}

TEST(FractalBuild, AnArchiveRefusesThePapersModeWhichBoundsNoError)
{
    test::ScratchDir dir;
    BuildOptions options;
    options.patch_size = 33;
    options.codec = "fractal,mode=paper";
    options.max_error = 4.0;
    options.progress = {};
    const std::string out = dir.path("paper.ridge");
    try {
        buildArchive(test::dataPath("everest_crop.tif"), out, options);
        FAIL() << "built an archive without a bound";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bounds no error"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("codec-bench"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(out)) << "no half-written output";
}
