// The progressive codec end to end: build -> read back -> verify against the source.
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

using namespace ridge;

namespace {

BuildOptions progressive(double max_error, int patch = 33)
{
    BuildOptions o;
    o.patch_size = patch;
    o.codec = "progressive";
    o.max_error = max_error;
    return o;
}

// verify --source: |bilinear surface - source| <= Err(P) on every valid sample of every
// level, and every level sample within δ_l; nothing else may be reported either.
void expectEveryBoundHolds(const std::string& archive, const std::string& source)
{
    VerifyOptions options;
    options.source = source;
    const VerifyReport v = verifyArchive(archive, options);
    ASSERT_TRUE(v.ok()) << v.problems.front();
    ASSERT_TRUE(v.source_checked);
    for (const LevelVerifyReport& l : v.levels) {
        EXPECT_EQ(l.bound_violations, 0) << "level " << l.level;
        EXPECT_EQ(l.level_violations, 0) << "level " << l.level;
        EXPECT_LE(l.max_level_error, l.level_bound + 1e-9) << "level " << l.level;
    }
}

} // namespace

TEST(ProgressiveBuild, StrictBoundOnEverySampleOfEveryLevelForSeveralTilesAndBounds)
{
    test::ScratchDir dir;
    for (const char* name : {"everest_crop.tif", "rainier_voids.tif"}) {
        const std::string source = test::dataPath(name);
        for (const double e : {0.5, 1.0, 4.0, 16.0}) {
            SCOPED_TRACE(std::string(name) + " at " + std::to_string(e) + " m");
            const std::string out = dir.path("p.ridge");
            buildArchive(source, out, progressive(e));
            const archive::ArchiveReader reader(out);
            const int finest = reader.geometry().finestLevel();
            EXPECT_LE(reader.levelErrorBound(finest), e);
            // δ_l doubles per level above the finest, as in the paper.
            for (int l = finest - 1; l > 0; --l)
                EXPECT_LE(reader.levelErrorBound(l), e * std::ldexp(1.0, finest - l));
            expectEveryBoundHolds(out, source);

            // The decoded finest level really is within the bound of the ingested codes.
            const io::ElevationRaster raster = io::ingestRaster(source);
            const CodeGrid decoded = decodeLevel(reader, finest);
            ASSERT_EQ(decoded.codes.size(), raster.grid.codes.size());
            double worst = 0;
            for (size_t i = 0; i < decoded.codes.size(); ++i)
                worst = std::max(worst, std::fabs(double(decoded.codes[i]) - raster.grid.codes[i]) *
                                            raster.quantization.scale);
            EXPECT_LE(worst, e);
            if (e >= 1.0) {
                EXPECT_GT(worst, 0.0); // lossy for real: the bound is used, not sidestepped
            }
        }
    }
}

TEST(ProgressiveBuild, PaperVariantNevilleLevelsAndStoredBlockErrorsAllVerify)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    BuildOptions paper = progressive(2.0);
    paper.codec = "progressive-paper";
    buildArchive(source, dir.path("paper.ridge"), paper);
    expectEveryBoundHolds(dir.path("paper.ridge"), source);

    // Neville levels are not subsamples of the finer level: refinements take the escape.
    BuildOptions neville = progressive(1.0);
    neville.filter = PyramidFilter::Neville4;
    buildArchive(source, dir.path("neville.ridge"), neville);
    expectEveryBoundHolds(dir.path("neville.ridge"), source);

    // Stored λ are measured on the reconstruction, so they equal the derived ones.
    BuildOptions stored = progressive(1.0);
    stored.store_block_errors = true;
    buildArchive(source, dir.path("stored.ridge"), stored);
    buildArchive(source, dir.path("derived.ridge"), progressive(1.0));
    expectEveryBoundHolds(dir.path("stored.ridge"), source);
    const archive::ArchiveReader a(dir.path("stored.ridge")), b(dir.path("derived.ridge"));
    EXPECT_LT(std::filesystem::file_size(dir.path("derived.ridge")),
              std::filesystem::file_size(dir.path("stored.ridge")));
    for (int64_t i = 0; i < a.geometry().patchCount(); ++i) {
        const PatchId p = a.geometry().patchAt(i);
        const std::vector<float> sa = a.readBlockErrors(p), sb = b.readBlockErrors(p);
        ASSERT_EQ(sa.size(), sb.size());
        for (size_t k = 0; k < sa.size(); ++k)
            ASSERT_GE(sa[k], sb[k] * (1 - 1e-6f)) << i; // stored rounds up, never below
    }
}

TEST(ProgressiveBuild, RandomAccessToOnePatchMatchesTheLevelDecode)
{
    test::ScratchDir dir;
    const std::string out = dir.path("p.ridge");
    buildArchive(test::dataPath("rainier_voids.tif"), out, progressive(1.0, 17));
    const archive::ArchiveReader reader(out);
    const PyramidGeometry& g = reader.geometry();
    const int level = g.finestLevel(), n = g.patchSize();
    const DecodedPatches all =
        decodePatches(reader, level, 0, 0, g.patchesX(level) - 1, g.patchesY(level) - 1);
    std::vector<uint16_t> alone(static_cast<size_t>(n) * n), expected(alone.size());
    for (const PatchId p :
         {PatchId{level, 0, 0}, PatchId{level, g.patchesX(level) - 1, g.patchesY(level) - 1},
          PatchId{level, g.patchesX(level) / 2, 1}}) {
        reader.decodePatch(p, alone.data()); // no parent given: the reader decodes the ancestors
        all.copyPatch(p, n, expected.data());
        EXPECT_EQ(alone, expected);
    }
}

TEST(ProgressiveBuild, CompressesFarBetterThanLosslessAndRejectsAMissingBound)
{
    test::ScratchDir dir;
    const std::string source = test::dataPath("everest_crop.tif");
    BuildOptions lossless;
    lossless.patch_size = 33;
    buildArchive(source, dir.path("lossless.ridge"), lossless);
    buildArchive(source, dir.path("p4.ridge"), progressive(4.0));
    EXPECT_LT(std::filesystem::file_size(dir.path("p4.ridge")) * 2,
              std::filesystem::file_size(dir.path("lossless.ridge")));

    BuildOptions no_bound = progressive(1.0);
    no_bound.max_error.reset();
    EXPECT_THROW(buildArchive(source, dir.path("x.ridge"), no_bound), Error);
    EXPECT_FALSE(std::filesystem::exists(dir.path("x.ridge")));
}
