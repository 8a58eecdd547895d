#include "progressive_entropy_v2.h"

#include "ridge/codec/height_codec.h"
#include "ridge/codec/progressive_tokens.h"
#include "ridge/codec/rans_coder.h"

#include <algorithm>
#include <array>
#include <optional>

namespace ridge {

namespace {

using progressive_tables::kContexts;
using progressive_tables::kContextsV4;
namespace tokens = progressive_tokens;

// Activity a = 2 × the mean neighbour magnitude -> context; the bounds are
// progressive_tables.cpp's kActivityFirst (the defaults' spreads follow them).
constexpr int kActivityLimit = 128;
constexpr std::array<uint8_t, kActivityLimit> kActivityContext = [] {
    constexpr int kFirst[kContexts] = {0, 1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20, 26, 34, 46, 64};
    std::array<uint8_t, kActivityLimit> t{};
    for (int a = 0; a < kActivityLimit; ++a)
        for (int c = 0; c < kContexts; ++c)
            if (a >= kFirst[c])
                t[a] = static_cast<uint8_t>(c);
    return t;
}();

// Residual magnitudes (clamped to 255) on a grid padded by 2 zero samples per side: every
// neighbour read is in bounds, and samples outside the coded region count as flat.
class MagnitudeGrid {
  public:
    explicit MagnitudeGrid(int n) : stride_(n + 4)
    {
        thread_local std::vector<uint8_t> storage;
        storage.assign(static_cast<size_t>(stride_) * stride_, 0);
        origin_ = storage.data() + 2 * stride_ + 2;
    }
    uint8_t* row(int y) { return origin_ + static_cast<ptrdiff_t>(y) * stride_; }
    ptrdiff_t stride() const { return stride_; }

