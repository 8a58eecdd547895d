#include "ridge/lod/arrival_blend.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

using namespace ridge;
using namespace ridge::lod;

namespace {

std::vector<SelectedPatch> patches(std::initializer_list<PatchId> ids)
{
    std::vector<SelectedPatch> out;
    for (PatchId p : ids)
        out.push_back(SelectedPatch{p});
    return out;
}

const PatchId kA{1, 0, 0};
const PatchId kChildren[4] = {{2, 0, 0}, {2, 1, 0}, {2, 0, 1}, {2, 1, 1}};

std::vector<SelectedPatch> children()
{
    return patches({kChildren[0], kChildren[1], kChildren[2], kChildren[3]});
}

// Streams the four children of kA in: one frame kA stands in for them, the next they are drawn.
struct Arrival {
    ArrivalBlends blends;
    std::set<std::pair<int, int>> evicted; // (level, x) of patches no longer resident
    double jump = 2.0;

    explicit Arrival(ArrivalBlendSettings s) : blends(s) {}
    void frame(const std::vector<SelectedPatch>& wanted, const std::vector<SelectedPatch>& drawn)
    {
        blends.advance(
            wanted, drawn,
            [&](PatchId p) {
                return !evicted.count({p.level, p.x});
            },
            [&](PatchId, PatchId) { return jump; });
    }
};

} // namespace

TEST(ArrivalBlends, AnArrivalFadesFromItsStandInByAtMostThePixelStepAFrameAndThenEnds)
{
    Arrival run(ArrivalBlendSettings{.max_frames = 32, .px_per_frame = 0.25});
    run.frame(children(), patches({kA})); // kA stands in for its missing children
    EXPECT_EQ(run.blends.fading(), 0u);
    // They arrive: a jump of up to 2 px at 0.25 px a frame is 8 steps.
    std::vector<float> weights;
    for (int f = 0; f < 12; ++f) {
        run.frame(children(), children());
        const std::optional<ArrivalBlend> b = run.blends.of(kChildren[2]);
        weights.push_back(b ? b->links[0].weight : 0.f);
        for (PatchId c : kChildren) // siblings fade together (their seams stay closed)
            EXPECT_EQ(run.blends.of(c).has_value(), b.has_value());
        if (b) {
            EXPECT_EQ(b->links[0].from, kA);
            EXPECT_EQ(b->depth, 1);
        }
    }
    float previous = 1.f; // kA's surface, as drawn the frame before
    for (size_t f = 0; f < weights.size(); ++f) {
        EXPECT_NEAR(weights[f], std::max(0.0, 1.0 - double(f + 1) / 8.0), 1e-6) << f;
        // The surface moves by |Δw| of the jump a frame: at most the step asked for.
        EXPECT_LE((previous - weights[f]) * run.jump, 0.25 + 1e-6) << f;
        previous = weights[f];
    }
    EXPECT_EQ(weights[7], 0.f); // the 8th frame draws the patch's own surface
    EXPECT_EQ(run.blends.fading(), 0u);
}

TEST(ArrivalBlends, OnlyArrivalsFadeNotChangesOfLevelOverASelectedAncestor)
{
    Arrival run(ArrivalBlendSettings{});
    run.frame(patches({kA}), patches({kA})); // kA wanted and drawn: an LOD choice
    run.frame(children(), children());       // the selection refines: the scheme's business
    EXPECT_EQ(run.blends.fading(), 0u);
    // Coarsening back is not an arrival either.
    run.frame(patches({kA}), patches({kA}));
    EXPECT_EQ(run.blends.fading(), 0u);
}

TEST(ArrivalBlends, AGrandchildFadesFromTheAncestorThatStoodInTwoLevelsUp)
{
    Arrival run(ArrivalBlendSettings{});
    const PatchId g{3, 1, 1};
    run.frame(patches({g}), patches({kA}));
    run.frame(patches({g}), patches({g}));
    ASSERT_TRUE(run.blends.of(g).has_value());
    EXPECT_EQ(run.blends.of(g)->links[0].from, kA);
}

TEST(ArrivalBlends, AFadeEndsWhenItsAncestorLeavesTheGpu)
{
    Arrival run(ArrivalBlendSettings{});
    run.frame(children(), patches({kA}));
    run.frame(children(), children());
    ASSERT_EQ(run.blends.fading(), 4u);
    run.evicted.insert({kA.level, kA.x});
    run.frame(children(), children());
    EXPECT_EQ(run.blends.fading(), 0u);
    // Nor does an arrival start from an ancestor that is gone.
    Arrival gone(ArrivalBlendSettings{});
    gone.frame(children(), patches({kA}));
    gone.evicted.insert({kA.level, kA.x});
    gone.frame(children(), children());
    EXPECT_EQ(gone.blends.fading(), 0u);
}

TEST(ArrivalBlends, TheFadeLastsWhatTheJumpNeedsWithinTheLongestFade)
{
    auto framesFor = [](double jump, int max_frames) {
        Arrival run(ArrivalBlendSettings{.max_frames = max_frames, .px_per_frame = 0.5});
        run.jump = jump;
        run.frame(children(), patches({kA}));
        run.frame(children(), children());
        const std::optional<ArrivalBlend> b = run.blends.of(kChildren[0]);
        // w = 1 − 1/n on the arrival frame.
        return b ? int(std::lround(1.0 / (1.0 - double(b->links[0].weight)))) : 1;
    };
    EXPECT_EQ(framesFor(0.4, 32), 1); // within a step: replaced at once
    EXPECT_EQ(framesFor(0.6, 32), 2);
    EXPECT_EQ(framesFor(5.0, 32), 10);
    EXPECT_EQ(framesFor(100.0, 32), 32);                                   // bounded in time
    EXPECT_EQ(framesFor(std::numeric_limits<double>::infinity(), 20), 20); // camera inside
    EXPECT_EQ(framesFor(std::nan(""), 20), 20);
    EXPECT_EQ(framesFor(100.0, 0), 1); // fading off
}

