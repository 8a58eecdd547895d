#include "ridge/codec/progressive_tables.h"

#include "ridge/codec/progressive_tokens.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace ridge {

using namespace progressive_tables;

namespace {

constexpr uint8_t kMagic = 'T';
// Version 1: kContexts per class, a varint per table. Version 2 (payload v4): kContextsV4 per
// class, a bitmap of the stored tables (most of 3× the tables are defaults).
constexpr uint8_t kVersionActivity = 1;
constexpr uint8_t kVersionParentClasses = 2;

uint8_t versionFor(int contexts)
{
    return contexts == kContexts ? kVersionActivity : kVersionParentClasses;
}

// Lower activity bound of each context (progressive_entropy_v2.cpp maps activities through
// the same list), used for the defaults' spread.
constexpr int kActivityFirst[kContexts + 1] = {0,  1,  2,  3,  4,  5,  6,  8, 10,
                                               13, 16, 20, 26, 34, 46, 64, 96};

// Frequencies summing to kProbScale, non-zero exactly where the count is. False for an
// all-zero histogram.
bool normalize(const uint64_t* counts, uint16_t* freq)
{
    uint64_t total = 0;
    for (int s = 0; s < kSymbols; ++s)
        total += counts[s];
    if (total == 0)
        return false;
    int64_t sum = 0;
    int largest = 0;
    for (int s = 0; s < kSymbols; ++s) {
        freq[s] = 0;
        if (counts[s] == 0)
            continue;
        // Integer rounding (128-bit products): the defaults are normalised by every reader
        // and must come out the same everywhere.
        const unsigned __int128 share =
            (static_cast<unsigned __int128>(counts[s]) * rans::kProbScale + total / 2) / total;
        freq[s] = static_cast<uint16_t>(std::max<unsigned __int128>(1, share));
        sum += freq[s];
        if (counts[s] > counts[largest])
            largest = s;
    }
    // Rounding leaves the sum a few units off: the difference goes to, or comes from, the
    // most frequent symbols, where it costs least.
    while (sum < int64_t(rans::kProbScale)) {
        ++freq[largest];
        ++sum;
    }
    while (sum > int64_t(rans::kProbScale)) {
        int s_max = -1;
        for (int s = 0; s < kSymbols; ++s)
            if (freq[s] > 1 && (s_max < 0 || freq[s] > freq[s_max]))
                s_max = s;
        --freq[s_max];
        --sum;
    }
    return true;
}

// x^k with multiplications only: exactly rounded IEEE steps, the same on every platform
// (std::pow need not be).
double powi(double x, uint64_t k)
{
    double r = 1.0;
    while (k) {
        if (k & 1)
            r *= x;
        x *= x;
        k >>= 1;
    }
    return r;
}

// The default model: |d| geometric with mean μ (θ = μ / (1 + μ)), signs equally likely,
// every token given a count of at least 1 so that any residual stays codable.
rans::Table geometricTable(int mean16)
{
    const double theta = double(mean16) / double(16 + mean16);
    uint64_t counts[kSymbols];
    const double scale = 1099511627776.0; // 2^40
    for (int s = 0; s < kSymbols; ++s) {
        double p;
        if (s < 15) {
            const int32_t d = progressive_tokens::residual(s, 0);
            p = powi(theta, static_cast<uint64_t>(d < 0 ? -d : d)) * (d == 0 ? 1.0 : 0.5);
        } else {
            const int t = s - 15, b = (t >> 2) + 3;
            const uint64_t lo = (uint64_t(1) << b) | (uint64_t((t >> 1) & 1) << (b - 1));
            const uint64_t len = uint64_t(1) << (b - 1);
            p = 0.5 * powi(theta, lo) * (1.0 - powi(theta, len)) / (1.0 - theta);
        }
        counts[s] = std::max<uint64_t>(1, static_cast<uint64_t>(p * scale));
    }
    uint16_t freq[kSymbols];
    normalize(counts, freq);
    rans::Table table;
    table.assign(freq, kSymbols);
    return table;
}

// Payload v4's defaults scale the activity's mean by the parent class: residuals between
// parent bins that agree are smaller, between bins 2 or more steps apart larger
// (mean16 · kParentScale[p] / 2).
constexpr int kParentScale[kParentClasses] = {1, 2, 4};

struct DefaultTables {
    rans::Table activity[kContexts];
    rans::Table by_parent[kContextsV4];
    rans::Table refinement;
    DefaultTables()
    {
        for (int c = 0; c < kContexts; ++c) {
            const int mean16 = 4 * (kActivityFirst[c] + kActivityFirst[c + 1]) + 6;
            activity[c] = geometricTable(mean16);
            for (int p = 0; p < kParentClasses; ++p)
                by_parent[p * kContexts + c] = geometricTable(mean16 * kParentScale[p] / 2);
        }
        refinement = geometricTable(4);
    }
};

const DefaultTables& defaultTables()
{
    static const DefaultTables tables;
    return tables;
}

// Class 0 (the root's MED residuals, a child's refinements) has activity contexts only.
const rans::Table& defaultTable(int level, int cls, int context, int contexts)
{
    const DefaultTables& d = defaultTables();
    if (cls == 0 && level > 0)
        return d.refinement;
    return (contexts == kContexts || cls == 0) ? d.activity[context % kContexts]
                                               : d.by_parent[context];
}

bool usedContext(int cls, int context)
{
    return cls > 0 || context < kContexts;
}

using progressive_tokens::getVarint;
using progressive_tokens::putVarint;

// Bytes one stored table takes: its symbol count, then its frequencies.
size_t storedBytes(const rans::Table& t)
{
    std::vector<uint8_t> bytes;
    putVarint(bytes, static_cast<uint32_t>(t.symbols));
    for (int s = 0; s < t.symbols; ++s)
        putVarint(bytes, t.freq[s]);
    return bytes.size();
}

} // namespace

