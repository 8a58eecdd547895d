// `ridge verify` checks what the levels of an archive imply for each other, which no field
// check at open can see (issue 23): coarse validity masks follow from the finest level's, the
// stored Err_Appr covers the interpolation error of the decoded levels, and with the source
// the finest validity matches its voids both ways. A patch that does not decode is one
// problem, not one per descendant decoded from it. Archives are real ones with one thing
// changed and every checksum recomputed; every real archive of the fixtures passes.
#include "archive_bytes.h"
#include "archive_craft.h"
#include "fixture_archives.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/core/error.h"
#include "ridge/io/raster_source.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

using namespace ridge;
using test::ArchiveBytes;
namespace eo = test::entry_offset;

namespace {

std::string build(const test::ScratchDir& dir, const std::string& name, const std::string& source,
                  int patch_size, io::VoidFill fill, PyramidFilter filter = PyramidFilter::Decimate,
                  const std::string& codec = "lossless")
{
    BuildOptions o;
    o.patch_size = patch_size;
    o.codec = codec;
    if (isLossyCodec(codec))
        o.max_error = 2.0;
    o.filter = filter;
    o.ingest.fill_voids = fill;
    o.progress = {};
    const std::string path = dir.path(name);
    buildArchive(test::dataPath(source), path, o);
    return path;
}

VerifyReport verify(const std::string& path, const std::string& source = "")
{
    VerifyOptions o;
    if (!source.empty())
        o.source = test::dataPath(source);
    return verifyArchive(path, o);
}

bool anyProblemHas(const VerifyReport& r, const std::string& phrase)
{
    return std::any_of(r.problems.begin(), r.problems.end(),
                       [&](const std::string& p) { return p.find(phrase) != std::string::npos; });
}

std::string allProblems(const VerifyReport& r)
{
    std::string out;
    for (const std::string& p : r.problems)
        out += p + "\n";
    return out.empty() ? "(verify said OK)" : out;
}

// `archive` with `edit` applied and resealed, saved as `crafted`.
std::string craft(const std::string& archive, const std::string& crafted,
                  const std::function<void(ArchiveBytes&, const archive::ArchiveReader&)>& edit)
{
    const archive::ArchiveReader reader(archive);
    ArchiveBytes bytes(archive);
    edit(bytes, reader);
    bytes.reseal();
    bytes.save(crafted);
    return crafted;
}

// Replaces the validity mask of patch `p` with `mask` (any size).
void setMask(ArchiveBytes& a, const archive::ArchiveReader& reader, PatchId p,
             const std::vector<uint8_t>& mask)
{
    const size_t entry = static_cast<size_t>(reader.geometry().patchIndex(p));
    const std::vector<uint8_t> blob = reader.readBlob(p);
    const size_t at = reader.record(p).block_errors_size;
    test::replaceBlobBytes(a, entry, at, at + test::validityMaskSize(blob, at), mask);
}

// The first patch of `level` whose stored mask has `kind`.
PatchId firstWithKind(const archive::ArchiveReader& reader, int level, PatchValidity::Kind kind)
{
    const PyramidGeometry& g = reader.geometry();
    for (int64_t i = g.firstPatchIndex(level); i < g.firstPatchIndex(level) + g.patchCount(level);
         ++i)
        if (reader.readValidity(g.patchAt(i)).kind == kind)
            return g.patchAt(i);
    return {-1, 0, 0};
}

} // namespace

TEST(VerifyCrossLevel, EveryArchiveTheFixturesBuildPasses)
{
    // The checks below must not cry wolf: every codec, filter and void mode, with and
    // without the source.
    test::ScratchDir dir;
    struct Case {
        const char* source;
        int patch;
        io::VoidFill fill;
        PyramidFilter filter;
        const char* codec;
    };
    const Case cases[] = {
        {"everest_crop.tif", 33, io::VoidFill::Interior, PyramidFilter::Decimate, "lossless"},
        {"everest_crop.tif", 17, io::VoidFill::Interior, PyramidFilter::Neville4, "progressive"},
        {"everest_crop.tif", 33, io::VoidFill::Interior, PyramidFilter::Decimate, "jpeg2000"},
        {"everest_utm44.tif", 17, io::VoidFill::Interior, PyramidFilter::Neville4, "lossless"},
        {"rainier_voids.tif", 17, io::VoidFill::None, PyramidFilter::Decimate, "progressive"},
        {"rainier_voids.tif", 17, io::VoidFill::Interior, PyramidFilter::Neville4, "raw"},
        {"rainier_voids.tif", 33, io::VoidFill::All, PyramidFilter::Decimate, "lossless"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.source) + " " + c.codec);
        const std::string path =
            build(dir, "ok.ridge", c.source, c.patch, c.fill, c.filter, c.codec);
        const VerifyReport plain = verify(path);
        EXPECT_TRUE(plain.ok()) << allProblems(plain);
        const VerifyReport full = verify(path, c.source);
        EXPECT_TRUE(full.ok()) << allProblems(full);
    }
}

