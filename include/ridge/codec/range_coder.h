#pragma once
// Adaptive multi-symbol range coder: the entropy coder of the progressive codec.
//
// The hardware-tessellation paper codes its symbols with adaptive arithmetic coding after
// Witten, Neal and Cleary [WNC87]: per-symbol frequencies learned on the fly. ridge keeps
// that model but makes it fast:
//   * frequencies live in a cumulative table whose total is a power of two (2^15), so the
//     decoder finds a symbol with multiplications and compares, never a division;
//   * adaptation moves the table towards the coded symbol by a shift (an exponentially
//     decaying histogram, as in Daala/AV1), fast at first and slower as the count grows;
//   * every symbol keeps a frequency of at least 1, so any symbol stays codable;
//   * the coder itself is the carry-propagating range coder of LZMA (32-bit range, 64-bit
//     low with a cache byte), which emits exactly the bytes the decoder reads.
// Header-only because the decoder loop is the codec's hot path and must inline.
//
// Decoding is defensive: bytes past the end read as zero and are counted, and a code value
// outside the current range (impossible for a stream this encoder wrote) raises `corrupt`.
// Callers check `ok()` after decoding; a corrupt stream yields garbage symbols, never UB.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::rc {

constexpr int kProbBits = 15;
constexpr uint32_t kProbTotal = 1u << kProbBits;
constexpr uint32_t kTop = 1u << 24; // renormalise when the range falls below this

// Adaptive cumulative frequency table over N symbols (2 <= N <= 16).
// Effective cumulative frequency F(s) = c[s] + s, F(0) = 0, F(N) = kProbTotal, hence every
// symbol has frequency >= 1 whatever the adaptation did to c.
template <int N> struct AdaptiveCdf {
    static_assert(N >= 2 && N <= 16);
    static constexpr uint32_t kSpan = kProbTotal - N; // total of the adaptive part
    uint16_t c[N + 1];
    uint16_t count;

    AdaptiveCdf() { reset(); }

    void reset()
    {
        for (int i = 0; i <= N; ++i)
            c[i] = static_cast<uint16_t>(kSpan * static_cast<uint32_t>(i) / N);
        count = 0;
    }
    uint32_t cumulative(int s) const { return c[s] + static_cast<uint32_t>(s); }

    // Mixes the table with a step at s: c <- c + floor((step_s - c) / 2^rate). Stays
    // monotone and inside [0, kSpan] (x + floor((t - x) / 2^r) is non-decreasing in x and
    // lies between x and t). Branch-free: the symbol is unpredictable.
    void update(int s)
    {
        const int rate = 4 + (count >= 16) + (count >= 64) + (count >= 256);
        count = static_cast<uint16_t>(count + (count < 256));
        for (int i = 1; i < N; ++i) {
            const int target = i > s ? static_cast<int>(kSpan) : 0;
            c[i] = static_cast<uint16_t>(c[i] + ((target - c[i]) >> rate));
        }
    }
};

class Encoder {
  public:
    explicit Encoder(std::vector<uint8_t>& out) : out_(out) {}

    template <int N> void encode(AdaptiveCdf<N>& cdf, int s)
    {
        const uint32_t r = range_ >> kProbBits;
        const uint32_t lo = cdf.cumulative(s);
        low_ += static_cast<uint64_t>(r) * lo;
        range_ = r * (cdf.cumulative(s + 1) - lo);
        normalize();
        cdf.update(s);
    }

    // `bits` (<= 24) equiprobable bits of `value`, most significant first.
    void encodeBits(uint32_t value, int bits)
    {
        for (int b = bits - 1; b >= 0; --b) {
            range_ >>= 1;
            if ((value >> b) & 1)
                low_ += range_;
            normalize();
        }
    }

    // Flushes the coder; the stream is complete after this.
    void finish()
    {
        for (int i = 0; i < 5; ++i)
            shiftLow();
    }

  private:
    void normalize()
    {
        while (range_ < kTop) {
            range_ <<= 8;
            shiftLow();
        }
    }
    void shiftLow()
    {
        if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
            const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
            uint8_t byte = cache_;
            do {
                out_.push_back(static_cast<uint8_t>(byte + carry));
                byte = 0xFF;
            } while (--pending_ != 0);
            cache_ = static_cast<uint8_t>(low_ >> 24);
        }
        ++pending_;
        low_ = (low_ & 0x00FFFFFFu) << 8;
    }

    std::vector<uint8_t>& out_;
    uint64_t low_ = 0;
    uint32_t range_ = 0xFFFFFFFFu;
    uint8_t cache_ = 0;
    uint64_t pending_ = 1;
};

class Decoder {
  public:
    Decoder(const uint8_t* data, size_t size) : p_(data), end_(data + size)
    {
        // The encoder's first byte is its initial cache (always 0).
        if (nextByte() != 0)
            corrupt_ = true;
        for (int i = 0; i < 4; ++i)
            code_ = (code_ << 8) | nextByte();
    }

    template <int N> int decode(AdaptiveCdf<N>& cdf)
    {
        const uint64_t r = range_ >> kProbBits;
        if (code_ >= r * kProbTotal) { // only a corrupt stream gets here
            corrupt_ = true;
            code_ = 0;
        }
        // s = number of boundaries F(1..N-1) at or below the code: branch-free, since a
        // search loop mispredicts on almost every symbol.
        const uint32_t code = static_cast<uint32_t>(code_), rr = static_cast<uint32_t>(r);
        int s = 0;
        for (int i = 1; i < N; ++i)
            s += rr * cdf.cumulative(i) <= code;
        const uint64_t lo = cdf.cumulative(s);
        code_ -= r * lo;
        range_ = r * (cdf.cumulative(s + 1) - lo);
        normalize();
        cdf.update(s);
        return s;
    }

    uint32_t decodeBits(int bits)
    {
        uint32_t value = 0;
        for (int b = 0; b < bits; ++b) {
            range_ >>= 1;
            const uint32_t bit = code_ >= range_;
            code_ -= bit ? range_ : 0;
            value = (value << 1) | bit;
            normalize();
        }
        if (code_ >= range_) {
            corrupt_ = true;
            code_ = 0;
        }
        return value;
    }

    // True while every byte read existed and the code stayed inside the range.
    bool ok() const { return !corrupt_ && overrun_ == 0; }
    bool truncated() const { return overrun_ != 0; }
    // Bytes of the stream not consumed (a complete stream is consumed exactly).
    size_t remaining() const { return static_cast<size_t>(end_ - p_); }

  private:
    uint32_t nextByte()
    {
        if (p_ < end_)
            return *p_++;
        ++overrun_;
        return 0;
    }
    void normalize()
    {
        while (range_ < kTop) {
            range_ <<= 8;
            code_ = (code_ << 8) | nextByte();
        }
    }

    // 64-bit holders although the values fit 32 bits: int32 residual stores elsewhere may
    // alias uint32 members, which would force a reload after every decoded symbol.
    const uint8_t* p_;
    const uint8_t* end_;
    uint64_t code_ = 0;
    uint64_t range_ = 0xFFFFFFFFu;
    size_t overrun_ = 0;
    bool corrupt_ = false;
};

} // namespace ridge::rc
