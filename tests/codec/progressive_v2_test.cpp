// Progressive codec v2's and v3's parts: rANS, tokens, per-archive tables, coded regions,
// training, and the payload bytes of every format pinned.
#include "ridge/codec/level_quantizer.h"
#include "ridge/codec/progressive_codec.h"
#include "ridge/codec/progressive_tables.h"
#include "ridge/codec/progressive_tokens.h"
#include "ridge/codec/rans_coder.h"
#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace ridge;

namespace {

std::vector<uint16_t> terrainPatch(int n, uint32_t seed, int noise)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> jitter(-noise, noise);
    std::vector<uint16_t> v(static_cast<size_t>(n) * n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            v[y * n + x] = static_cast<uint16_t>(
                std::clamp(30000 + int(900 * std::sin(x * 0.07 + seed) + 600 * std::cos(y * 0.05)) +
                               jitter(rng),
                           0, 65535));
    return v;
}

std::vector<uint8_t> encode(const ProgressiveCodec& codec, const std::vector<uint16_t>& codes,
                            const PatchContext& ctx)
{
    std::vector<uint8_t> payload(codec.encodeBound(ctx));
    payload.resize(codec.encode(payload.data(), payload.size(), codes.data(), ctx));
    return payload;
}

// A root patch of 65², its reconstruction under `codec`, and four children: what the
// training tests observe.
struct TrainingFamily {
    static constexpr int n = 65;
    std::vector<uint16_t> root, root_drawn;
    std::vector<std::vector<uint16_t>> children;

    TrainingFamily(const ProgressiveCodec& codec, uint32_t child_seed, int child_noise)
        : root(terrainPatch(n, 1, 3)), root_drawn(root.size())
    {
        codec.reconstruct(root.data(), {n, 0, nullptr, 0}, root_drawn.data());
        for (int c = 0; c < 4; ++c)
            children.push_back(terrainPatch(n, child_seed + uint32_t(c), child_noise));
    }
};

rans::Table tableOf(std::vector<uint16_t> freq)
{
    rans::Table t;
    t.assign(freq.data(), static_cast<int>(freq.size()));
    return t;
}

} // namespace

TEST(Rans, InterleavedLanesRoundTripSymbolsOfSeveralTablesExactly)
{
    const rans::Table skewed = tableOf({4000, 60, 30, 6});
    const rans::Table flat = tableOf(std::vector<uint16_t>(64, 64));
    const rans::Table certain = tableOf({4096});
    std::mt19937 rng(5);
    struct Coded {
        const rans::Table* table;
        int symbol;
    };
    std::vector<Coded> symbols;
    for (int i = 0; i < 30001; ++i) {
        const int pick = int(rng() % 3);
        const rans::Table& t = pick == 0 ? skewed : pick == 1 ? flat : certain;
        int s = int(rng() % uint32_t(t.symbols));
        if (&t == &skewed)
            s = (rng() % 100) < 97 ? 0 : s;
        symbols.push_back({&t, s});
    }
    rans::Encoder enc;
    for (const Coded& c : symbols)
        enc.put(*c.table, c.symbol);
    std::vector<uint8_t> stream;
    enc.finish(stream);
    rans::Decoder dec(stream.data(), stream.size());
    for (size_t i = 0; i < symbols.size(); ++i)
        ASSERT_EQ(dec.decode(*symbols[i].table, int(i % rans::kLanes)), symbols[i].symbol) << i;
    EXPECT_TRUE(dec.finishedExactly());

    // Runs (v3's rows): the same symbols, whatever the runs' lengths and wherever the lanes
    // stand when one starts, down to the stream's last words.
    rans::Decoder runs(stream.data(), stream.size());
    std::vector<const rans::Table*> tables;
    unsigned lane = 0;
    for (size_t first = 0, length = 1; first < symbols.size();
         first += length, length = length % 9 + 1) {
        const size_t count = std::min(length, symbols.size() - first);
        tables.clear();
        for (size_t k = 0; k < count; ++k)
            tables.push_back(symbols[first + k].table);
        runs.decodeRun(tables.data(), int(count), lane, [&](int k, int s) {
            ASSERT_EQ(s, symbols[first + size_t(k)].symbol) << first + size_t(k);
        });
        ASSERT_EQ(lane % rans::kLanes, (first + count) % rans::kLanes);
    }
    EXPECT_TRUE(runs.finishedExactly());

    // Truncated or corrupted: never finishes exactly.
    rans::Decoder cut(stream.data(), stream.size() - 2);
    for (size_t i = 0; i < symbols.size(); ++i)
        cut.decode(*symbols[i].table, int(i % rans::kLanes));
    EXPECT_FALSE(cut.finishedExactly());
    EXPECT_TRUE(cut.overrun());
    std::vector<uint8_t> bad = stream;
    bad[bad.size() / 2] ^= 0x10;
    rans::Decoder flipped(bad.data(), bad.size());
    for (size_t i = 0; i < symbols.size(); ++i)
        flipped.decode(*symbols[i].table, int(i % rans::kLanes));
    EXPECT_FALSE(flipped.finishedExactly());
}