TEST(VerifyCrossLevel, ACoarseMaskThatDoesNotFollowFromTheFinestLevelIsCaughtForBothFilters)
{
    test::ScratchDir dir;
    for (const PyramidFilter filter : {PyramidFilter::Decimate, PyramidFilter::Neville4}) {
        SCOPED_TRACE(filterName(filter));
        // "Nothing valid" on a level-1 patch of data: render then lacks that quadrant at
        // coarse LOD.
        const std::string everest =
            build(dir, "everest.ridge", "everest_crop.tif", 33, io::VoidFill::Interior, filter);
        const std::string none = craft(everest, dir.path("none.ridge"),
                                       [](ArchiveBytes& a, const archive::ArchiveReader& r) {
                                           setMask(a, r, {1, 0, 0}, {1});
                                       });
        for (const std::string source : {"", "everest_crop.tif"}) {
            const VerifyReport report = verify(none, source);
            EXPECT_TRUE(anyProblemHas(report,
                                      "patch (level 1, x 0, y 0): validity mask (0 of 1089 samples "
                                      "valid, 0 of 1024 cells drawable) differs from the one the "
                                      "finest level's sample validity determines (1089 of 1089"))
                << allProblems(report);
        }
        // The root's bitmap of a warped collar replaced by "all valid": drawn over the collar.
        const std::string utm =
            build(dir, "utm.ridge", "everest_utm44.tif", 17, io::VoidFill::Interior, filter);
        const PatchId root{0, 0, 0};
        ASSERT_EQ(archive::ArchiveReader(utm).readValidity(root).kind, PatchValidity::Kind::Mixed);
        const std::string all = craft(
            utm, dir.path("all.ridge"),
            [&](ArchiveBytes& a, const archive::ArchiveReader& r) { setMask(a, r, root, {0}); });
        const VerifyReport report = verify(all);
        EXPECT_TRUE(anyProblemHas(report, "patch (level 0, x 0, y 0): validity mask (289 of 289"))
            << allProblems(report);
    }
}

TEST(VerifyCrossLevel, ValidSamplesOverKeptSourceVoidsAreCaughtWithTheSource)
{
    // --fill-voids none keeps every void; a finest mask edited to "all valid" claims heights
    // there that extract would export. verify --source compared only the other direction.
    test::ScratchDir dir;
    const std::string none = build(dir, "none.ridge", "rainier_voids.tif", 17, io::VoidFill::None);
    const archive::ArchiveReader reader(none);
    const PatchId patch =
        firstWithKind(reader, reader.geometry().finestLevel(), PatchValidity::Kind::Mixed);
    ASSERT_GE(patch.level, 0);
    const std::string crafted =
        craft(none, dir.path("crafted.ridge"),
              [&](ArchiveBytes& a, const archive::ArchiveReader& r) { setMask(a, r, patch, {0}); });
    const VerifyReport report = verify(crafted, "rainier_voids.tif");
    EXPECT_TRUE(anyProblemHas(report, "finest samples are valid (drawn, exported as heights) "
                                      "where the source has voids that --fill-voids none keeps"))
        << allProblems(report);
}

TEST(VerifyCrossLevel, SourceVoidsThatTheFillModeFillsMustNotBeKept)
{
    // The other way round for --fill-voids all: a finest patch whose mask marks exactly the
    // source's voids invalid (a consistent mask, so only the source comparison can tell).
    test::ScratchDir dir;
    const std::string all = build(dir, "all.ridge", "rainier_voids.tif", 17, io::VoidFill::All);
    const archive::ArchiveReader reader(all);
    const PyramidGeometry& g = reader.geometry();
    io::ReferenceRaster source(test::dataPath("rainier_voids.tif"), io::IngestOptions{});
    std::vector<double> rows(static_cast<size_t>(g.width()) * g.height());
    source.readRows(0, g.height(), rows.data());
    const int n = g.patchSize(), c = n - 1, L = g.finestLevel();
    PatchId chosen{-1, 0, 0};
    PatchValidity mask;
    for (int y = 0; y < g.patchesY(L) && chosen.level < 0; ++y)
        for (int x = 0; x < g.patchesX(L) && chosen.level < 0; ++x) {
            PatchValidity v;
            v.kind = PatchValidity::Kind::Mixed;
            v.patch_size = n;
            v.samples.resize(static_cast<size_t>(n) * n);
            v.cells.resize(static_cast<size_t>(c) * c);
            int voids = 0;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const int sx = std::min(x * c + i, g.width() - 1);
                    const int sy = std::min(y * c + j, g.height() - 1);
                    const bool is_void = std::isnan(rows[static_cast<size_t>(sy) * g.width() + sx]);
                    v.samples[static_cast<size_t>(j) * n + i] = is_void ? 0 : 1;
                    voids += is_void;
                }
            for (int j = 0; j < c; ++j)
                for (int i = 0; i < c; ++i)
                    v.cells[static_cast<size_t>(j) * c + i] =
                        v.sampleValid(i, j) && v.sampleValid(i + 1, j) && v.sampleValid(i, j + 1) &&
                        v.sampleValid(i + 1, j + 1);
            if (voids > 0 && voids < n * n) {
                chosen = {L, x, y};
                mask = v;
            }
        }
    ASSERT_GE(chosen.level, 0) << "no finest patch of the fixture holds voids";
    const std::string crafted = craft(all, dir.path("crafted.ridge"),
                                      [&](ArchiveBytes& a, const archive::ArchiveReader& r) {
                                          setMask(a, r, chosen, archive::packValidity(mask, n));
                                      });
    const VerifyReport report = verify(crafted, "rainier_voids.tif");
    // Format v4 flags the filled voids, and a flag on a sample the mask calls nodata is
    // refused by the reader itself; either way the archive fails, naming what is wrong.
    EXPECT_TRUE(anyProblemHas(report, "finest samples are kept as nodata where the source has "
                                      "voids that --fill-voids all fills") ||
                anyProblemHas(report, "is flagged filled but is not valid"))
        << allProblems(report);
}

