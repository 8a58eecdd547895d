#pragma once
// Residual <-> (token, raw bits) of progressive codec v2, and the raw-bit streams.
//
// A residual d is one entropy-coded token, signed so that a skewed sign costs nothing, plus
// raw bits for the low end of large magnitudes (JPEG XL's "hybrid uint" with one mantissa
// bit in the token):
//   |d| < 8:          token = zigzag(d)                 0..14, no raw bits
//   |d| in [2^b, 2^(b+1)), b = 3..16:
//                     token = 15 + 4(b−3) + 2·m + s     15..70
//                     m = the bit below the leading one, s = sign, then b − 1 raw bits.
// |d| < 2^17 covers every residual of 16-bit codes (refinements < 2^16, predictions within
// ±2^17 of a bin); larger ones are rejected by the encoder and cannot be decoded.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

namespace ridge::progressive_tokens {

constexpr int kDirect = 8;
constexpr int32_t kMaxMagnitude = (1 << 17) - 1;

struct Token {
    int symbol;
    int raw_count;
    uint32_t raw;
};

inline Token tokenize(int32_t d)
{
    const uint32_t m = static_cast<uint32_t>(d < 0 ? -d : d);
    if (m < kDirect)
        return {d >= 0 ? 2 * d : -2 * d - 1, 0, 0};
    const int b = std::bit_width(m) - 1; // 3..16
    const int mid = static_cast<int>((m >> (b - 1)) & 1);
    return {15 + 4 * (b - 3) + 2 * mid + (d < 0), b - 1, m & ((1u << (b - 1)) - 1)};
}

// Raw bits that follow `symbol` (0 for direct tokens).
inline int rawCount(int symbol)
{
    return symbol < 15 ? 0 : ((symbol - 15) >> 2) + 2;
}

// The residual of `symbol` with its raw bits.
inline int32_t residual(int symbol, uint32_t raw)
{
    if (symbol < 15) // zigzag: 0, −1, 1, −2, 2, ...
        return (symbol & 1) ? -((symbol + 1) >> 1) : symbol >> 1;
    const int t = symbol - 15;
    const int b = (t >> 2) + 3;
    const int32_t m = static_cast<int32_t>((1u << b) | (uint32_t((t >> 1) & 1) << (b - 1)) | raw);
    return (t & 1) ? -m : m;
}

// LEB128 varints (the v2 stream's rANS size, the codec tables' counts and frequencies).
inline void putVarint(std::vector<uint8_t>& out, uint32_t v)
{
    while (v >= 0x80) {
        out.push_back(static_cast<uint8_t>(v | 0x80));
        v >>= 7;
    }
    out.push_back(static_cast<uint8_t>(v));
}

// Reads at most 4 bytes (values below 2^28); false when the bytes end first or run longer.
inline bool getVarint(const uint8_t*& p, const uint8_t* end, uint32_t& v)
{
    v = 0;
    for (int shift = 0; shift < 28; shift += 7) {
        if (p == end)
            return false;
        const uint8_t b = *p++;
        v |= uint32_t(b & 0x7f) << shift;
        if (!(b & 0x80))
            return true;
    }
    return false;
}

// Bits written LSB first into little-endian 64-bit words, read back the same way.
class BitWriter {
  public:
    void put(uint32_t bits, int count)
    {
        if (count == 0)
            return;
        acc_ |= uint64_t(bits) << fill_;
        fill_ += count;
        while (fill_ >= 8) {
            bytes_.push_back(static_cast<uint8_t>(acc_));
            acc_ >>= 8;
            fill_ -= 8;
        }
    }
    // Appends the bits, the last byte zero-padded, to `out`.
    void finish(std::vector<uint8_t>& out)
    {
        if (fill_ > 0)
            bytes_.push_back(static_cast<uint8_t>(acc_));
        out.insert(out.end(), bytes_.begin(), bytes_.end());
        bytes_.clear();
        acc_ = 0;
        fill_ = 0;
    }

  private:
    std::vector<uint8_t> bytes_;
    uint64_t acc_ = 0;
    int fill_ = 0;
};

class BitReader {
  public:
    BitReader(const uint8_t* data, size_t size) : p_(data), end_(data + size) {}
    uint32_t get(int count)
    {
        if (count == 0)
            return 0;
        if (fill_ < count)
            refill();
        if (fill_ < count) { // past the end
            overrun_ = true;
            fill_ = count;
        }
        const uint32_t v = static_cast<uint32_t>(acc_ & ((uint64_t(1) << count) - 1));
        acc_ >>= count;
        fill_ -= count;
        return v;
    }
    bool overrun() const { return overrun_; }
    // True when the stream ended exactly: no overrun, no unread byte, zero padding bits.
    bool finishedExactly() const { return !overrun_ && p_ == end_ && fill_ < 8 && acc_ == 0; }

  private:
    void refill()
    {
        while (fill_ <= 56 && p_ < end_) {
            acc_ |= uint64_t(*p_++) << fill_;
            fill_ += 8;
        }
    }
    const uint8_t* p_;
    const uint8_t* end_;
    uint64_t acc_ = 0;
    int fill_ = 0;
    bool overrun_ = false;
};

} // namespace ridge::progressive_tokens