SymbolCounts::SymbolCounts(int level_count, int contexts)
    : level_count_(level_count), contexts_(contexts),
      counts_(static_cast<size_t>(level_count) * kClasses * contexts * kSymbols, 0)
{
}

void SymbolCounts::merge(const SymbolCounts& other)
{
    for (size_t i = 0; i < counts_.size() && i < other.counts_.size(); ++i)
        counts_[i] += other.counts_[i];
}

std::vector<uint8_t> SymbolCounts::serialize() const
{
    std::vector<uint8_t> out(4);
    uint32_t nonzero = 0;
    for (size_t i = 0; i < counts_.size(); ++i) {
        if (counts_[i] == 0)
            continue;
        ++nonzero;
        for (int b = 0; b < 4; ++b)
            out.push_back(static_cast<uint8_t>(i >> (8 * b)));
        for (int b = 0; b < 8; ++b)
            out.push_back(static_cast<uint8_t>(counts_[i] >> (8 * b)));
    }
    for (int b = 0; b < 4; ++b)
        out[b] = static_cast<uint8_t>(nonzero >> (8 * b));
    return out;
}

bool SymbolCounts::mergeSerialized(const uint8_t* data, size_t size)
{
    auto read = [&](size_t at, int bytes) {
        uint64_t v = 0;
        for (int b = 0; b < bytes; ++b)
            v |= uint64_t{data[at + b]} << (8 * b);
        return v;
    };
    if (size < 4)
        return false;
    const uint64_t nonzero = read(0, 4);
    if (size != 4 + nonzero * 12)
        return false;
    std::vector<uint64_t> sum = counts_;
    for (uint64_t k = 0; k < nonzero; ++k) {
        const uint64_t at = read(4 + k * 12, 4), count = read(8 + k * 12, 8);
        if (at >= sum.size() || count > UINT64_MAX - sum[at])
            return false;
        sum[at] += count;
    }
    counts_ = std::move(sum);
    return true;
}

ProgressiveTables::ProgressiveTables(int level_count, int contexts)
    : level_count_(level_count), contexts_(contexts),
      index_(static_cast<size_t>(level_count) * kClasses * contexts, nullptr),
      stored_symbols_(index_.size(), 0)
{
    for (int l = 0; l < level_count; ++l)
        for (int c = 0; c < kClasses; ++c)
            for (int x = 0; x < contexts; ++x)
                index_[(size_t(l) * kClasses + c) * contexts + x] =
                    &defaultTable(l, c, x, contexts);
}

std::shared_ptr<const ProgressiveTables> ProgressiveTables::defaults(int level_count, int contexts)
{
    return std::shared_ptr<const ProgressiveTables>(new ProgressiveTables(level_count, contexts));
}