  private:
    int stride_;
    uint8_t* origin_;
};

inline int contextOf(int activity)
{
    return activity < kActivityLimit ? kActivityContext[activity] : kContexts - 1;
}

// contextOf(sum / divisor) for every sum of up to 6 magnitudes (each <= 255), as one lookup:
// v3's row contexts take no division and no range check.
template <int kDivisor>
constexpr std::array<uint8_t, 6 * 255 + 1> kContextOfSum = [] {
    std::array<uint8_t, 6 * 255 + 1> t{};
    for (int sum = 0; sum < int(t.size()); ++sum) {
        const int a = sum / kDivisor;
        t[size_t(sum)] = a < kActivityLimit ? kActivityContext[size_t(a)] : kContexts - 1;
    }
    return t;
}();

inline uint8_t clampMagnitude(int32_t d)
{
    const int32_t m = d < 0 ? -d : d;
    return static_cast<uint8_t>(m < 255 ? m : 255);
}

// Context of a sample from the magnitudes its pass already has. v2: v1's neighbourhoods, which
// include the previous sample of the same pass (W), so each context waits for the symbol
// before it. v3: only samples of earlier rows or earlier passes, so a whole row's contexts are
// known before its first symbol is decoded and the rANS lanes decode side by side
// (FastDecoder::passV3); W's place goes to the sample north-east of it. The root (class 0)
// keeps W in both.
template <int kVersion, int kClass> inline int context(const uint8_t* at, ptrdiff_t s)
{
    if constexpr (kClass == 0) // root, raster order: W, N, NW, NE
        return contextOf((at[-1] + at[-s] + at[-s - 1] + at[-s + 1]) >> 1);
    else if constexpr (kVersion == 2 && kClass == 1) // A: the previous A, three A above
        return contextOf((at[-2] + at[-2 * s] + at[-2 * s - 2] + at[-2 * s + 2]) >> 1);
    else if constexpr (kVersion == 2 && kClass == 2) // B: the 4 diagonal A, W and N in B
        return contextOf((at[-s - 1] + at[-s + 1] + at[s - 1] + at[s + 1] + at[-2] + at[-2 * s]) /
                         3);
    else if constexpr (kVersion == 2) // C: the 2 A and 2 B beside it, W and N in C
        return contextOf((at[-s] + at[s] + at[-1] + at[1] + at[-2] + at[-2 * s]) / 3);
    else if constexpr (kClass == 1) // A: the three A above, the one straight above twice
        return kContextOfSum<2>[2 * at[-2 * s] + at[-2 * s - 2] + at[-2 * s + 2]];
    else if constexpr (kClass == 2) // B: the 4 diagonal A, N and NE in B
        return kContextOfSum<3>[at[-s - 1] + at[-s + 1] + at[s - 1] + at[s + 1] + at[-2 * s] +
                                at[-2 * s + 2]];
    else // C: the 2 A and 2 B beside it, N and NE in C
        return kContextOfSum<3>[at[-s] + at[s] + at[-1] + at[1] + at[-2 * s] + at[-2 * s + 2]];
}

// v4: the bins of the child's R samples, (region.width + 1) / 2 a row: row j, column i is
// sample (2i, 2j). Every A, B and C sample of the region lies between lattice samples.
class RLattice {
  public:
    RLattice(const int32_t* residuals, int n, const ResidualCodingV2& c)
        : stride_((c.region.width + 1) / 2)
    {
        thread_local std::vector<int32_t> storage;
        const int rows = (c.region.height + 1) / 2;
        storage.resize(static_cast<size_t>(stride_) * rows);
        data_ = storage.data();
        const int half = (n - 1) / 2;
        const int x0 = (c.child_index & 1) * half, y0 = (c.child_index >> 1) * half;
        for (int j = 0; j < rows; ++j) {
            const int32_t* parent = c.parent_bins + static_cast<size_t>(y0 + j) * n + x0;
            const int32_t* refine = residuals + static_cast<size_t>(2 * j) * n;
            int32_t* out = data_ + static_cast<size_t>(j) * stride_;
            for (int i = 0; i < stride_; ++i)
                out[i] = parent[i] + (c.refinements ? refine[2 * i] : 0);
        }
    }
    // Row j = y / 2 of a sample in row y.
    const int32_t* row(int y) const { return data_ + static_cast<ptrdiff_t>(y >> 1) * stride_; }
    ptrdiff_t stride() const { return stride_; }

  private:
    ptrdiff_t stride_;
    int32_t* data_ = nullptr;
};

inline int clampSteps(int32_t d)
{
    const int32_t m = d < 0 ? -d : d;
    return m < 2 ? m : 2;
}

// v4: the context offset of the parent class (progressive_entropy_v2.h) of the sample in
// column x whose lattice row is b (RLattice::row): A between its row's R samples x ± 1, B
// between those of its column in rows y ± 1, C among its four diagonal R samples.
template <int kClass> inline int parentOffset(const int32_t* b, ptrdiff_t bs, int x)
{
    const int i = x >> 1;
    if constexpr (kClass == 1)
        return kContexts * clampSteps(b[i] - b[i + 1]);
    else if constexpr (kClass == 2)
        return kContexts * clampSteps(b[i] - b[i + bs]);
    else {
        const int32_t lo = std::min(std::min(b[i], b[i + 1]), std::min(b[i + bs], b[i + bs + 1]));
        const int32_t hi = std::max(std::max(b[i], b[i + 1]), std::max(b[i + bs], b[i + bs + 1]));
        return kContexts * clampSteps(hi - lo);
    }
}

// Whether `coding` can use tables or counts of `contexts` per class: v4 needs 48 and, below
// the root, the parent's bins; v2 and v3 need 16. The codec always passes such; a false here
// is a caller's error, never a payload's.
bool consistent(const ResidualCodingV2& coding, int contexts)
{
    if (coding.version == 4)
        return contexts == kContextsV4 && (coding.root || coding.parent_bins);
    return contexts == kContexts;
}

// Residuals the tokens carry (progressive_tokens.h); the encoder rejects any other.
inline bool codable(int32_t d)
{
    return d <= tokens::kMaxMagnitude && d >= -tokens::kMaxMagnitude;
}

struct EncodeSide {
    const ProgressiveTables& tables;
    int level;
    rans::Encoder& rans;
    tokens::BitWriter& raw;
    bool ok = true;

