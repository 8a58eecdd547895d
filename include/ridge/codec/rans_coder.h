#pragma once
// Static-model interleaved rANS: the entropy coder of progressive codec v2.
//
// rANS (Duda, "Asymmetric numeral systems", 2013) in the byte-oriented form of ryg_rans'
// "rans_word": a 32-bit state kept in [L, 2^32) with L = 2^16, renormalised by whole 16-bit
// words, probabilities quantised to 12 bits. Static tables (per archive, see
// progressive_tables.h) make decoding a table lookup and a multiply per symbol: no search,
// no adaptation, which is what makes v2 fast (v1's adaptive range coder spent ~300
// instructions a sample, most of them in the linear symbol search and the table update).
//
// kLanes states are interleaved, symbol i on lane i mod kLanes, all lanes sharing one word
// stream, so consecutive symbols' state updates do not wait on each other. rANS is LIFO:
// the encoder takes the symbols last to first and writes words backwards; the decoder reads
// them forwards. Header-only because the decoder is the codec's hot loop and must inline.
//
// Decoding is defensive: a lookup can only yield a symbol of non-zero frequency, reading
// past the end stops at the end and sets `overrun`, and finish() checks that every state
// came back to L and every word was consumed, which a stream this encoder wrote always does.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace ridge::rans {

constexpr int kProbBits = 12;
constexpr uint32_t kProbScale = 1u << kProbBits;
constexpr uint32_t kLow = 1u << 16; // L: the lower end of the state interval
constexpr int kLanes = 4;
constexpr int kMaxSymbols = 72; // alphabet bound of every table

// One static model: frequencies summing to kProbScale over `symbols` symbols, and the
// decoder's slot -> symbol lookup.
struct Table {
    int symbols = 0;
    std::array<uint16_t, kMaxSymbols> freq{};
    std::array<uint16_t, kMaxSymbols + 1> cum{};
    std::array<uint8_t, kProbScale> lookup{};

    // From frequencies that sum to kProbScale (checked by the caller: tables are validated
    // when parsed). Fills cum and lookup.
    void assign(const uint16_t* frequencies, int count)
    {
        symbols = count;
        freq.fill(0);
        cum[0] = 0;
        for (int s = 0; s < kMaxSymbols; ++s) {
            freq[s] = s < count ? frequencies[s] : 0;
            cum[s + 1] = static_cast<uint16_t>(cum[s] + freq[s]);
            for (uint32_t slot = cum[s]; slot < cum[s + 1]; ++slot)
                lookup[slot] = static_cast<uint8_t>(s);
        }
    }
};

// Collects (table, symbol) pairs in coding order, then writes them last to first.
class Encoder {
  public:
    void put(const Table& table, int symbol) { pending_.push_back({&table, symbol}); }
    size_t pending() const { return pending_.size(); }

    // Appends the stream (kLanes final states, then the words) to `out` and clears.
    void finish(std::vector<uint8_t>& out)
    {
        std::array<uint32_t, kLanes> state;
        state.fill(kLow);
        words_.clear();
        for (size_t i = pending_.size(); i-- > 0;) {
            const Pending& p = pending_[i];
            uint32_t& x = state[i % kLanes];
            const uint32_t f = p.table->freq[p.symbol];
            // x_max = ((L >> prob_bits) << 16) · f: after encoding, x stays below 2^32
            // (64-bit: it is 2^32 itself for a symbol of probability 1).
            const uint64_t x_max = uint64_t((kLow >> kProbBits) << 16) * f;
            if (x >= x_max) {
                words_.push_back(static_cast<uint16_t>(x));
                x >>= 16;
            }
            x = ((x / f) << kProbBits) + (x % f) + p.table->cum[p.symbol];
        }
        const size_t start = out.size();
        out.resize(start + 4 * kLanes + 2 * words_.size());
        uint8_t* dst = out.data() + start;
        for (int lane = 0; lane < kLanes; ++lane, dst += 4)
            store32(dst, state[lane]);
        for (size_t w = words_.size(); w-- > 0; dst += 2) { // the decoder reads them forwards
            dst[0] = static_cast<uint8_t>(words_[w]);
            dst[1] = static_cast<uint8_t>(words_[w] >> 8);
        }
        pending_.clear();
    }

