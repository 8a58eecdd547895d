#include "progressive_entropy.h"

#include "ridge/codec/height_codec.h"
#include "ridge/codec/range_coder.h"

#include <array>
#include <bit>
#include <cstdlib>

namespace ridge {

namespace {

constexpr int kActivityClasses = 12;
constexpr int kDirectMagnitudes = 8; // tokens 0..7 are |d| itself
constexpr int kOctaveTokens = 7;     // tokens 8..14: [8·2^k, 16·2^k), k + 3 raw bits
constexpr int kEscapeToken = 15;
constexpr int32_t kEscapeBase = kDirectMagnitudes << kOctaveTokens; // 1024
constexpr int kRefineEscape = 3;

// Activity a = 2 × mean neighbour magnitude -> class, about two classes per octave.
constexpr std::array<uint8_t, 48> kActivityClass = [] {
    std::array<uint8_t, 48> t{};
    constexpr int kFirst[kActivityClasses] = {0, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48};
    for (int a = 0; a < 48; ++a)
        for (int c = 0; c < kActivityClasses; ++c)
            if (a >= kFirst[c])
                t[a] = static_cast<uint8_t>(c);
    return t;
}();

struct Models {
    rc::AdaptiveCdf<16> magnitude[4][kActivityClasses]; // [sample class][activity]
    rc::AdaptiveCdf<2> sign[4];
    rc::AdaptiveCdf<4> refinement;
};

// Neighbourhood magnitudes (clamped to 255) on a grid padded by 2 zero samples per side, so
// every neighbour read is in bounds and samples outside the patch count as flat.
class ActivityGrid {
  public:
    explicit ActivityGrid(int n) : stride_(n + 4)
    {
        thread_local std::vector<uint16_t> storage; // not uint8_t: char stores alias everything
        storage.assign(static_cast<size_t>(stride_) * stride_, 0);
        origin_ = storage.data() + 2 * stride_ + 2;
    }
    void set(int x, int y, int32_t magnitude)
    {
        origin_[y * stride_ + x] = static_cast<uint16_t>(magnitude < 255 ? magnitude : 255);
    }
    int at(int x, int y) const { return origin_[y * stride_ + x]; }

    // Activity class from the neighbours each pass has already decoded (see the header).
    int context(SampleClass cls, bool root, int x, int y) const
    {
        int a;
        if (root) // W, N, NW, NE in raster order
            a = (at(x - 1, y) + at(x, y - 1) + at(x - 1, y - 1) + at(x + 1, y - 1)) / 2;
        else if (cls == SampleClass::A) // A neighbours of the previous A row and this one
            a = (at(x - 2, y) + at(x, y - 2) + at(x - 2, y - 2) + at(x + 2, y - 2)) / 2;
        else if (cls == SampleClass::B) // the 4 diagonal A samples, then W and N in B
            a = (at(x - 1, y - 1) + at(x + 1, y - 1) + at(x - 1, y + 1) + at(x + 1, y + 1) +
                 at(x - 2, y) + at(x, y - 2)) /
                3;
        else // C: the 2 A and 2 B samples around it, then W and N in C
            a = (at(x, y - 1) + at(x, y + 1) + at(x - 1, y) + at(x + 1, y) + at(x - 2, y) +
                 at(x, y - 2)) /
                3;
        return a < 48 ? kActivityClass[a] : kActivityClasses - 1;
    }

  private:
    int stride_;
    uint16_t* origin_;
};

// A magnitude beyond the octaves: 5-bit length of m − 1024, then its bits below the top one.
void encodeEscape(rc::Encoder& enc, int32_t excess)
{
    const int length = excess == 0 ? 0 : std::bit_width(static_cast<uint32_t>(excess));
    enc.encodeBits(static_cast<uint32_t>(length), 5);
    if (length > 1)
        enc.encodeBits(static_cast<uint32_t>(excess) - (1u << (length - 1)), length - 1);
}

int32_t decodeEscape(rc::Decoder& dec, bool& bad)
{
    const int length = static_cast<int>(dec.decodeBits(5));
    if (length > 21) {
        bad = true;
        return 0;
    }
    if (length <= 1)
        return length;
    return static_cast<int32_t>((1u << (length - 1)) | dec.decodeBits(length - 1));
}

struct EncodeSide {
    rc::Encoder& enc;
    Models& models;

