// Bytes fetched per view on the Everest fixture: the renderer's selection, every ancestor of
// it counted once for the progressive codec, none for the lossless one.
#include "fixture_archives.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/stream/view_bytes.h"

#include <gtest/gtest.h>

#include <set>

using namespace ridge;
using stream::TypicalView;

namespace {

constexpr lod::Viewport kFullHd{1920, 1080};

// The brute-force count: every selected patch and, if asked, every ancestor, into a set.
uint64_t bruteForceBytes(const archive::ArchiveReader& reader, const lod::Selection& selection,
                         bool with_ancestors, size_t& patches)
{
    const PyramidGeometry& g = reader.geometry();
    std::set<int64_t> unique;
    for (const lod::SelectedPatch& s : selection.patches) {
        unique.insert(g.patchIndex(s.id));
        if (with_ancestors)
            for (PatchId p = s.id; p.level > 0;) {
                p = p.parent();
                unique.insert(g.patchIndex(p));
            }
    }
    uint64_t bytes = 0;
    for (const int64_t i : unique)
        bytes += reader.index()[size_t(i)].size;
    patches = unique.size();
    return bytes;
}

struct Counted {
    stream::ViewBytes bytes;
    lod::Selection selection;
};

Counted countView(const archive::ArchiveReader& reader, const lod::PatchQuadtree& quadtree,
                  TypicalView view, lod::Viewport viewport = kFullHd)
{
    const lod::Camera camera = stream::typicalViewCamera(quadtree, view, viewport);
    const lod::SelectionSettings settings = stream::rendererSelectionSettings(2.0, 1.0);
    return {stream::viewBytes(reader, quadtree, camera, settings),
            quadtree.select(camera, settings)};
}

} // namespace

TEST(ViewBytes, ProgressiveViewsCountEveryAncestorOnceAndNothingElse)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "progressive"));
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(reader);
    const PyramidGeometry& g = reader.geometry();
    for (const TypicalView view : stream::kTypicalViews) {
        const Counted c = countView(reader, quadtree, view);
        const std::string name = stream::typicalViewName(view);
        EXPECT_TRUE(c.bytes.counts_ancestors) << name;
        EXPECT_EQ(c.bytes.selected, c.selection.patches.size()) << name;
        ASSERT_GT(c.bytes.selected, 0u) << name << ": the view must see the terrain";
        size_t unique = 0;
        EXPECT_EQ(c.bytes.bytes, bruteForceBytes(reader, c.selection, true, unique)) << name;
        EXPECT_EQ(c.bytes.patches, unique) << name;

        // The fetched set is closed under parent(): a progressive decode never lacks one.
        std::vector<lod::SelectedPatch> selected = c.selection.patches;
        const std::vector<PatchId> fetched = stream::patchesToFetch(g, selected, true);
        std::set<int64_t> in_set;
        for (const PatchId p : fetched)
            in_set.insert(g.patchIndex(p));
        EXPECT_EQ(in_set.size(), fetched.size()) << name << ": a patch counted twice";
        for (const PatchId p : fetched)
            if (p.level > 0) {
                EXPECT_TRUE(in_set.count(g.patchIndex(p.parent())))
                    << name << ": " << archive::ArchiveReader::patchName(p)
                    << " without its parent";
            }
        for (const lod::SelectedPatch& s : selected)
            EXPECT_TRUE(in_set.count(g.patchIndex(s.id))) << name;
    }
}

TEST(ViewBytes, OnATerrainThatOutresolvesTheScreenTheFarViewFetchesFewerBytesThanTheNear)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "progressive"));
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(reader);
    // The fixture is 301 samples across: at 64 x 36 pixels it out-resolves the screen about
    // 5 times, as the Sierra mosaic (10801 across) does a 1920-pixel one. At full HD it has
    // fewer samples than pixels, and a view of all of it needs nearly every finest patch.
    const lod::Viewport viewport{64, 36};
    const Counted near_view = countView(reader, quadtree, TypicalView::Near, viewport);
    const Counted far_view = countView(reader, quadtree, TypicalView::Far, viewport);
    EXPECT_LT(far_view.bytes.bytes, near_view.bytes.bytes);
    // Both stay within the archive: every blob at most once.
    uint64_t all = 0;
    for (const archive::PatchRecord& r : reader.index())
        all += r.size;
    EXPECT_LE(near_view.bytes.bytes, all);
}

TEST(ViewBytes, LosslessViewsCountTheSelectedPatchesAlone)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "lossless"));
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(reader);
    for (const TypicalView view : stream::kTypicalViews) {
        const Counted c = countView(reader, quadtree, view);
        const std::string name = stream::typicalViewName(view);
        EXPECT_FALSE(c.bytes.counts_ancestors) << name;
        EXPECT_EQ(c.bytes.patches, c.bytes.selected) << name << ": no ancestor counted";
        size_t unique = 0;
        EXPECT_EQ(c.bytes.bytes, bruteForceBytes(reader, c.selection, false, unique)) << name;
    }
}

TEST(ViewBytes, TheConvenienceOverloadRunsTheSameSelection)
{
    test::ScratchDir dir;
    const archive::ArchiveReader reader(test::buildEverestArchive(dir, "progressive"));
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(reader);
    const lod::Camera camera = stream::typicalViewCamera(quadtree, TypicalView::Mid, kFullHd);
    const stream::ViewBytes a = stream::viewBytes(reader, camera, 2.0, 1.0);
    const stream::ViewBytes b =
        stream::viewBytes(reader, quadtree, camera, stream::rendererSelectionSettings(2.0, 1.0));
    EXPECT_EQ(a.bytes, b.bytes);
    EXPECT_EQ(a.selected, b.selected);
}