  private:
    struct Pending {
        const Table* table;
        int symbol;
    };
    static void store32(uint8_t* p, uint32_t v)
    {
        for (int k = 0; k < 4; ++k)
            p[k] = static_cast<uint8_t>(v >> (8 * k));
    }
    std::vector<Pending> pending_;
    std::vector<uint16_t> words_;
};

class Decoder {
  public:
    Decoder(const uint8_t* data, size_t size) : p_(data), end_(data + size)
    {
        if (size < 4 * kLanes) {
            overrun_ = true;
            state_.fill(kLow);
            p_ = end_;
            return;
        }
        for (int lane = 0; lane < kLanes; ++lane, p_ += 4) {
            state_[lane] = uint32_t(p_[0]) | uint32_t(p_[1]) << 8 | uint32_t(p_[2]) << 16 |
                           uint32_t(p_[3]) << 24;
            // A state below L cannot come from the encoder; lifting it keeps the arithmetic
            // defined and finish() reports the stream as corrupt.
            if (state_[lane] < kLow) {
                state_[lane] = kLow;
                corrupt_ = true;
            }
        }
    }

    // The next symbol on `lane` (the caller cycles lanes 0, 1, ..., kLanes−1, 0, ...).
    int decode(const Table& table, int lane)
    {
        uint32_t& x = state_[lane];
        const uint32_t slot = x & (kProbScale - 1);
        const int s = table.lookup[slot];
        x = table.freq[s] * (x >> kProbBits) + slot - table.cum[s];
        if (x < kLow) {
            if (end_ - p_ >= 2) {
                x = (x << 16) | uint32_t(p_[0]) | uint32_t(p_[1]) << 8;
                p_ += 2;
            } else {
                overrun_ = true;
                x = (x << 16) | kLow; // stays in range; the stream is reported truncated
            }
        }
        return s;
    }

    // Decodes `count` symbols, symbol k with *tables[k], handing each to out(k, symbol): what
    // `count` calls of decode() cycling the lanes from `lane` give (and `lane` advances as
    // they would), but with the states in registers and whole rounds of kLanes symbols
    // decoded together, so that the lanes' updates overlap. Only for symbols whose tables
    // do not depend on one another: the caller chose every table before the run.
    template <class Out>
    void decodeRun(const Table* const* tables, int count, unsigned& lane, Out&& out)
    {
        int k = 0;
        if (count >= kLanes) {
            uint32_t x[kLanes];
            for (int l = 0; l < kLanes; ++l)
                x[l] = state_[(lane + l) & (kLanes - 1)];
            // Each round reads at most one word a lane: 2·kLanes bytes left means no bound
            // check inside it.
            for (; k + kLanes <= count && end_ - p_ >= 2 * kLanes; k += kLanes) {
#pragma GCC unroll 4
                for (int l = 0; l < kLanes; ++l) {
                    const Table& t = *tables[k + l];
                    const uint32_t slot = x[l] & (kProbScale - 1);
                    const int s = t.lookup[slot];
                    x[l] = t.freq[s] * (x[l] >> kProbBits) + slot - t.cum[s];
                    // Branch-free renormalisation: whether a lane reads a word is as good as
                    // random, and the word is in bounds either way.
                    const uint32_t renormalize = x[l] < kLow; // 0 or 1
                    const uint32_t word = uint32_t(p_[0]) | uint32_t(p_[1]) << 8;
                    x[l] = (x[l] << (16 * renormalize)) | (word & (0u - renormalize));
                    p_ += 2 * renormalize;
                    out(k + l, s);
                }
            }
            for (int l = 0; l < kLanes; ++l) // whole rounds: `lane` is where it was
                state_[(lane + l) & (kLanes - 1)] = x[l];
        }
        for (; k < count; ++k) // the rest, and the stream's last words, checked one by one
            out(k, decode(*tables[k], int(lane++ & (kLanes - 1))));
    }

    bool overrun() const
    {
        return overrun_;
    }
    // True when every lane is back at its initial state and every word was read: the
    // stream decoded exactly as written.
    bool finishedExactly() const
    {
        if (corrupt_ || overrun_ || p_ != end_)
            return false;
        for (uint32_t x : state_)
            if (x != kLow)
                return false;
        return true;
    }
    bool consumedAll() const
    {
        return p_ == end_;
    }

  private:
    std::array<uint32_t, kLanes> state_{};
    const uint8_t* p_;
    const uint8_t* end_;
    bool overrun_ = false;
    bool corrupt_ = false;
};

} // namespace ridge::rans