TEST(ProgressiveTokens, EveryResidualRoundTripsThroughTokenAndRawBits)
{
    for (int32_t d = -progressive_tokens::kMaxMagnitude; d <= progressive_tokens::kMaxMagnitude;
         ++d) {
        const progressive_tokens::Token t = progressive_tokens::tokenize(d);
        ASSERT_GE(t.symbol, 0);
        ASSERT_LT(t.symbol, progressive_tables::kSymbols);
        ASSERT_EQ(t.raw_count, progressive_tokens::rawCount(t.symbol)) << d;
        ASSERT_LT(uint64_t(t.raw), uint64_t(1) << t.raw_count) << d;
        ASSERT_EQ(progressive_tokens::residual(t.symbol, t.raw), d);
    }
}

TEST(LevelQuantizer, ReciprocalQuantizationEqualsDivisionForEveryCode)
{
    for (const double e : {0.0, 1.0, 2.0, 7.5, 100.0, 4095.0, 32767.0, 65535.0})
        for (int k = 0; k <= 2; ++k) {
            const LevelQuantizer q = LevelQuantizer::make(e, k);
            for (int h = 0; h <= 65535; ++h)
                ASSERT_EQ(q.quantize(uint16_t(h)), int32_t((h + q.bound) / q.step))
                    << "bound " << q.bound << " code " << h;
        }
}