    int32_t code(int cls, int ctx, int32_t* slot)
    {
        const int32_t d = *slot;
        if (!codable(d)) {
            ok = false;
            return 0;
        }
        const tokens::Token t = tokens::tokenize(d);
        const rans::Table& table = tables.table(level, cls, ctx);
        if (t.symbol >= table.symbols || table.freq[t.symbol] == 0) {
            ok = false;
            return d;
        }
        rans.put(table, t.symbol);
        raw.put(t.raw, t.raw_count);
        return d;
    }
};

struct CountSide {
    SymbolCounts& counts;
    int level;
    bool ok = true;

    int32_t code(int cls, int ctx, int32_t* slot)
    {
        const int32_t d = *slot;
        if (!codable(d)) {
            ok = false;
            return 0;
        }
        ++counts.at(level, cls, ctx, tokens::tokenize(d).symbol);
        return d;
    }
};

// One pass of class kClass over samples (x0 + 2i, y0 + 2j) of the coded region; `lattice`
// (v4 only) gives the parent class.
template <int kVersion, int kClass, class Side>
void pass(int32_t* residuals, int n, const CodedRegion& r, MagnitudeGrid& mags, Side& side,
          int level_class, const RLattice* lattice = nullptr)
{
    constexpr int kNeighbourhood = kVersion == 2 ? 2 : 3; // v4 has v3's
    const int x0 = kClass == 0 ? 0 : (kClass & 1), y0 = kClass == 0 ? 0 : (kClass >> 1);
    const int step = kClass == 0 ? 1 : 2;
    for (int y = y0; y < r.height; y += step) {
        int32_t* row = residuals + static_cast<size_t>(y) * n;
        uint8_t* mrow = mags.row(y);
        for (int x = x0; x < r.width; x += step) {
            int ctx = context<kNeighbourhood, kClass>(mrow + x, mags.stride());
            if constexpr (kVersion == 4 && kClass > 0)
                ctx += parentOffset<kClass>(lattice->row(y), lattice->stride(), x);
            mrow[x] = clampMagnitude(side.code(level_class, ctx, row + x));
        }
    }
}

template <int kVersion, class Side>
void traverse(int32_t* residuals, int n, const ResidualCodingV2& coding, Side& side)
{
    MagnitudeGrid mags(n);
    const CodedRegion& r = coding.region;
    if (coding.root) {
        pass<kVersion, 0>(residuals, n, r, mags, side, 0);
        return;
    }
    if (coding.refinements)
        for (int y = 0; y < r.height; y += 2)
            for (int x = 0; x < r.width; x += 2)
                side.code(0, 0, residuals + static_cast<size_t>(y) * n + x);
    std::optional<RLattice> lattice;
    if constexpr (kVersion == 4)
        lattice.emplace(residuals, n, coding);
    const RLattice* l = lattice ? &*lattice : nullptr;
    pass<kVersion, 1>(residuals, n, r, mags, side, 1, l);
    pass<kVersion, 2>(residuals, n, r, mags, side, 2, l);
    pass<kVersion, 3>(residuals, n, r, mags, side, 3, l);
}

template <class Side>
void traverse(int32_t* residuals, int n, const ResidualCodingV2& coding, Side& side)
{
    if (coding.version == 2)
        traverse<2>(residuals, n, coding, side);
    else if (coding.version == 3)
        traverse<3>(residuals, n, coding, side);
    else
        traverse<4>(residuals, n, coding, side);
}

// The decoder's hot loop, written out instead of going through DecodeSide: the rANS states,
// the word pointer and the tables of the pass live in locals, and `__restrict` tells the
// compiler that storing a residual or a magnitude cannot change them, so nothing is reloaded
// per symbol. Visits exactly traverse()'s samples in traverse()'s order.
class FastDecoder {
  public:
    FastDecoder(const uint8_t* data, size_t size, tokens::BitReader& raw)
        : rans_(data, size), raw_(raw)
    {
    }

