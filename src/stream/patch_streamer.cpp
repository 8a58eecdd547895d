#include "ridge/stream/patch_streamer.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <chrono>

namespace ridge::stream {

StreamerOptions StreamerOptions::forRamBudget(size_t bytes, int threads)
{
    StreamerOptions o;
    o.compressed_cache_bytes = bytes / 4;
    o.decoded_cache_bytes = bytes - o.compressed_cache_bytes;
    // Reads are short (pread of a few kB, usually from the page cache); decoding is the work.
    o.io_threads = 1;
    o.decode_threads = std::max(threads, 1);
    return o;
}

PatchStreamer::PatchStreamer(const archive::ArchiveReader& reader, const StreamerOptions& options)
    : reader_(reader), options_(options), compressed_(options.compressed_cache_bytes, 1),
      // A root-to-leaf chain always fits, whatever the budget: predictive decoding needs it.
      decoded_(options.decoded_cache_bytes, size_t(reader.geometry().levelCount()) + 1)
{
    for (int t = 0; t < std::max(options.io_threads, 1); ++t)
        workers_.emplace_back([this] { work(Stage::Read); });
    for (int t = 0; t < std::max(options.decode_threads, 1); ++t)
        workers_.emplace_back([this] { work(Stage::Decode); });
}

PatchStreamer::~PatchStreamer()
{
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    read_cv_.notify_all();
    decode_cv_.notify_all();
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
    if (failed_.count(key) || ready_keys_.count(key))
        return;
    for (auto* pending : {&queued_, &in_flight_})
        if (auto it = pending->find(key); it != pending->end()) {
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
    const Stage stage = compressed_.find(key) ? Stage::Decode : Stage::Read;
    queued_[key] = Request{p, priority, frame_, stage};
    ++stats_.requested;
    (stage == Stage::Read ? read_cv_ : decode_cv_).notify_one();
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

bool PatchStreamer::waitIdleFor(double timeout_seconds)
{
    std::unique_lock<std::mutex> lock(mutex_);
    return idle_cv_.wait_for(lock, std::chrono::duration<double>(timeout_seconds),
                             [this] { return queued_.empty() && in_flight_.empty(); });
}

StreamerStats PatchStreamer::stats() const
{
    std::lock_guard<std::mutex> lock(mutex_);
    StreamerStats s = stats_;
    s.cache_bytes = decoded_.weight();
    s.compressed_bytes = compressed_.weight();
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
    const auto* hit = decoded_.find(key);
    return hit ? *hit : nullptr;
}

std::unordered_map<int64_t, PatchStreamer::Request>::iterator PatchStreamer::nextLocked(Stage stage)
{
    auto best = queued_.end();
    for (auto it = queued_.begin(); it != queued_.end();) {
        if (it->second.frame < frame_) {
            it = queued_.erase(it);
            ++stats_.cancelled;
            continue;
        }
        if (it->second.stage == stage &&
            (best == queued_.end() || it->second.priority > best->second.priority))
            best = it;
        ++it;
    }
    if (queued_.empty() && in_flight_.empty())
        idle_cv_.notify_all();
    return best;
}

void PatchStreamer::finishLocked(int64_t key)
{
    in_flight_.erase(key);
    if (queued_.empty() && in_flight_.empty())
        idle_cv_.notify_all();
}

void PatchStreamer::failLocked(int64_t key, const std::string& message)
{
    if (error_.empty())
        error_ = message;
    failed_.insert(key);
}

// The blob of `p` from the compressed cache (`*cached` set), or read now (unlocked around
// the read).
PatchStreamer::Blob PatchStreamer::blobLocked(PatchId p, std::unique_lock<std::mutex>& lock,
                                              bool* cached)
{
    const int64_t key = reader_.geometry().patchIndex(p);
    const Blob* hit = compressed_.find(key);
    if (cached)
        *cached = hit != nullptr;
    if (hit)
        return *hit;
    lock.unlock();
    Blob blob;
    try {
        blob = std::make_shared<const std::vector<uint8_t>>(reader_.readBlob(p));
    } catch (...) {
        lock.lock();
        throw;
    }
    lock.lock();
    stats_.bytes_read += blob->size();
    compressed_.insert(key, blob, blob->size());
    return blob;
}

// Decodes `p` from its blob, unlocking around the decoding itself: to the codec's CPU half
// when the GPU finishes it, else to codes with its ancestors first when the codec predicts from
// them. Two workers may decode a shared ancestor twice; the cache keeps one. `codes`: decoded to
// codes whatever the GPU could do (an ancestor a CPU half reads); a patch cached as a GPU
// payload is then finished on the CPU when the codec can, not decoded again.
std::shared_ptr<const DecodedPatch>
PatchStreamer::decodeLocked(PatchId p, std::unique_lock<std::mutex>& lock, bool codes)
{
    const int64_t key = reader_.geometry().patchIndex(p);
    const GpuDecoding gpu = reader_.codec().capabilities().gpu;
    if (auto hit = findCacheLocked(key)) {
        if (!codes || !hit->codes.empty())
            return hit;
        if (hit->gpu_payload && gpu.finishes_on_cpu)
            return finishOnCpuLocked(*hit, lock);
    }
    const bool on_gpu = !codes && options_.gpu_decode && reader_.decodesOnGpu(p.level);
    std::shared_ptr<const DecodedPatch> parent;
    if (p.level > 0 && reader_.codec().needsParent(p.level) &&
        (!on_gpu || gpu.cpu_half_reads_parent))
        parent = decodeLocked(p.parent(), lock, true);
    bool had_blob = false;
    const Blob blob = blobLocked(p, lock, &had_blob);
    lock.unlock();
    auto out = std::make_shared<DecodedPatch>();
    out->id = p;
    const size_t samples = size_t(reader_.geometry().patchSize()) * reader_.geometry().patchSize();
    try {
        if (on_gpu) {
            out->gpu_payload = reader_.decodeForGpu(
                p, *blob, parent ? parent->codes.data() : nullptr, &out->block_errors);
            PatchValidity validity;
            reader_.payloadOffset(p, *blob, &validity, &out->sample_flags);
            out->setDrawableCells(validity);
        } else {
            out->codes.resize(samples);
            PatchValidity validity;
            reader_.decodeBlob(p, *blob, out->codes.data(), parent ? parent->codes.data() : nullptr,
                               &out->block_errors, &validity, &out->sample_flags);
            out->setDrawableCells(validity);
            prepareProducts(*out, options_.preparations);
        }
    } catch (...) {
        lock.lock();
        throw;
    }
    lock.lock();
    ++stats_.decoded;
    stats_.compressed_hits += had_blob;
    stats_.bytes_decoded += out->bytes();
    // Codes replace a cached GPU payload of the same patch (decoded for a child whose CPU half
    // reads them): kept, the payload would have every later child decode the patch again.
    if (out->codes.empty())
        decoded_.insert(key, out, out->bytes());
    else
        decoded_.assign(key, out, out->bytes());
    return out;
}

// The codes of a patch the decoded cache holds as a GPU payload, from that payload and the
// parent's codes (the codec's GPU half run on the CPU): the entropy decoding, most of a
// decode's time, is not done twice. What else the patch holds carries over.
std::shared_ptr<const DecodedPatch>
PatchStreamer::finishOnCpuLocked(const DecodedPatch& on_gpu, std::unique_lock<std::mutex>& lock)
{
    const PatchId p = on_gpu.id;
    std::shared_ptr<const DecodedPatch> parent;
    if (p.level > 0 && reader_.codec().needsParent(p.level))
        parent = decodeLocked(p.parent(), lock, true);
    const std::shared_ptr<const GpuPayload> payload = on_gpu.gpu_payload;
    lock.unlock();
    auto out = std::make_shared<DecodedPatch>();
    out->id = p;
    out->drawable_cells = on_gpu.drawable_cells;
    out->sample_flags = on_gpu.sample_flags;
    try {
        const int n = reader_.geometry().patchSize();
        out->codes.resize(size_t(n) * n);
        reader_.finishOnCpu(p, *payload, parent ? parent->codes.data() : nullptr,
                            out->codes.data());
        // decodeForGpu gave the stored λ, or none when the archive stores none (a codec that
        // finishes on the CPU is not refinable): then derived, as decodeBlob does.
        out->block_errors = on_gpu.block_errors.empty()
                                ? reader_.deriveBlockErrors(out->codes.data())
                                : on_gpu.block_errors;
        prepareProducts(*out, options_.preparations);
    } catch (...) {
        lock.lock();
        throw;
    }
    lock.lock();
    ++stats_.finished_on_cpu;
    stats_.bytes_decoded += out->bytes();
    decoded_.assign(reader_.geometry().patchIndex(p), out, out->bytes());
    return out;
}

// One worker of `stage`: takes the most urgent request of its stage and reads it into the
// compressed cache (then hands it to the decode pool with whatever priority and frame
// renewals gave it) or decodes it (then makes it ready).
void PatchStreamer::work(Stage stage)
{
    std::condition_variable& cv = stage == Stage::Read ? read_cv_ : decode_cv_;
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        cv.wait(lock, [&] {
            return stop_ || std::any_of(queued_.begin(), queued_.end(),
                                        [&](const auto& q) { return q.second.stage == stage; });
        });
        if (stop_)
            return;
        auto next = nextLocked(stage);
        if (next == queued_.end())
            continue;
        const int64_t key = next->first;
        const PatchId id = next->second.id;
        in_flight_[key] = next->second;
        queued_.erase(next);
        try {
            if (stage == Stage::Read) {
                blobLocked(id, lock);
                Request r = in_flight_[key];
                r.stage = Stage::Decode;
                queued_[key] = r;
                decode_cv_.notify_one();
            } else {
                ready_.push_back(decodeLocked(id, lock));
                ready_keys_.insert(key);
            }
        } catch (const Error& e) {
            failLocked(key, e.what());
        }
        finishLocked(key);
    }
}

} // namespace ridge::stream