TEST(ProgressiveTables, FittedTablesRoundTripTheirBytesAndBadBytesAreRejected)
{
    SymbolCounts counts(3);
    std::mt19937 rng(9);
    for (int l = 0; l < 3; ++l)
        for (int c = 0; c < progressive_tables::kClasses; ++c)
            for (int x = 0; x < progressive_tables::kContexts; x += 3)
                for (int i = 0; i < 20000; ++i)
                    ++counts.at(
                        l, c, x,
                        std::min(int(std::abs(std::normal_distribution<>(0, 1 + x)(rng))) * 2, 70));
    const auto fitted = ProgressiveTables::fit(counts);
    ASSERT_GT(fitted->storedCount(), 0);
    const std::vector<uint8_t> bytes = fitted->serialize();
    std::string problem;
    const auto back = ProgressiveTables::parse(bytes.data(), bytes.size(), 3,
                                               progressive_tables::kContexts, &problem);
    ASSERT_NE(back, nullptr) << problem;
    EXPECT_EQ(back->serialize(), bytes);
    for (int l = 0; l < 3; ++l)
        for (int c = 0; c < progressive_tables::kClasses; ++c)
            for (int x = 0; x < progressive_tables::kContexts; ++x)
                ASSERT_EQ(back->table(l, c, x).freq, fitted->table(l, c, x).freq);
    // A stored table must pay for itself: the fitted one costs no more bits than the default.
    for (int c = 0; c < progressive_tables::kClasses; ++c)
        EXPECT_LE(ProgressiveTables::cost(counts.histogram(0, c, 3), fitted->table(0, c, 3)),
                  ProgressiveTables::cost(counts.histogram(0, c, 3),
                                          ProgressiveTables::defaults(3)->table(0, c, 3)));

    auto rejects = [&](std::vector<uint8_t> b, int levels, const std::string& phrase) {
        std::string why;
        EXPECT_EQ(ProgressiveTables::parse(b.data(), b.size(), levels,
                                           progressive_tables::kContexts, &why),
                  nullptr)
            << phrase;
        EXPECT_NE(why.find(phrase), std::string::npos) << why;
    };
    rejects(bytes, 4, "are for 3 levels");
    std::vector<uint8_t> b = bytes;
    b[0] = 'X';
    rejects(b, 3, "'T'");
    b = bytes;
    b[1] = 2;
    rejects(b, 3, "version");
    b = bytes;
    b.push_back(0);
    rejects(b, 3, "trailing");
    rejects(std::vector<uint8_t>(bytes.begin(), bytes.end() - 1), 3, "truncated");
    b = bytes;
    b[3] = 2; // the predictor weights flag
    rejects(b, 3, "must be 0 or 1");
    b = bytes;
    b[4] = 72; // the first table's symbol count
    rejects(b, 3, "at most 71");
    // A frequency changed: the sum is off.
    b = bytes;
    size_t first_stored = 4;
    while (b[first_stored] == 0)
        ++first_stored;
    ASSERT_LT(b[first_stored], 0x80);
    b[first_stored + 1] ^= 1;
    rejects(b, 3, "sum to");
    // No tables at all is an empty region, not a region of default entries.
    std::vector<uint8_t> empty{'T', 1, 1, 0};
    empty.resize(4 + progressive_tables::kClasses * progressive_tables::kContexts, 0);
    rejects(empty, 1, "store no table");

    // Predictor weights: stored for levels 1.., each within ±4095, not all zero when flagged.
    std::vector<PredictorWeights> w(3);
    w[2].w[1][4] = -1234;
    const auto weighted = ProgressiveTables::withWeights(w);
    const std::vector<uint8_t> wb = weighted->serialize();
    ASSERT_EQ(wb.size(), 4 + 2 * 36 * 2 + size_t(3 * 64));
    const auto wback =
        ProgressiveTables::parse(wb.data(), wb.size(), 3, progressive_tables::kContexts, &problem);
    ASSERT_NE(wback, nullptr) << problem;
    EXPECT_EQ(wback->weights(1), nullptr);
    ASSERT_NE(wback->weights(2), nullptr);
    EXPECT_EQ(wback->weights(2)->w[1][4], -1234);
    b = wb;
    const size_t at = 4 + (36 + 12 + 4) * 2; // level 2, class B, tap 4
    b[at] = 0x00;
    b[at + 1] = 0x10; // 4096
    rejects(b, 3, "within ±4095");
    b = wb;
    b[at] = 0;
    b[at + 1] = 0;
    rejects(b, 3, "all 0");
}

TEST(ProgressiveTables, DefaultsArePinned)
{
    // Every reader rebuilds the defaults: they are part of the format (docs/FORMAT.md). A change
    // of their generator changes these sums and breaks every archive that relies on them.
    const auto d = ProgressiveTables::defaults(2);
    uint64_t digest = 1469598103934665603ull;
    for (int c = 0; c < progressive_tables::kClasses; ++c)
        for (int x = 0; x < progressive_tables::kContexts; ++x)
            for (int s = 0; s < progressive_tables::kSymbols; ++s)
                digest = (digest ^ d->table(1, c, x).freq[s]) * 1099511628211ull;
    EXPECT_EQ(d->table(0, 0, 0).freq[0], 2464);
    EXPECT_EQ(d->table(1, 0, 0).freq[0], 3214);
    EXPECT_EQ(digest, 1228109806224266157ull);

    // Payload v4's: the activity's tables for class 0, scaled by the parent class elsewhere.
    const auto d4 = ProgressiveTables::defaults(2, progressive_tables::kContextsV4);
    uint64_t digest4 = 1469598103934665603ull;
    for (int c = 0; c < progressive_tables::kClasses; ++c)
        for (int x = 0; x < progressive_tables::kContextsV4; ++x)
            for (int s = 0; s < progressive_tables::kSymbols; ++s)
                digest4 = (digest4 ^ d4->table(1, c, x).freq[s]) * 1099511628211ull;
    EXPECT_EQ(d4->table(0, 0, 3).freq[0], d->table(0, 0, 3).freq[0]);
    EXPECT_EQ(d4->table(1, 1, 16 + 5).freq[0], d->table(1, 1, 5).freq[0]); // parent class 1
    EXPECT_GT(d4->table(1, 1, 5).freq[0], d4->table(1, 1, 16 + 5).freq[0]);
    EXPECT_GT(d4->table(1, 1, 16 + 5).freq[0], d4->table(1, 1, 32 + 5).freq[0]);
    EXPECT_EQ(digest4, 6183447825476605637ull);
}