    // v2's passes and the root of both: each context waits for the symbol before it.
    template <int kClass>
    void pass(int32_t* __restrict residuals, int n, const CodedRegion& r, uint8_t* __restrict mags,
              ptrdiff_t ms, const rans::Table* const* tables)
    {
        const int x0 = kClass == 0 ? 0 : (kClass & 1), y0 = kClass == 0 ? 0 : (kClass >> 1);
        const int step = kClass == 0 ? 1 : 2;
        for (int y = y0; y < r.height; y += step) {
            int32_t* __restrict row = residuals + static_cast<size_t>(y) * n;
            uint8_t* __restrict mrow = mags + y * ms;
            for (int x = x0; x < r.width; x += step) {
                const int32_t d = next(*tables[context<2, kClass>(mrow + x, ms)]);
                row[x] = d;
                mrow[x] = clampMagnitude(d);
            }
        }
    }

    // v3's and v4's A, B and C passes: a row's tables first (its contexts read earlier rows
    // and passes, and v4's the R lattice, only), then its symbols in rounds of one per lane.
    template <int kClass>
    void passV3(int32_t* __restrict residuals, int n, const CodedRegion& r,
                uint8_t* __restrict mags, ptrdiff_t ms, const rans::Table* const* tables,
                const RLattice* lattice = nullptr)
    {
        static_assert(kClass >= 1 && kClass <= 3);
        const int x0 = kClass & 1, y0 = kClass >> 1;
        const int count = (r.width - x0 + 1) / 2;
        thread_local std::vector<const rans::Table*> row_tables;
        row_tables.resize(size_t(count));
        const rans::Table** __restrict row_table = row_tables.data();
        for (int y = y0; y < r.height; y += 2) {
            int32_t* __restrict row = residuals + static_cast<size_t>(y) * n + x0;
            uint8_t* __restrict mrow = mags + y * ms + x0;
            if (lattice) {
                const int32_t* b = lattice->row(y);
                const ptrdiff_t bs = lattice->stride();
                for (int k = 0; k < count; ++k)
                    row_table[k] = tables[context<3, kClass>(mrow + 2 * k, ms) +
                                          parentOffset<kClass>(b, bs, x0 + 2 * k)];
            } else {
                for (int k = 0; k < count; ++k)
                    row_table[k] = tables[context<3, kClass>(mrow + 2 * k, ms)];
            }
            rans_.decodeRun(row_table, count, lane_, [&](int k, int s) {
                // Zigzag without a branch on the sign, which is as good as random.
                const int32_t d = s < 15 ? (s >> 1) ^ -(s & 1)
                                         : tokens::residual(s, raw_.get(tokens::rawCount(s)));
                row[2 * k] = d;
                mrow[2 * k] = clampMagnitude(d);
            });
        }
    }

    void refinements(int32_t* __restrict residuals, int n, const CodedRegion& r,
                     const rans::Table& table)
    {
        for (int y = 0; y < r.height; y += 2)
            for (int x = 0; x < r.width; x += 2)
                residuals[static_cast<size_t>(y) * n + x] = next(table);
    }

    const rans::Decoder& rans() const { return rans_; }

  private:
    int32_t next(const rans::Table& t)
    {
        const int s = rans_.decode(t, int(lane_++ & (rans::kLanes - 1)));
        if (s < 15) // zigzag, no raw bits: the common case (no branch on the sign)
            return (s >> 1) ^ -(s & 1);
        return tokens::residual(s, raw_.get(tokens::rawCount(s)));
    }

