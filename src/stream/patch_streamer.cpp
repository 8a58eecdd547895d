#include "ridge/stream/patch_streamer.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge::stream {
namespace {

size_t decodedPatchBytes(const archive::ArchiveReader& reader)
{
    const size_t n = size_t(reader.geometry().patchSize());
    return n * n * sizeof(uint16_t) +
           size_t(reader.blockLayout().valuesPerPatch()) * sizeof(float) + sizeof(DecodedPatch);
}

} // namespace

PatchStreamer::PatchStreamer(const archive::ArchiveReader& reader, size_t ram_budget_bytes,
                             int threads)
    : reader_(reader), patch_bytes_(decodedPatchBytes(reader)),
      // All patches weigh the same: the byte budget is a count, and a root-to-leaf chain
      // always fits, whatever the budget.
      cache_(std::max(ram_budget_bytes / patch_bytes_, size_t(reader.geometry().levelCount()) + 1))
{
    for (int t = 0; t < std::max(threads, 1); ++t)
        workers_.emplace_back([this] { work(); });
}

PatchStreamer::~PatchStreamer()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    work_cv_.notify_all();
    for (std::thread& t : workers_)
        t.join();
}

void PatchStreamer::beginFrame()
{
    std::lock_guard<std::mutex> lock(mutex_);
    ++frame_;
}

void PatchStreamer::request(PatchId p, double priority)
{
    std::lock_guard<std::mutex> lock(mutex_);
    const int64_t key = reader_.geometry().patchIndex(p);
    if (failed_.count(key) || ready_keys_.count(key) || in_flight_.count(key))
        return;
    if (auto it = queued_.find(key); it != queued_.end()) {
        it->second.priority = priority;
        it->second.frame = frame_;
        return;
    }
    if (auto hit = findCacheLocked(key)) {
        ++stats_.cache_hits;
        ready_.push_back(hit);
        ready_keys_.insert(key);
        return;
    }
    queued_[key] = Request{p, priority, frame_};
    ++stats_.requested;
    work_cv_.notify_one();
}

std::vector<std::shared_ptr<const DecodedPatch>> PatchStreamer::takeReady()
{
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::shared_ptr<const DecodedPatch>> out;
    out.swap(ready_);
    ready_keys_.clear();
    return out;
}

std::shared_ptr<const DecodedPatch> PatchStreamer::cached(PatchId p)
{
    std::lock_guard<std::mutex> lock(mutex_);
    return findCacheLocked(reader_.geometry().patchIndex(p));
}

void PatchStreamer::waitIdle()
{
    std::unique_lock<std::mutex> lock(mutex_);
    idle_cv_.wait(lock, [this] { return queued_.empty() && in_flight_.empty(); });
}

StreamerStats PatchStreamer::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    StreamerStats s = stats_;
    s.cache_bytes = cache_.size() * patch_bytes_;
    s.queued = queued_.size();
    s.in_flight = in_flight_.size();
    return s;
}

std::string PatchStreamer::error() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    return error_;
}

std::shared_ptr<const DecodedPatch> PatchStreamer::findCacheLocked(int64_t key)
{
    const auto* hit = cache_.find(key);
    return hit ? *hit : nullptr;
}

void PatchStreamer::insertCacheLocked(const std::shared_ptr<const DecodedPatch>& patch)
{
    cache_.insert(reader_.geometry().patchIndex(patch->id), patch);
}

// Decodes `p` (ancestors first when the codec predicts from them), unlocking around the
// decoding itself. Two workers may decode a shared ancestor twice; the cache keeps one.
std::shared_ptr<const DecodedPatch> PatchStreamer::decodeLocked(PatchId p,
                                                                std::unique_lock<std::mutex>& lock)
{
    if (auto hit = findCacheLocked(reader_.geometry().patchIndex(p)))
        return hit;
    std::shared_ptr<const DecodedPatch> parent;
    if (p.level > 0 && reader_.codec().needsParent(p.level))
        parent = decodeLocked(PatchId{p.level - 1, p.x / 2, p.y / 2}, lock);
    lock.unlock();
    auto out = std::make_shared<DecodedPatch>();
    out->id = p;
    const int n = reader_.geometry().patchSize();
    out->codes.resize(size_t(n) * n);
    try {
        reader_.decodePatch(p, out->codes.data(), parent ? parent->codes.data() : nullptr,
                            &out->block_errors);
    } catch (...) {
        lock.lock();
        throw;
    }
    lock.lock();
    ++stats_.decoded;
    stats_.bytes_read += reader_.record(p).size;
    insertCacheLocked(out);
    return out;
}

void PatchStreamer::work()
{
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        work_cv_.wait(lock, [this] { return stop_ || !queued_.empty(); });
        if (stop_)
            return;
        // Drop stale requests, then take the most urgent one.
        auto best = queued_.end();
        for (auto it = queued_.begin(); it != queued_.end();) {
            if (it->second.frame < frame_) {
                it = queued_.erase(it);
                ++stats_.cancelled;
                continue;
            }
            if (best == queued_.end() || it->second.priority > best->second.priority)
                best = it;
            ++it;
        }
        if (best == queued_.end()) {
            idle_cv_.notify_all();
            continue;
        }
        const int64_t key = best->first;
        const PatchId id = best->second.id;
        queued_.erase(best);
        in_flight_.insert(key);
        try {
            std::shared_ptr<const DecodedPatch> patch = decodeLocked(id, lock);
            ready_.push_back(patch);
            ready_keys_.insert(key);
        } catch (const Error& e) {
            if (error_.empty())
                error_ = e.what();
            failed_.insert(key);
        }
        in_flight_.erase(key);
        if (queued_.empty() && in_flight_.empty())
            idle_cv_.notify_all();
    }
}

} // namespace ridge::stream
