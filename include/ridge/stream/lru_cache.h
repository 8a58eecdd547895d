#pragma once
// A least-recently-used map with O(1) find, touch and insert: the decoded-patch caches of
// PatchLoader and PatchStreamer. Not thread-safe (PatchStreamer locks around it).
#include <cstddef>
#include <list>
#include <unordered_map>
#include <utility>

namespace ridge::stream {

template <class Key, class Value> class LruCache {
  public:
    explicit LruCache(size_t capacity) : capacity_(capacity) {}

    // The value for `key`, now the most recently used; null when absent.
    const Value* find(const Key& key)
    {
        auto it = index_.find(key);
        if (it == index_.end())
            return nullptr;
        order_.splice(order_.begin(), order_, it->second);
        return &it->second->second;
    }
    // Inserts (or keeps) `key`, most recently used, dropping the least recently used entries
    // beyond the capacity.
    void insert(const Key& key, Value value)
    {
        if (find(key))
            return;
        order_.emplace_front(key, std::move(value));
        index_[key] = order_.begin();
        while (order_.size() > capacity_) {
            index_.erase(order_.back().first);
            order_.pop_back();
        }
    }
    size_t size() const { return order_.size(); }

  private:
    size_t capacity_;
    std::list<std::pair<Key, Value>> order_; // most recently used first
    std::unordered_map<Key, typename std::list<std::pair<Key, Value>>::iterator> index_;
};

} // namespace ridge::stream