    rans::Decoder rans_;
    unsigned lane_ = 0;
    tokens::BitReader& raw_;
};

} // namespace

bool encodeResidualsV2(const int32_t* residuals, int n, const ResidualCodingV2& coding,
                       const ProgressiveTables& tables, std::vector<uint8_t>& out)
{
    if (!consistent(coding, tables.contexts()))
        return false;
    thread_local rans::Encoder rans;
    tokens::BitWriter raw;
    EncodeSide side{tables, coding.level, rans, raw};
    traverse(const_cast<int32_t*>(residuals), n, coding, side); // EncodeSide only reads
    std::vector<uint8_t> words;
    rans.finish(words);
    if (!side.ok)
        return false;
    tokens::putVarint(out, static_cast<uint32_t>(words.size()));
    out.insert(out.end(), words.begin(), words.end());
    raw.finish(out);
    return true;
}

bool countResidualsV2(const int32_t* residuals, int n, const ResidualCodingV2& coding,
                      SymbolCounts& counts)
{
    if (!consistent(coding, counts.contexts()))
        return false;
    CountSide side{counts, coding.level};
    traverse(const_cast<int32_t*>(residuals), n, coding, side); // CountSide only reads
    return side.ok;
}

int decodeResidualsV2(const uint8_t* data, size_t size, int n, const ResidualCodingV2& coding,
                      const ProgressiveTables& tables, int32_t* residuals)
{
    // The rANS stream's length.
    uint32_t rans_size = 0;
    const uint8_t* p = data;
    if (!tokens::getVarint(p, data + size, rans_size))
        return p == data + size ? kCodecTruncated : kCodecCorrupt;
    const size_t used = static_cast<size_t>(p - data);
    if (rans_size > size - used)
        return kCodecTruncated;
    std::fill(residuals, residuals + static_cast<size_t>(n) * n, 0);
    tokens::BitReader raw(data + used + rans_size, size - used - rans_size);
    FastDecoder dec(data + used, rans_size, raw);
    MagnitudeGrid mags(n);
    uint8_t* origin = mags.row(0);
    const ptrdiff_t ms = mags.stride();
    const CodedRegion& r = coding.region;
    const int contexts = tables.contexts();
    if (!consistent(coding, contexts))
        return kCodecBadHeader; // the codec passes both: never reached from a payload
    const rans::Table* by_context[4][kContextsV4];
    for (int c = 0; c < 4; ++c)
        for (int x = 0; x < contexts; ++x)
            by_context[c][x] = &tables.table(coding.level, c, x);
    if (coding.root) {
        dec.pass<0>(residuals, n, r, origin, ms, by_context[0]);
    } else {
        if (coding.refinements)
            dec.refinements(residuals, n, r, *by_context[0][0]);
        if (coding.version == 2) {
            dec.pass<1>(residuals, n, r, origin, ms, by_context[1]);
            dec.pass<2>(residuals, n, r, origin, ms, by_context[2]);
            dec.pass<3>(residuals, n, r, origin, ms, by_context[3]);
        } else if (coding.version == 4) {
            const RLattice lattice(residuals, n, coding);
            dec.passV3<1>(residuals, n, r, origin, ms, by_context[1], &lattice);
            dec.passV3<2>(residuals, n, r, origin, ms, by_context[2], &lattice);
            dec.passV3<3>(residuals, n, r, origin, ms, by_context[3], &lattice);
        } else {
            dec.passV3<1>(residuals, n, r, origin, ms, by_context[1]);
            dec.passV3<2>(residuals, n, r, origin, ms, by_context[2]);
            dec.passV3<3>(residuals, n, r, origin, ms, by_context[3]);
        }
    }
    if (dec.rans().overrun())
        return kCodecTruncated;
    if (!dec.rans().finishedExactly())
        return kCodecCorrupt;
    if (raw.overrun())
        return kCodecTruncated;
    if (!raw.finishedExactly())
        return kCodecTrailingBytes; // whole bytes past the raw bits, or set padding bits
    return kCodecOk;
}

} // namespace ridge
