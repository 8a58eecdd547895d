#pragma once
// Asynchronous patch streaming: the render thread never waits on disk or decoding.
//
// The render thread calls request() for the patches it wants (each frame, with a priority:
// larger first) and takeReady() for what has been decoded since. Worker threads read blobs
// (pread, ArchiveReader is thread-safe) and decode them — ancestors first for predictive
// codecs — into a RAM cache of decoded patches bounded in bytes (LRU). Requests not renewed
// by the latest beginFrame() are stale and dropped before a worker starts them, so a camera
// that moves fast never queues work for places it has left.
//
// Thread safety: every member may be called from the render thread while workers run; the
// destructor stops and joins the workers (in-flight decodes finish first).
#include "ridge/stream/lru_cache.h"
#include "ridge/stream/patch_loader.h"

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace ridge::stream {

struct StreamerStats {
    uint64_t requested = 0;  // requests accepted (not already ready, queued or cached)
    uint64_t cancelled = 0;  // stale requests dropped
    uint64_t decoded = 0;    // patches decoded by workers (ancestors included)
    uint64_t bytes_read = 0; // blob bytes
    uint64_t cache_hits = 0; // requests served from the RAM cache
    size_t cache_bytes = 0;  // decoded patches held now
    size_t queued = 0;       // waiting for a worker now
    size_t in_flight = 0;    // being decoded now
};

class PatchStreamer {
  public:
    // `ram_budget_bytes` bounds the decoded-patch cache (at least a root-to-leaf chain is
    // always kept). `threads` >= 1.
    PatchStreamer(const archive::ArchiveReader& reader, size_t ram_budget_bytes, int threads = 2);
    ~PatchStreamer();
    PatchStreamer(const PatchStreamer&) = delete;
    PatchStreamer& operator=(const PatchStreamer&) = delete;

    // Starts a frame: requests made before it and not renewed after it become stale.
    void beginFrame();
    // Asks for `p` (a larger priority is served first). Cheap when `p` is queued, in flight
    // or already ready; a cached patch is made ready at once.
    void request(PatchId p, double priority);
    // Patches decoded since the last call, in completion order.
    std::vector<std::shared_ptr<const DecodedPatch>> takeReady();
    // The decoded patch if it is in the RAM cache now (no decoding), else null.
    std::shared_ptr<const DecodedPatch> cached(PatchId p);
    // Blocks until no request is queued or in flight (tests, benchmarks).
    void waitIdle();

    StreamerStats stats() const;
    // The first decode error ("PATH: patch (...): ..."), empty if none. A failed patch is
    // not requested again.
    std::string error() const;

  private:
    struct Request {
        PatchId id;
        double priority = 0.0;
        uint64_t frame = 0;
    };
    void work();
    std::shared_ptr<const DecodedPatch> decodeLocked(PatchId p, std::unique_lock<std::mutex>& lock);
    void insertCacheLocked(const std::shared_ptr<const DecodedPatch>& patch);
    std::shared_ptr<const DecodedPatch> findCacheLocked(int64_t key);

    const archive::ArchiveReader& reader_;
    size_t patch_bytes_;
    mutable std::mutex mutex_;
    std::condition_variable work_cv_, idle_cv_;
    std::unordered_map<int64_t, Request> queued_;
    std::unordered_set<int64_t> in_flight_, failed_;
    std::vector<std::shared_ptr<const DecodedPatch>> ready_;
    std::unordered_set<int64_t> ready_keys_;
    LruCache<int64_t, std::shared_ptr<const DecodedPatch>> cache_; // decoded, by patch index
    uint64_t frame_ = 0;
    bool stop_ = false;
    std::string error_;
    StreamerStats stats_;
    std::vector<std::thread> workers_;
};

} // namespace ridge::stream
