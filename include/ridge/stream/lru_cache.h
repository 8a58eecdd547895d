#pragma once
// A least-recently-used map with O(1) find, touch and insert, bounded by the total weight of
// its entries (a count when every weight is 1, bytes when weights are sizes): the patch
// caches of PatchLoader and PatchStreamer. Not thread-safe (PatchStreamer locks around it).
#include <algorithm>
#include <cstddef>
#include <list>
#include <unordered_map>
#include <utility>

namespace ridge::stream {

template <class Key, class Value> class LruCache {
  public:
    // `min_entries`: entries kept whatever their weight (so that a chain of ancestors fits
    // into a small byte budget).
    explicit LruCache(size_t capacity, size_t min_entries = 0)
        : capacity_(capacity), min_entries_(min_entries)
    {
    }

    // The value for `key`, now the most recently used; null when absent.
    const Value* find(const Key& key)
    {
        auto it = index_.find(key);
        if (it == index_.end())
            return nullptr;
        order_.splice(order_.begin(), order_, it->second);
        return &it->second->value;
    }
    // Inserts (or keeps) `key`, most recently used, dropping the least recently used entries
    // while the total weight exceeds the capacity.
    void insert(const Key& key, Value value, size_t weight = 1)
    {
        if (find(key))
            return;
        order_.push_front(Entry{key, std::move(value), weight});
        index_[key] = order_.begin();
        weight_ += weight;
        while (weight_ > capacity_ && order_.size() > std::max<size_t>(min_entries_, 1)) {
            weight_ -= order_.back().weight;
            index_.erase(order_.back().key);
            order_.pop_back();
        }
    }
    // Inserts `key` or replaces its value and weight, most recently used either way.
    void assign(const Key& key, Value value, size_t weight = 1)
    {
        if (auto it = index_.find(key); it != index_.end()) {
            const auto entry = it->second;
            weight_ -= entry->weight;
            index_.erase(it);
            order_.erase(entry);
        }
        insert(key, std::move(value), weight);
    }
    size_t size() const { return order_.size(); }
    size_t weight() const { return weight_; }

  private:
    struct Entry {
        Key key;
        Value value;
        size_t weight;
    };
    size_t capacity_, min_entries_;
    size_t weight_ = 0;
    std::list<Entry> order_; // most recently used first
    std::unordered_map<Key, typename std::list<Entry>::iterator> index_;
};

} // namespace ridge::stream