double ProgressiveTables::cost(const uint64_t* counts, const rans::Table& table)
{
    double bits = 0;
    for (int s = 0; s < kSymbols; ++s) {
        if (counts[s] == 0)
            continue;
        if (s >= table.symbols || table.freq[s] == 0)
            return std::numeric_limits<double>::infinity();
        bits += double(counts[s]) * (rans::kProbBits - std::log2(double(table.freq[s])));
    }
    return bits;
}

bool ProgressiveTables::hasWeights() const
{
    for (const PredictorWeights& w : weights_)
        if (w.any())
            return true;
    return false;
}

std::shared_ptr<const ProgressiveTables>
ProgressiveTables::withWeights(std::vector<PredictorWeights> weights, int contexts)
{
    std::shared_ptr<ProgressiveTables> t(
        new ProgressiveTables(static_cast<int>(weights.size()), contexts));
    t->weights_ = std::move(weights);
    if (!t->hasWeights())
        t->weights_.clear();
    return t;
}

std::shared_ptr<const ProgressiveTables> ProgressiveTables::fit(const SymbolCounts& counts,
                                                                const ProgressiveTables* base)
{
    std::shared_ptr<ProgressiveTables> t(
        new ProgressiveTables(counts.levelCount(), counts.contexts()));
    if (base)
        t->weights_ = base->weights_;
    for (int l = 0; l < counts.levelCount(); ++l)
        for (int c = 0; c < kClasses; ++c)
            for (int x = 0; x < counts.contexts(); ++x) {
                const uint64_t* h = counts.histogram(l, c, x);
                uint16_t freq[kSymbols];
                if (!normalize(h, freq))
                    continue;
                int symbols = kSymbols;
                while (freq[symbols - 1] == 0)
                    --symbols;
                auto fitted = std::make_unique<rans::Table>();
                fitted->assign(freq, symbols);
                const size_t i = (size_t(l) * kClasses + c) * counts.contexts() + x;
                // Version 2's bitmap costs no more per stored table than version 1's varint.
                const double stored = cost(h, *fitted) + 8.0 * double(storedBytes(*fitted));
                if (!(stored < cost(h, *t->index_[i])))
                    continue;
                t->index_[i] = fitted.get();
                t->stored_symbols_[i] = symbols;
                t->owned_.push_back(std::move(fitted));
            }
    return t;
}