// Tables version 2 (payload v4): 48 contexts per class, a bitmap of the stored ones.
TEST(ProgressiveTables, ParentClassTablesRoundTripTheirBitmapAndBadBitmapsAreRejected)
{
    using progressive_tables::kContextsV4;
    SymbolCounts counts(3, kContextsV4);
    std::mt19937 rng(5);
    for (int l = 0; l < 3; ++l)
        for (int c = 0; c < progressive_tables::kClasses; ++c)
            for (int x = c == 0 ? 0 : 7; x < (c == 0 ? 16 : kContextsV4); x += 5)
                for (int i = 0; i < 20000; ++i)
                    ++counts.at(
                        l, c, x,
                        std::min(int(std::abs(std::normal_distribution<>(0, 1 + x % 16)(rng))) * 2,
                                 70));
    const auto fitted = ProgressiveTables::fit(counts);
    ASSERT_EQ(fitted->contexts(), kContextsV4);
    ASSERT_GT(fitted->storedCount(), 0);
    const std::vector<uint8_t> bytes = fitted->serialize();
    ASSERT_EQ(bytes[1], 2); // tables version 2
    const size_t bitmap_bytes = (3 * 4 * kContextsV4 + 7) / 8;
    std::string problem;
    const auto back =
        ProgressiveTables::parse(bytes.data(), bytes.size(), 3, kContextsV4, &problem);
    ASSERT_NE(back, nullptr) << problem;
    EXPECT_EQ(back->serialize(), bytes);
    for (int l = 0; l < 3; ++l)
        for (int c = 0; c < progressive_tables::kClasses; ++c)
            for (int x = 0; x < kContextsV4; ++x)
                ASSERT_EQ(back->table(l, c, x).freq, fitted->table(l, c, x).freq);

    auto rejects = [&](std::vector<uint8_t> b, int contexts, const std::string& phrase) {
        std::string why;
        EXPECT_EQ(ProgressiveTables::parse(b.data(), b.size(), 3, contexts, &why), nullptr)
            << phrase;
        EXPECT_NE(why.find(phrase), std::string::npos) << why;
    };
    // Each version is its payload's: v4's tables are not v3's and the other way round.
    rejects(bytes, progressive_tables::kContexts, "must be 1 for this payload version");
    rejects(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 4 + bitmap_bytes - 1), kContextsV4,
            "truncated in the stored-table bitmap");
    // The bitmap's first byte covers level 0, class 0, contexts 0..7: mark one not stored
    // and the next table's bytes are read where they are not.
    std::vector<uint8_t> b = bytes;
    ASSERT_NE(b[4], 0);
    b[4] &= uint8_t(b[4] - 1); // clear the lowest set bit
    rejects(b, kContextsV4, "trailing");
    // Class 0 has activity contexts only: its tables 16..47 are never stored.
    b = bytes;
    b[4 + 2] |= 1; // table 16 = level 0, class 0, context 16
    rejects(b, kContextsV4, "class 0 has no context 16");
    // A table marked stored must hold symbols.
    SymbolCounts one(1, kContextsV4);
    for (int i = 0; i < 50000; ++i)
        ++one.at(0, 1, 20, std::min(int(std::abs(std::normal_distribution<>(0, 4)(rng))), 70));
    std::vector<uint8_t> single = ProgressiveTables::fit(one)->serialize();
    const size_t single_bitmap = (4 * kContextsV4 + 7) / 8;
    ASSERT_GT(single.size(), 4 + single_bitmap);
    single.resize(4 + single_bitmap + 1);
    single.back() = 0; // S = 0
    std::string why;
    EXPECT_EQ(ProgressiveTables::parse(single.data(), single.size(), 1, kContextsV4, &why),
              nullptr);
    EXPECT_NE(why.find("marked stored with 0 symbols"), std::string::npos) << why;
}

