#pragma once
// The static entropy tables of progressive codec v2, one per (level, sample class, context),
// learned from the whole pyramid at build time and stored once per archive (the "codec
// tables" region of docs/FORMAT.md).
//
// Symbols are signed residual tokens (progressive_tokens.h, 71 of them). Sample classes:
// 0 = the R refinements of a child patch (one context) or, at level 0, the MED residuals
// of the root patch; 1, 2, 3 = the A, B, C prediction errors. Contexts are the activity
// classes of the residuals already decoded around a sample (kContexts of them); payload v4
// multiplies them by the parent class, how far apart the parent's bins bracketing the sample
// are (0, 1, 2 or more steps: kParentClasses), as context = parent class · kContexts +
// activity (kContextsV4 per class; class 0 uses the first kContexts).
//
// A table that is not stored is the codec's default for its context: a two-sided geometric
// distribution whose spread follows the activity class, generated with integer and exactly
// rounded arithmetic only, so every platform builds the same tables. The trainer stores a
// table only when the bits it saves on the archive's own symbols exceed its own bytes, so a
// tiny archive stores almost nothing and pays almost nothing.
#include "ridge/codec/progressive_reconstruction.h"
#include "ridge/codec/rans_coder.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ridge {

namespace progressive_tables {
inline constexpr int kClasses = 4;
inline constexpr int kContexts = 16; // activity contexts (payload v2, v3: all of them)
inline constexpr int kParentClasses = 3;
inline constexpr int kContextsV4 = kContexts * kParentClasses;
inline constexpr int kSymbols = 71;
inline constexpr int kMaxLevels = 32;
} // namespace progressive_tables

// Symbol counts [level][class][context][symbol], what the trainer accumulates; `contexts`
// per class (kContexts or kContextsV4).
class SymbolCounts {
  public:
    explicit SymbolCounts(int level_count = 0, int contexts = progressive_tables::kContexts);
    int levelCount() const { return level_count_; }
    int contexts() const { return contexts_; }
    uint64_t& at(int level, int cls, int context, int symbol)
    {
        return counts_[index(level, cls, context) * progressive_tables::kSymbols + symbol];
    }
    uint64_t at(int level, int cls, int context, int symbol) const
    {
        return counts_[index(level, cls, context) * progressive_tables::kSymbols + symbol];
    }
    const uint64_t* histogram(int level, int cls, int context) const
    {
        return &counts_[index(level, cls, context) * progressive_tables::kSymbols];
    }
    void merge(const SymbolCounts& other);
    // The non-zero counts as bytes (u32 count, then u32 position + u64 count each, little
    // endian), and their sum back in: false for bytes that are not such for this size.
    std::vector<uint8_t> serialize() const;
    bool mergeSerialized(const uint8_t* data, size_t size);

  private:
    size_t index(int level, int cls, int context) const
    {
        return (static_cast<size_t>(level) * progressive_tables::kClasses + cls) * contexts_ +
               context;
    }
    int level_count_;
    int contexts_;
    std::vector<uint64_t> counts_;
};

class ProgressiveTables {
  public:
    // Every table the default, `contexts` per class (kContexts: payload v2 and v3;
    // kContextsV4: payload v4).
    static std::shared_ptr<const ProgressiveTables>
    defaults(int level_count, int contexts = progressive_tables::kContexts);
    // Default tables with these predictor corrections ([level], level 0 unused; all-zero
    // weights are none).
    static std::shared_ptr<const ProgressiveTables>
    withWeights(std::vector<PredictorWeights> weights,
                int contexts = progressive_tables::kContexts);
    // Tables fitted to `counts`, each stored only where it pays (see above), keeping `base`'s
    // predictor corrections (the counts were taken with them).
    static std::shared_ptr<const ProgressiveTables> fit(const SymbolCounts& counts,
                                                        const ProgressiveTables* base = nullptr);
    // Parses serialize()'s bytes for an archive of `level_count` levels and `contexts` per
    // class; null, with *problem saying what is wrong, for anything but exactly such bytes
    // (version, sizes, symbol counts, frequency sums, trailing bytes).
    static std::shared_ptr<const ProgressiveTables>
    parse(const uint8_t* data, size_t size, int level_count, int contexts, std::string* problem);

    // The stored form (docs/FORMAT.md, "Codec tables": version 1 for kContexts per class,
    // version 2 for kContextsV4); empty when every table is a default.
    std::vector<uint8_t> serialize() const;

    const rans::Table& table(int level, int cls, int context) const
    {
        return *index_[(static_cast<size_t>(level) * progressive_tables::kClasses + cls) *
                           contexts_ +
                       context];
    }
    int levelCount() const { return level_count_; }
    int contexts() const { return contexts_; }
    int storedCount() const { return static_cast<int>(owned_.size()); }
    // The predictor corrections of `level`, null when it has none.
    const PredictorWeights* weights(int level) const
    {
        return level < static_cast<int>(weights_.size()) && weights_[level].any() ? &weights_[level]
                                                                                  : nullptr;
    }
    bool hasWeights() const;

    // Bits `counts` cost under `table` (from its quantised frequencies), +inf when a counted
    // symbol has frequency 0.
    static double cost(const uint64_t* counts, const rans::Table& table);

  private:
    ProgressiveTables(int level_count, int contexts);
    int level_count_;
    int contexts_;
    std::vector<std::unique_ptr<rans::Table>> owned_; // stored tables, in index order
    std::vector<const rans::Table*> index_;           // [level][class][context]
    std::vector<int> stored_symbols_;                 // per index entry: 0 = default
    std::vector<PredictorWeights> weights_;           // [level]; empty = none
};

} // namespace ridge