std::vector<uint8_t> ProgressiveTables::serialize() const
{
    if (owned_.empty() && !hasWeights())
        return {};
    const uint8_t version = versionFor(contexts_);
    std::vector<uint8_t> out{kMagic, version, static_cast<uint8_t>(level_count_)};
    // Predictor corrections: a flag, then levels 1.. × classes A, B, C × 12 taps as i16.
    out.push_back(hasWeights() ? 1 : 0);
    if (hasWeights())
        for (int l = 1; l < level_count_; ++l)
            for (const auto& cls : weights_[l].w)
                for (const int16_t v : cls) {
                    out.push_back(static_cast<uint8_t>(uint16_t(v)));
                    out.push_back(static_cast<uint8_t>(uint16_t(v) >> 8));
                }
    if (version == kVersionParentClasses) {
        std::vector<uint8_t> bitmap((index_.size() + 7) / 8, 0);
        for (size_t i = 0; i < index_.size(); ++i)
            if (stored_symbols_[i] > 0)
                bitmap[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
        out.insert(out.end(), bitmap.begin(), bitmap.end());
    }
    for (size_t i = 0; i < index_.size(); ++i) {
        if (version == kVersionParentClasses && stored_symbols_[i] == 0)
            continue;
        putVarint(out, static_cast<uint32_t>(stored_symbols_[i]));
        for (int s = 0; s < stored_symbols_[i]; ++s)
            putVarint(out, index_[i]->freq[s]);
    }
    return out;
}

std::shared_ptr<const ProgressiveTables> ProgressiveTables::parse(const uint8_t* data, size_t size,
                                                                  int level_count, int contexts,
                                                                  std::string* problem)
{
    auto fail = [&](const std::string& what) -> std::shared_ptr<const ProgressiveTables> {
        if (problem)
            *problem = what;
        return nullptr;
    };
    if (level_count < 1 || level_count > kMaxLevels)
        return fail("level count " + std::to_string(level_count) + " is outside 1..32");
    if (contexts != kContexts && contexts != kContextsV4)
        return fail("internal error: " + std::to_string(contexts) + " contexts per class");
    if (size == 0)
        return defaults(level_count, contexts);
    if (size < 3 || data[0] != kMagic)
        return fail("codec tables do not start with 'T'");
    const uint8_t version = versionFor(contexts);
    if (data[1] != version)
        return fail("codec tables version is " + std::to_string(data[1]) + ": must be " +
                    std::to_string(version) + " for this payload version");
    if (data[2] != level_count)
        return fail("codec tables are for " + std::to_string(data[2]) +
                    " levels: the archive has " + std::to_string(level_count));
    std::shared_ptr<ProgressiveTables> t(new ProgressiveTables(level_count, contexts));
    const uint8_t* p = data + 3;
    const uint8_t* end = data + size;
    if (p == end)
        return fail("codec tables truncated before the predictor weights flag");
    const uint8_t has_weights = *p++;
    if (has_weights > 1)
        return fail("codec tables predictor weights flag is " + std::to_string(has_weights) +
                    ": must be 0 or 1");
    if (has_weights) {
        const size_t bytes = size_t(level_count - 1) * 3 * kCorrectionTapCount * 2;
        if (size_t(end - p) < bytes)
            return fail("codec tables truncated in the predictor weights");
        t->weights_.assign(size_t(level_count), PredictorWeights{});
        for (int l = 1; l < level_count; ++l)
            for (auto& cls : t->weights_[l].w)
                for (int16_t& v : cls) {
                    v = static_cast<int16_t>(uint16_t(p[0]) | uint16_t(p[1]) << 8);
                    p += 2;
                    if (v > kMaxCorrectionWeight || v < -kMaxCorrectionWeight)
                        return fail("codec tables: level " + std::to_string(l) +
                                    " has a predictor weight of " + std::to_string(v) +
                                    ": must be within ±4095");
                }
        if (!t->hasWeights())
            return fail("codec tables: predictor weights flagged but all 0 (not canonical)");
    }
    const uint8_t* bitmap = nullptr;
    if (version == kVersionParentClasses) {
        const size_t bytes = (t->index_.size() + 7) / 8;
        if (size_t(end - p) < bytes)
            return fail("codec tables truncated in the stored-table bitmap");
        static_assert(kClasses * kContextsV4 % 8 == 0, "a level's bitmap is whole bytes");
        bitmap = p;
        p += bytes;
    }
    for (size_t i = 0; i < t->index_.size(); ++i) {
        const std::string where = "codec table " + std::to_string(i);
        if (bitmap && !(bitmap[i / 8] >> (i % 8) & 1))
            continue;
        const int cls = int(i / size_t(contexts)) % kClasses, context = int(i % size_t(contexts));
        if (!usedContext(cls, context))
            return fail(where + " is stored: class 0 has no context " + std::to_string(context));
        uint32_t symbols;
        if (!getVarint(p, end, symbols))
            return fail(where + ": truncated");
        if (symbols > uint32_t(kSymbols))
            return fail(where + " has " + std::to_string(symbols) + " symbols: at most 71");
        if (symbols == 0 && bitmap)
            return fail(where + " is marked stored with 0 symbols");
        if (symbols == 0)
            continue;
        uint16_t freq[kSymbols] = {};
        uint32_t sum = 0;
        for (uint32_t s = 0; s < symbols; ++s) {
            uint32_t f;
            if (!getVarint(p, end, f))
                return fail(where + ": truncated");
            if (f > rans::kProbScale)
                return fail(where + ": frequency " + std::to_string(f) + " above 4096");
            freq[s] = static_cast<uint16_t>(f);
            sum += f;
        }
        if (sum != rans::kProbScale)
            return fail(where + ": frequencies sum to " + std::to_string(sum) + ": must be 4096");
        if (freq[symbols - 1] == 0)
            return fail(where + ": its last symbol has frequency 0 (not canonical)");
        auto table = std::make_unique<rans::Table>();
        table->assign(freq, static_cast<int>(symbols));
        t->index_[i] = table.get();
        t->stored_symbols_[i] = static_cast<int>(symbols);
        t->owned_.push_back(std::move(table));
    }
    if (p != end)
        return fail("codec tables have " + std::to_string(end - p) + " trailing bytes");
    if (t->owned_.empty() && !t->hasWeights())
        return fail("codec tables store no table (an archive without tables has none)");
    return t;
}

} // namespace ridge