TEST(ProgressiveCodecV2, CodesOnlyTheRegionAndRepeatsItsEdgeBeyond)
{
    const int n = 33;
    const ProgressiveCodec codec(1, 3);
    const std::vector<uint16_t> root = terrainPatch(n, 3, 20), codes = terrainPatch(n, 4, 20);
    for (const auto& [sx, sy] : {std::pair{33, 33}, std::pair{10, 33}, std::pair{33, 2},
                                 std::pair{5, 7}, std::pair{2, 2}}) {
        const PatchContext root_ctx{n, 0, nullptr, 0, sx, sy};
        std::vector<uint16_t> root_drawn(root.size()), decoded(root.size());
        codec.reconstruct(root.data(), root_ctx, root_drawn.data());
        const std::vector<uint8_t> root_payload = encode(codec, root, root_ctx);
        ASSERT_EQ(codec.decode(decoded.data(), root_payload.data(), root_payload.size(), root_ctx),
                  kCodecOk);
        EXPECT_EQ(decoded, root_drawn);
        const CodedRegion r = codec.codedRegion(root_ctx);
        EXPECT_EQ(r.width % 2, 1);
        EXPECT_GE(r.width, std::max(3, std::min(sx, n)));
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const int iy = std::min(y, r.height - 1), ix = std::min(x, r.width - 1);
                ASSERT_EQ(decoded[y * n + x], decoded[iy * n + ix]) << x << "," << y;
                if (x < r.width && y < r.height) {
                    ASSERT_LE(std::abs(int(decoded[y * n + x]) - int(root[y * n + x])), 1);
                }
            }
        for (int child = 0; child < 4; ++child) {
            const PatchContext ctx{n, 1, root_drawn.data(), child, sx, sy};
            std::vector<uint16_t> expected(codes.size());
            codec.reconstruct(codes.data(), ctx, expected.data());
            const std::vector<uint8_t> payload = encode(codec, codes, ctx);
            ASSERT_EQ(codec.decode(decoded.data(), payload.data(), payload.size(), ctx), kCodecOk);
            ASSERT_EQ(decoded, expected) << sx << "x" << sy << " child " << child;
        }
        if (sx < n) { // fewer samples, fewer bytes
            const PatchContext whole{n, 0, nullptr, 0};
            EXPECT_LT(root_payload.size(), encode(codec, root, whole).size());
        }
    }
}

