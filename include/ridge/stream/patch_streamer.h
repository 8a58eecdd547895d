#pragma once
// Asynchronous patch streaming: the render thread never waits on disk or decoding.
//
// Three stages, as the streaming issue and the clipmaps thesis (§5.2–5.4) ask:
//   1. I/O threads read blobs (pread; ArchiveReader is thread-safe) into a RAM cache of
//      compressed patches, bounded in bytes (LRU);
//   2. a decode pool entropy-decodes cached blobs into a RAM cache of decoded patches,
//      bounded in bytes (LRU) — either to codes (ancestors first for predictive codecs) or,
//      with gpu_decode, to the codec's CPU half (HeightCodec::decodeForGpu: the progressive
//      codec's residuals, the JPEG 2000 difference layer, the fractal transforms), which the
//      renderer's GPU decoder for the codec finishes (hardware-tessellation paper,
//      "Implementation Details");
//   3. the render thread calls request() for the patches it wants (each frame, with a
//      priority: larger first) and takeReady() for what is decoded since.
// Requests not renewed by the latest beginFrame() are stale and dropped before a worker
// starts them, so a camera that moves fast never queues work for places it has left.
//
// Thread safety: every member may be called from the render thread while workers run; the
// destructor stops and joins the workers (in-flight work finishes first).
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

struct StreamerOptions {
    size_t compressed_cache_bytes = size_t(64) << 20; // blobs as read
    size_t decoded_cache_bytes = size_t(192) << 20;   // decode results
    int io_threads = 1;
    int decode_threads = 2;
    // Deliver the patches the codec decodes on the GPU (ArchiveReader::decodesOnGpu) as its
    // CPU half (DecodedPatch::gpu_payload) instead of decoding them to codes on the CPU.
    bool gpu_decode = false;
    // Run by the decode workers on every patch they decode to codes (DecodedPatch::prepared):
    // what the renderer's LOD schemes derive from codes, built off the render thread.
    std::vector<PatchPreparation> preparations;

    // One RAM budget split between the two caches: a quarter for compressed blobs (several
    // times as many patches as the same bytes decoded), the rest for decoded patches.
    static StreamerOptions forRamBudget(size_t bytes, int threads);
};

struct StreamerStats {
    uint64_t requested = 0; // requests accepted (not already ready, queued or cached)
    uint64_t cancelled = 0; // stale requests dropped
    uint64_t decoded = 0;   // patches decoded by the pool (ancestors included)
    // Patches the decoded cache held as GPU payloads whose codes a child's CPU half needed,
    // finished on the CPU (HeightCodec::finishOnCpu) instead of being decoded again.
    uint64_t finished_on_cpu = 0;
    uint64_t bytes_read = 0;      // blob bytes read from the archive
    uint64_t bytes_decoded = 0;   // bytes of decode results (codes or GPU payloads, λ)
    uint64_t cache_hits = 0;      // requests served from the decoded cache
    uint64_t compressed_hits = 0; // decodes that found their blob in the compressed cache
    size_t cache_bytes = 0;       // decoded patches held now
    size_t compressed_bytes = 0;  // compressed blobs held now
    size_t queued = 0;            // waiting for a worker now
    size_t in_flight = 0;         // being read or decoded now
};

class PatchStreamer {
  public:
    PatchStreamer(const archive::ArchiveReader& reader, const StreamerOptions& options);
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
    // The same for at most `timeout_seconds`: true when idle, false when the time ran out.
    bool waitIdleFor(double timeout_seconds);

    StreamerStats stats() const;
    const StreamerOptions& options() const { return options_; }
    // The first error ("PATH: patch (...): ..."), empty if none. A failed patch is not
    // requested again.
    std::string error() const;

  private:
    using Blob = std::shared_ptr<const std::vector<uint8_t>>;
    enum class Stage { Read, Decode };
    struct Request {
        PatchId id;
        double priority = 0.0;
        uint64_t frame = 0;
        Stage stage = Stage::Read;
    };
    void work(Stage stage);
    // The most urgent queued request of `stage` after dropping stale ones; end() if none.
    std::unordered_map<int64_t, Request>::iterator nextLocked(Stage stage);
    void finishLocked(int64_t key);
    void failLocked(int64_t key, const std::string& message);
    Blob blobLocked(PatchId p, std::unique_lock<std::mutex>& lock, bool* cached = nullptr);
    std::shared_ptr<const DecodedPatch> decodeLocked(PatchId p, std::unique_lock<std::mutex>& lock,
                                                     bool codes = false);
    std::shared_ptr<const DecodedPatch> findCacheLocked(int64_t key);
    std::shared_ptr<const DecodedPatch> finishOnCpuLocked(const DecodedPatch& on_gpu,
                                                          std::unique_lock<std::mutex>& lock);

    const archive::ArchiveReader& reader_;
    StreamerOptions options_;
    mutable std::mutex mutex_;
    std::condition_variable read_cv_, decode_cv_, idle_cv_;
    std::unordered_map<int64_t, Request> queued_;
    std::unordered_map<int64_t, Request> in_flight_; // renewals land here while a worker runs
    std::unordered_set<int64_t> failed_;
    std::vector<std::shared_ptr<const DecodedPatch>> ready_;
    std::unordered_set<int64_t> ready_keys_;
    LruCache<int64_t, Blob> compressed_;                             // by patch index
    LruCache<int64_t, std::shared_ptr<const DecodedPatch>> decoded_; // by patch index
    uint64_t frame_ = 0;
    bool stop_ = false;
    std::string error_;
    StreamerStats stats_;
    std::vector<std::thread> workers_;
};

} // namespace ridge::stream