TEST(VerifyCrossLevel, AnUnderstatedErrApprIsCaughtWithoutTheSource)
{
    // Levels 0 and 1 claim no more than their children: consistent with every field check
    // at open (parent >= child, err = err_appr + δ), wrong by the interpolation error the
    // decoded levels show. Only --source caught it before.
    test::ScratchDir dir;
    for (const std::string codec : {"lossless", "progressive"}) {
        SCOPED_TRACE(codec);
        const std::string path = build(dir, codec + ".ridge", "everest_crop.tif", 33,
                                       io::VoidFill::Interior, PyramidFilter::Decimate, codec);
        const std::string crafted = craft(
            path, dir.path("crafted.ridge"), [](ArchiveBytes& a, const archive::ArchiveReader& r) {
                const PyramidGeometry& g = r.geometry();
                float level2 = 0.f;
                for (int64_t i = g.firstPatchIndex(2); i < g.firstPatchIndex(3); ++i)
                    level2 = std::max(level2, r.index()[i].err_appr);
                for (int64_t i = 0; i < g.firstPatchIndex(2); ++i) {
                    const double delta = r.levelErrorBound(g.patchAt(i).level);
                    float err = static_cast<float>(level2 + delta);
                    if (double(err) < double(level2) + delta)
                        err = std::nextafter(err, INFINITY);
                    a.setEntry<float>(static_cast<size_t>(i), eo::kErrAppr, level2);
                    a.setEntry<float>(static_cast<size_t>(i), eo::kErr, err);
                }
            });
        // The reader's field checks accept it: the lie is only in what the samples show.
        EXPECT_NO_THROW(archive::ArchiveReader{crafted});
        const VerifyReport report = verify(crafted);
        EXPECT_TRUE(anyProblemHas(report, "patch (level 0, x 0, y 0): stored Err_Appr"))
            << allProblems(report);
        EXPECT_TRUE(anyProblemHas(report, "is below Err_Int")) << allProblems(report);
    }
}

TEST(VerifyCrossLevel, OneBadRootIsOneProblemNotOnePerDescendant)
{
    // Progressive patches decode from their parent: every descendant of a bad root decoded
    // from zeros and was listed (42 problems); now the root is named once, with the count.
    test::ScratchDir dir;
    const std::string path = build(dir, "p.ridge", "everest_crop.tif", 33, io::VoidFill::Interior,
                                   PyramidFilter::Decimate, "progressive");
    const std::string crafted = craft(
        path, dir.path("crafted.ridge"), [](ArchiveBytes& a, const archive::ArchiveReader& r) {
            const PatchId root{0, 0, 0};
            const std::vector<uint8_t> blob = r.readBlob(root);
            const size_t payload = r.payloadOffset(root, blob);
            a.bytes()[r.record(root).offset + payload] ^= 0xFF; // the payload's magic byte
        });
    const VerifyReport report = verify(crafted);
    ASSERT_EQ(report.problems.size(), 1u) << allProblems(report);
    EXPECT_NE(report.problems[0].find("patch (level 0, x 0, y 0): cannot decode: bad payload "
                                      "header (the 98 patches below it decode from it and are "
                                      "not checked)"),
              std::string::npos)
        << report.problems[0];
    // With the source too: nothing is compared on the undecoded patches.
    EXPECT_EQ(verify(crafted, "everest_crop.tif").problems.size(), 1u);
}

TEST(VerifyCrossLevel, ACrsThatNothingCanReadIsAProblem)
{
    // The reader cannot parse WKT (only ridge_io talks to PROJ), so an archive whose CRS is
    // garbage opened everywhere and verify said OK, while extract refused to write it.
    test::ScratchDir dir;
    const std::string path = build(dir, "e.ridge", "everest_crop.tif", 33, io::VoidFill::Interior);
    const std::string crafted =
        craft(path, dir.path("crafted.ridge"), [](ArchiveBytes& a, const archive::ArchiveReader&) {
            nlohmann::json j = nlohmann::json::parse(a.metadata());
            j["georeference"]["crs_wkt"] = "GEOGCRS[\"broken";
            a.setMetadata(j.dump());
        });
    const VerifyReport report = verify(crafted);
    EXPECT_TRUE(anyProblemHas(report, "metadata: georeference.crs_wkt is not a CRS PROJ can read"))
        << allProblems(report);
}