TEST(ProgressiveCodecV2, TrainedTablesCodeTheirOwnPatchesSmallerAndExactly)
{
    const int n = TrainingFamily::n;
    const ProgressiveCodec codec(1, 2);
    const TrainingFamily family(codec, 10, 3);
    const std::vector<uint16_t>& root = family.root;
    const std::vector<uint16_t>& root_drawn = family.root_drawn;
    const std::vector<std::vector<uint16_t>>& children = family.children;
    // The build's loop: every stage (corrections, then tables) sees every patch.
    std::unique_ptr<HeightCodec> trained_codec = std::make_unique<ProgressiveCodec>(codec);
    int stages = 0;
    while (const std::unique_ptr<CodecTrainer> trainer = trained_codec->trainer()) {
        trainer->observe(root.data(), {n, 0, nullptr, 0});
        for (int c = 0; c < 4; ++c)
            trainer->observe(children[c].data(), {n, 1, root_drawn.data(), c});
        trained_codec = trainer->finish();
        ++stages;
    }
    EXPECT_EQ(stages, 2);
    const auto& trained = static_cast<const ProgressiveCodec&>(*trained_codec);
    EXPECT_EQ(trained.trainingStage(), 2);
    EXPECT_NE(trained.weights(1), nullptr) << "4 patches of 65² fit corrections";
    EXPECT_FALSE(trained.storeTables().empty());
    size_t with_defaults = 0, with_trained = 0;
    for (int c = 0; c < 4; ++c) {
        const PatchContext ctx{n, 1, root_drawn.data(), c};
        const std::vector<uint8_t> payload = encode(trained, children[c], ctx);
        ASSERT_FALSE(payload.empty());
        std::vector<uint16_t> decoded(children[c].size()), expected(children[c].size());
        ASSERT_EQ(trained.decode(decoded.data(), payload.data(), payload.size(), ctx), kCodecOk);
        trained.reconstruct(children[c].data(), ctx, expected.data());
        EXPECT_EQ(decoded, expected);
        with_trained += payload.size();
        with_defaults += encode(codec, children[c], ctx).size();
        // The same payload under other tables does not decode to the same patch.
        std::vector<uint16_t> other(decoded.size());
        EXPECT_FALSE(codec.decode(other.data(), payload.data(), payload.size(), ctx) == kCodecOk &&
                     other == decoded);
    }
    EXPECT_LT(with_trained, with_defaults);
    // Stored tables come back through the archive's settings.
    CodecSettings settings;
    settings.level_count = 2;
    trained.storeParameters(settings.param);
    settings.tables = trained.storeTables();
    const std::unique_ptr<HeightCodec> back = makeCodec(kProgressiveCodecId, settings);
    ASSERT_NE(back, nullptr);
    EXPECT_EQ(back->storeTables(), settings.tables);
    settings.tables.push_back(0);
    std::string problem;
    EXPECT_EQ(makeCodec(kProgressiveCodecId, settings, &problem), nullptr);
    EXPECT_NE(problem.find("codec tables"), std::string::npos) << problem;
}

TEST(ProgressiveCodecV2, PayloadBytesOfEveryFormatArePinned)
{
    // A 5×5 root and one child, bound 1, default tables: a change of these bytes is a format
    // change (payload v1, v2 or v3) and needs a new version.
    const int n = 5;
    std::vector<uint16_t> root(25), child(25);
    for (int i = 0; i < 25; ++i) {
        root[i] = static_cast<uint16_t>(1000 + 7 * (i % 5) + 3 * (i / 5) + (i * i) % 5);
        child[i] = static_cast<uint16_t>(1000 + 4 * (i % 5) + 5 * (i / 5) + (i * 7) % 3);
    }
    auto hex = [](const std::vector<uint8_t>& b) {
        std::string s;
        for (uint8_t v : b)
            s += "0123456789abcdef"[v >> 4], s += "0123456789abcdef"[v & 15];
        return s;
    };
    for (const ProgressiveVariant& v : {ProgressiveVariant::v1(), ProgressiveVariant::v2(),
                                        ProgressiveVariant::v3(), ProgressiveVariant{}}) {
        const ProgressiveCodec codec(1, 2, v);
        std::vector<uint16_t> drawn(25);
        codec.reconstruct(root.data(), {n, 0, nullptr, 0}, drawn.data());
        const std::string r = hex(encode(codec, root, {n, 0, nullptr, 0}));
        const std::string c = hex(encode(codec, child, {n, 1, drawn.data(), 2, 4, 5}));
        if (v.format == 1) {
            EXPECT_EQ(r, "500100c912285019dab361ce16f4601c19b200");
            EXPECT_EQ(c, "500100e219bbc965049eaf37927df98d78ea03c26b00");
        } else if (v.format == 2) { // 'P', 2, flags (1: refinements coded), varint rANS
                                    // size, rANS, raw bits
            EXPECT_EQ(r, "50020018dd3f795b32a15302c2edab00cb0d1600d2a381f463168fd84d");
            EXPECT_EQ(c, "50020118234f0600f36c02003fff1e16ff2d4a000c2b5c4e7c9c38da");
        } else if (v.format == 3) { // v2's layout; the root's contexts are v2's, a child's
                                    // differ
            EXPECT_EQ(r, "50030018dd3f795b32a15302c2edab00cb0d1600d2a381f463168fd84d");
            EXPECT_EQ(c, "500301185e9f03001c4d02002b9f8b18e7de5c007a60991e497c5acb");
        } else { // v4: v3's root; a child's contexts add the parent class
            EXPECT_EQ(r, "50040018dd3f795b32a15302c2edab00cb0d1600d2a381f463168fd84d");
            EXPECT_EQ(c, "5004011829cf0c00176d03004d9f2a19bbaea400f697d64e341ae2d7");
        }
    }
}