    void refinement(int32_t* slot)
    {
        const int32_t r = *slot;
        if (r >= -1 && r <= 1) {
            enc.encode(models.refinement, r + 1);
            return;
        }
        enc.encode(models.refinement, kRefineEscape);
        enc.encodeBits(r < 0, 1);
        encodeEscape(enc, std::abs(r));
    }

    int32_t error(int cls, int context, int32_t* slot)
    {
        const int32_t d = *slot;
        const int32_t m = std::abs(d);
        rc::AdaptiveCdf<16>& model = models.magnitude[cls][context];
        if (m < kDirectMagnitudes) {
            enc.encode(model, m);
        } else if (m < kEscapeBase) {
            const int k = std::bit_width(static_cast<uint32_t>(m)) - 4; // m in [8·2^k, 16·2^k)
            enc.encode(model, kDirectMagnitudes + k);
            enc.encodeBits(static_cast<uint32_t>(m - (kDirectMagnitudes << k)), k + 3);
        } else {
            enc.encode(model, kEscapeToken);
            encodeEscape(enc, m - kEscapeBase);
        }
        if (m != 0)
            enc.encode(models.sign[cls], d < 0);
        return m;
    }
};

struct DecodeSide {
    rc::Decoder& dec;
    Models& models;
    bool bad = false;

    void refinement(int32_t* slot)
    {
        const int s = dec.decode(models.refinement);
        if (s != kRefineEscape) {
            *slot = s - 1;
            return;
        }
        const bool negative = dec.decodeBits(1);
        const int32_t m = decodeEscape(dec, bad);
        bad |= m > kMaxResidual;
        *slot = negative ? -m : m;
    }

    int32_t error(int cls, int context, int32_t* slot)
    {
        const int token = dec.decode(models.magnitude[cls][context]);
        int32_t m;
        if (token < kDirectMagnitudes) {
            m = token;
        } else if (token < kEscapeToken) {
            const int k = token - kDirectMagnitudes;
            m = (kDirectMagnitudes << k) + static_cast<int32_t>(dec.decodeBits(k + 3));
        } else {
            m = kEscapeBase + decodeEscape(dec, bad);
            if (m > kMaxResidual) {
                bad = true;
                m = 0;
            }
        }
        *slot = (m != 0 && dec.decode(models.sign[cls])) ? -m : m;
        return m;
    }
};

// One traversal for both directions, so encoder and decoder cannot disagree on the order:
// the coarsest patch in raster order; a child's R samples, then A, B and C, each in raster
// order (the reconstruction's pass order).
template <class Side>
void traverse(int32_t* residuals, int n, const ResidualCoding& coding, Side& side)
{
    ActivityGrid activity(n);
    auto slot = [&](int x, int y) { return residuals + static_cast<size_t>(y) * n + x; };
    auto context = [&](SampleClass cls, int x, int y) {
        return coding.contexts ? activity.context(cls, coding.root, x, y) : 0;
    };
    if (coding.root) {
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                activity.set(x, y, side.error(0, context(SampleClass::R, x, y), slot(x, y)));
        return;
    }
    for (int y = 0; y < n; y += 2)
        for (int x = 0; x < n; x += 2)
            side.refinement(slot(x, y));
    for (const SampleClass cls : {SampleClass::A, SampleClass::B, SampleClass::C}) {
        const int x0 = static_cast<int>(cls) & 1, y0 = static_cast<int>(cls) >> 1;
        for (int y = y0; y < n; y += 2)
            for (int x = x0; x < n; x += 2)
                activity.set(x, y,
                             side.error(static_cast<int>(cls), context(cls, x, y), slot(x, y)));
    }
}

} // namespace

void encodeResiduals(const int32_t* residuals, int n, const ResidualCoding& coding,
                     std::vector<uint8_t>& out)
{
    Models models;
    rc::Encoder enc(out);
    EncodeSide side{enc, models};
    traverse(const_cast<int32_t*>(residuals), n, coding, side); // EncodeSide only reads
    enc.finish();
}

int decodeResiduals(const uint8_t* data, size_t size, int n, const ResidualCoding& coding,
                    int32_t* residuals)
{
    Models models;
    rc::Decoder dec(data, size);
    DecodeSide side{dec, models};
    traverse(residuals, n, coding, side);
    if (dec.truncated())
        return kCodecTruncated;
    if (!dec.ok() || side.bad)
        return kCodecCorrupt;
    if (dec.remaining() != 0)
        return kCodecTrailingBytes;
    return kCodecOk;
}

} // namespace ridge