TEST(ArrivalBlends, ResetForgetsTheStandInsAndTheFades)
{
    Arrival run(ArrivalBlendSettings{});
    run.frame(children(), patches({kA}));
    run.frame(children(), children());
    ASSERT_GT(run.blends.fading(), 0u);
    run.blends.reset();
    EXPECT_EQ(run.blends.fading(), 0u);
    run.frame(children(), children()); // no last frame: nothing arrives
    EXPECT_EQ(run.blends.fading(), 0u);
}

TEST(ArrivalBlends, SettingsOutsideTheirRangesAreRefusedByName)
{
    for (const ArrivalBlendSettings s :
         {ArrivalBlendSettings{.max_frames = -1}, ArrivalBlendSettings{.max_frames = 10001},
          ArrivalBlendSettings{.px_per_frame = 0.0},
          ArrivalBlendSettings{.px_per_frame = std::nan("")},
          ArrivalBlendSettings{.px_per_frame = INFINITY}}) {
        try {
            ArrivalBlends b(s);
            ADD_FAILURE() << "accepted " << s.max_frames << " " << s.px_per_frame;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("arrival blend"), std::string::npos) << e.what();
        }
    }
}

TEST(ArrivalBlends, ACascadeOfArrivalsStartsOnTheSurfaceDrawnAndKeepsTheFadesBeneath)
{
    Arrival run(ArrivalBlendSettings{.max_frames = 32, .px_per_frame = 0.25});
    const PatchId root{0, 0, 0};
    run.frame(children(), patches({root})); // the root stands in
    run.frame(children(), patches({kA}));   // kA arrives, standing in for its children
    const std::optional<ArrivalBlend> parent = run.blends.of(kA);
    ASSERT_TRUE(parent.has_value());
    ASSERT_EQ(parent->depth, 1);
    EXPECT_EQ(parent->links[0].from, root);
    run.frame(children(), children()); // the children arrive while kA still fades
    const std::optional<ArrivalBlend> child = run.blends.of(kChildren[1]);
    ASSERT_TRUE(child.has_value());
    ASSERT_EQ(child->depth, 2);
    EXPECT_EQ(child->links[0].from, kA);
    EXPECT_EQ(child->links[1].from, root);
    // Beneath, kA's fade as it was drawn: the children start on the surface of the frame before.
    EXPECT_FLOAT_EQ(child->links[1].weight, parent->links[0].weight);
    run.frame(children(), children());
    const std::optional<ArrivalBlend> on = run.blends.of(kChildren[1]);
    ASSERT_TRUE(on.has_value());
    EXPECT_LT(on->links[1].weight, child->links[1].weight); // and goes on
    EXPECT_LT(on->links[0].weight, child->links[0].weight);
}

// A surface as the shaders draw it: the patch's own height mixed with the chain's (each
// ancestor's height given by `height`).
double drawnSurface(double own, const ArrivalBlend& b, const std::function<double(PatchId)>& height)
{
    double s = height(b.links[size_t(b.depth - 1)].from);
    for (int i = b.depth - 2; i >= 0; --i)
        s = height(b.links[size_t(i)].from) * (1.0 - b.links[size_t(i + 1)].weight) +
            s * b.links[size_t(i + 1)].weight;
    return own * (1.0 - b.links[0].weight) + s * b.links[0].weight;
}

TEST(ArrivalBlends, ADeepCascadeMovesTheSurfaceByLittleAFrameAndKeepsAtMostTheLongestChain)
{
    // Levels 1..7 over one point arrive one a frame (each standing in for the next): what is
    // drawn there moves by at most a step a frame while the chain fits, and by the least share
    // when it is cut. Heights: level L at 100·L metres, a jump of 100 px a level.
    ArrivalBlendSettings settings{.max_frames = 1000, .px_per_frame = 1.0};
    ArrivalBlends blends(settings);
    auto height = [](PatchId p) { return 100.0 * p.level; };
    auto jump = [](PatchId a, PatchId b) {
        return 1.0 * std::abs(double(b.level - a.level)) * 100;
    };
    auto resident = [](PatchId) { return true; };
    PatchId wanted{8, 0, 0};
    double before = height({0, 0, 0});
    blends.advance(patches({wanted}), patches({{0, 0, 0}}), resident, jump);
    int max_depth = 0;
    for (int level = 1; level <= 8; ++level) {
        const PatchId p{level, 0, 0};
        blends.advance(patches({wanted}), patches({p}), resident, jump);
        const std::optional<ArrivalBlend> b = blends.of(p);
        ASSERT_TRUE(b.has_value()) << level;
        max_depth = std::max(max_depth, b->depth);
        const double now = drawnSurface(height(p), *b, height);
        // The new patch's own step (100·level px over at most 1000 frames), and what cutting
        // the chain past its longest drops: bounded, far below the 100 m a level.
        EXPECT_LE(std::abs(now - before), level <= ArrivalBlend::kMaxDepth ? 1.0 : 2.0) << level;
        before = now;
    }
    EXPECT_EQ(max_depth, ArrivalBlend::kMaxDepth);
}