// A sharded build trains one codec across processes: observations split between trainers,
// saved and merged in any order, and the partial codec handed on as its training state, give
// the codec one trainer seeing every patch gives.
TEST(ProgressiveCodecV2, TrainingSplitAcrossTrainersLearnsTheSameCodec)
{
    const int n = TrainingFamily::n;
    const ProgressiveCodec codec(1, 2);
    const TrainingFamily family(codec, 20, 5);
    const std::vector<uint16_t>& root = family.root;
    const std::vector<uint16_t>& root_drawn = family.root_drawn;
    const std::vector<std::vector<uint16_t>>& children = family.children;
    auto observe = [&](CodecTrainer& t, int c) {
        if (c < 0)
            t.observe(root.data(), {n, 0, nullptr, 0});
        else
            t.observe(children[size_t(c)].data(), {n, 1, root_drawn.data(), c});
    };
    std::unique_ptr<HeightCodec> whole = std::make_unique<ProgressiveCodec>(codec);
    std::unique_ptr<HeightCodec> split = std::make_unique<ProgressiveCodec>(codec);
    int stages = 0;
    while (const std::unique_ptr<CodecTrainer> one = whole->trainer()) {
        for (int c = -1; c < 4; ++c)
            observe(*one, c);
        whole = one->finish();
        // The split: the state handed to two "shards" through bytes, each observing half,
        // merged into a third in reverse order.
        const std::vector<uint8_t> state = split->trainingState();
        std::unique_ptr<HeightCodec> shard_codec = makeCodec("progressive", 1, 2);
        shard_codec->restoreTraining(state.data(), state.size());
        const std::unique_ptr<CodecTrainer> a = shard_codec->trainer(), b = shard_codec->trainer();
        const std::unique_ptr<CodecTrainer> coordinator = split->trainer();
        ASSERT_TRUE(a && b && coordinator);
        observe(*a, 3);
        observe(*a, 0);
        observe(*b, 2);
        observe(*b, 1);
        observe(*coordinator, -1);
        for (const CodecTrainer* t : {b.get(), a.get()}) {
            const std::vector<uint8_t> seen = t->saveObservations();
            coordinator->mergeObservations(seen.data(), seen.size());
        }
        split = coordinator->finish();
        EXPECT_EQ(split->trainingState(), whole->trainingState()) << "stage " << stages;
        ++stages;
    }
    EXPECT_EQ(stages, 2);
    EXPECT_EQ(split->trainer(), nullptr);
    EXPECT_EQ(split->storeTables(), whole->storeTables());
    EXPECT_FALSE(whole->storeTables().empty());

    // Bytes that are not a trainer's or a codec's are refused.
    const std::unique_ptr<CodecTrainer> fresh = makeCodec("progressive", 1, 2)->trainer();
    std::vector<uint8_t> seen = fresh->saveObservations();
    seen.pop_back();
    EXPECT_THROW(fresh->mergeObservations(seen.data(), seen.size()), Error);
    std::unique_ptr<HeightCodec> target = makeCodec("progressive", 1, 2);
    std::vector<uint8_t> state = whole->trainingState();
    state[0] = 3; // no stage 3
    EXPECT_THROW(target->restoreTraining(state.data(), state.size()), Error);
    state = whole->trainingState();
    state.pop_back();
    EXPECT_THROW(target->restoreTraining(state.data(), state.size()), Error);
    const uint8_t one_byte = 1;
    EXPECT_THROW(makeCodec("lossless")->restoreTraining(&one_byte, 1), Error);
}
