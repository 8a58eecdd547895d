#pragma once
// A map from patch index to a small value for one frame, which a frame loop clears and
// refills without allocating: open addressing over a power-of-two table whose entries carry
// the generation that wrote them, so clear() is O(1) and keeps the table. It only grows
// (to keep the load at most 1/2); a dense array over PyramidGeometry::patchCount() would be
// simpler but takes gigabytes for a planet-sized archive, and std::unordered_map allocates a
// node per insertion.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace ridge::stream {

template <typename Value> class FrameKeyMap {
  public:
    // Forgets every entry; the table stays.
    void clear()
    {
        ++generation_;
        size_ = 0;
    }
    size_t size() const { return size_; }
    // Room for `n` keys without growing.
    void reserve(size_t n)
    {
        while (2 * n > table_.size())
            grow();
    }
    bool contains(int64_t key) const { return find(key) != nullptr; }

    // Inserts key -> value unless `key` is present; returns whether it was inserted.
    bool insert(int64_t key, Value value)
    {
        if (2 * (size_ + 1) > table_.size())
            grow();
        Entry& e = table_[probe(table_, key)];
        if (e.generation == generation_)
            return false;
        e = Entry{key, std::move(value), generation_};
        ++size_;
        return true;
    }

    // The value of `key`, or null.
    const Value* find(int64_t key) const
    {
        if (table_.empty())
            return nullptr;
        const Entry& e = table_[probe(table_, key)];
        return e.generation == generation_ ? &e.value : nullptr;
    }

  private:
    struct Entry {
        int64_t key = 0;
        Value value{};
        uint64_t generation = 0; // the map's generation starts at 1: a new entry is empty
    };

    // The slot holding `key` this generation, or the empty one where it would go.
    size_t probe(const std::vector<Entry>& table, int64_t key) const
    {
        const size_t mask = table.size() - 1;
        // Fibonacci hashing, high bits folded down: patch indices of a region come in runs.
        uint64_t h = uint64_t(key) * 0x9E3779B97F4A7C15ull;
        size_t k = size_t(h ^ (h >> 32)) & mask;
        while (table[k].generation == generation_ && table[k].key != key)
            k = (k + 1) & mask;
        return k;
    }

    void grow()
    {
        std::vector<Entry> bigger(table_.empty() ? 64 : 2 * table_.size());
        for (Entry& e : table_)
            if (e.generation == generation_)
                bigger[probe(bigger, e.key)] = std::move(e);
        table_.swap(bigger);
    }

    std::vector<Entry> table_;
    uint64_t generation_ = 1;
    size_t size_ = 0;
};

} // namespace ridge::stream
