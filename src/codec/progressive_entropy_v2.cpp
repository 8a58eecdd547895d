#include "progressive_entropy_v2.h"

#include "ridge/codec/height_codec.h"
#include "ridge/codec/progressive_tokens.h"
#include "ridge/codec/rans_coder.h"

#include <array>

namespace ridge {

namespace {

using progressive_tables::kContexts;
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
        thread_local std::vector<uint16_t> storage;
        storage.assign(static_cast<size_t>(stride_) * stride_, 0);
        origin_ = storage.data() + 2 * stride_ + 2;
    }
    uint16_t* row(int y) { return origin_ + static_cast<ptrdiff_t>(y) * stride_; }
    ptrdiff_t stride() const { return stride_; }

  private:
    int stride_;
    uint16_t* origin_;
};

inline int contextOf(int activity)
{
    return activity < kActivityLimit ? kActivityContext[activity] : kContexts - 1;
}

inline uint16_t clampMagnitude(int32_t d)
{
    const int32_t m = d < 0 ? -d : d;
    return static_cast<uint16_t>(m < 255 ? m : 255);
}

// Context of a sample from the magnitudes its pass already has (v1's neighbourhoods).
template <int kClass> inline int context(const uint16_t* at, ptrdiff_t s)
{
    if constexpr (kClass == 0) // root, raster order: W, N, NW, NE
        return contextOf((at[-1] + at[-s] + at[-s - 1] + at[-s + 1]) >> 1);
    else if constexpr (kClass == 1) // A: the previous A of the row, three A of the row above
        return contextOf((at[-2] + at[-2 * s] + at[-2 * s - 2] + at[-2 * s + 2]) >> 1);
    else if constexpr (kClass == 2) // B: the 4 diagonal A, then W and N in B
        return contextOf((at[-s - 1] + at[-s + 1] + at[s - 1] + at[s + 1] + at[-2] + at[-2 * s]) /
                         3);
    else // C: the 2 A and 2 B beside it, then W and N in C
        return contextOf((at[-s] + at[s] + at[-1] + at[1] + at[-2] + at[-2 * s]) / 3);
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

// One pass of class kClass over samples (x0 + 2i, y0 + 2j) of the coded region.
template <int kClass, class Side>
void pass(int32_t* residuals, int n, const CodedRegion& r, MagnitudeGrid& mags, Side& side,
          int level_class)
{
    const int x0 = kClass == 0 ? 0 : (kClass & 1), y0 = kClass == 0 ? 0 : (kClass >> 1);
    const int step = kClass == 0 ? 1 : 2;
    for (int y = y0; y < r.height; y += step) {
        int32_t* row = residuals + static_cast<size_t>(y) * n;
        uint16_t* mrow = mags.row(y);
        for (int x = x0; x < r.width; x += step) {
            const int ctx = context<kClass>(mrow + x, mags.stride());
            mrow[x] = clampMagnitude(side.code(level_class, ctx, row + x));
        }
    }
}

template <class Side>
void traverse(int32_t* residuals, int n, const ResidualCodingV2& coding, Side& side)
{
    MagnitudeGrid mags(n);
    const CodedRegion& r = coding.region;
    if (coding.root) {
        pass<0>(residuals, n, r, mags, side, 0);
        return;
    }
    if (coding.refinements)
        for (int y = 0; y < r.height; y += 2)
            for (int x = 0; x < r.width; x += 2)
                side.code(0, 0, residuals + static_cast<size_t>(y) * n + x);
    pass<1>(residuals, n, r, mags, side, 1);
    pass<2>(residuals, n, r, mags, side, 2);
    pass<3>(residuals, n, r, mags, side, 3);
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

    template <int kClass>
    void pass(int32_t* __restrict residuals, int n, const CodedRegion& r, uint16_t* __restrict mags,
              ptrdiff_t ms, const rans::Table* const* tables)
    {
        const int x0 = kClass == 0 ? 0 : (kClass & 1), y0 = kClass == 0 ? 0 : (kClass >> 1);
        const int step = kClass == 0 ? 1 : 2;
        for (int y = y0; y < r.height; y += step) {
            int32_t* __restrict row = residuals + static_cast<size_t>(y) * n;
            uint16_t* __restrict mrow = mags + y * ms;
            for (int x = x0; x < r.width; x += step) {
                const int32_t d = next(*tables[context<kClass>(mrow + x, ms)]);
                row[x] = d;
                mrow[x] = clampMagnitude(d);
            }
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
        if (s < 15) // zigzag, no raw bits: the common case
            return (s & 1) ? -((s + 1) >> 1) : s >> 1;
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
    uint16_t* origin = mags.row(0);
    const ptrdiff_t ms = mags.stride();
    const CodedRegion& r = coding.region;
    const rans::Table* by_context[4][kContexts];
    for (int c = 0; c < 4; ++c)
        for (int x = 0; x < kContexts; ++x)
            by_context[c][x] = &tables.table(coding.level, c, x);
    if (coding.root) {
        dec.pass<0>(residuals, n, r, origin, ms, by_context[0]);
    } else {
        if (coding.refinements)
            dec.refinements(residuals, n, r, *by_context[0][0]);
        dec.pass<1>(residuals, n, r, origin, ms, by_context[1]);
        dec.pass<2>(residuals, n, r, origin, ms, by_context[2]);
        dec.pass<3>(residuals, n, r, origin, ms, by_context[3]);
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
