#pragma once
// What the sharded build's steps share (pipeline/shard.h). Internal to ridge_pipeline.
#include "build_stages.h"

#include "ridge/archive/shard_file.h"
#include "ridge/pipeline/shard.h"
#include "ridge/pyramid/patch_error.h"

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace ridge::shard_internal {

using build_stages::recordedSourceName;

// The finest samples under patch `root` and its descendants, shared edges included, clamped to
// the raster.
io::PixelWindow subtreeWindow(const PyramidGeometry& g, PatchId root);

// Reads a plan file's JSON into `plan`, every field checked for type and range; the
// structure and hashes are loadPlan's.
class PlanReader {
  public:
    PlanReader(std::string path, const std::string& text);
    void read(ShardPlan& plan) const;

  private:
    std::string path_;
    std::string text_;
};

// Sections of the shard files.
inline constexpr uint32_t kTagInfo = archive::shardTag("INFO");         // JSON
inline constexpr uint32_t kTagRoot = archive::shardTag("ROOT");         // n² u16 codes
inline constexpr uint32_t kTagRootFlags = archive::shardTag("RFLG");    // n² flag bytes
inline constexpr uint32_t kTagObservations = archive::shardTag("OBSV"); // trainer bytes
inline constexpr uint32_t kTagCodec = archive::shardTag("CODC");        // training state
inline constexpr uint32_t kTagParents = archive::shardTag("PRNT");      // level k−1 recons
inline constexpr uint32_t kTagRecords = archive::shardTag("RECS");      // index entries
inline constexpr uint32_t kTagBlobs = archive::shardTag("BLOB");        // patch blobs
inline constexpr uint32_t kTagTables = archive::shardTag("TABL");       // archive codec tables
// Bounds on sections a reader allocates whole.
inline constexpr uint64_t kMaxInfoBytes = uint64_t{1} << 20;
inline constexpr uint64_t kMaxObservationBytes = uint64_t{64} << 20;

// The keys of the steps' outputs: the hash of everything the output depends on.
uint64_t summaryKey(const PlanShard& shard);
uint64_t observationKey(const PlanShard& shard, uint64_t top_state);
uint64_t segmentKey(const PlanShard& shard, uint64_t top_state, const uint16_t* parent, int n);
uint64_t hashBytes(const std::vector<uint8_t>& bytes);

// The patches of a shard's subtree (root level k down to the finest), positioned level by
// level, row-major: the order of its segment's records.
class SubtreeLayout {
  public:
    SubtreeLayout(const PyramidGeometry& g, PatchId root);
    const PatchId& root() const { return root_; }
    // The subtree's patches of level l: columns [firstX, endX) × rows [firstY, endY).
    int firstX(int l) const { return root_.x << (l - root_.level); }
    int firstY(int l) const { return root_.y << (l - root_.level); }
    int endX(int l) const;
    int endY(int l) const;
    int columns(int l) const { return endX(l) - firstX(l); }
    int64_t count(int l) const { return int64_t(columns(l)) * (endY(l) - firstY(l)); }
    int64_t total() const { return first_.back(); }
    // Position of level l's first patch.
    int64_t firstPosition(int l) const { return first_[size_t(l - root_.level)]; }
    // The k-th patch of level l in row-major order.
    PatchId patchAt(int l, int64_t k) const;
    // The patch's position in its level's view of the subtree's window.
    PatchId local(PatchId p) const
    {
        return {p.level, p.x - firstX(p.level), p.y - firstY(p.level)};
    }
    // Its position among all the subtree's patches; −1 for a patch outside the subtree.
    int64_t position(PatchId p) const;

  private:
    const PyramidGeometry* g_;
    PatchId root_;
    std::vector<int64_t> first_; // position of each level's first patch, then the total
};

// A shard's window read from the source and its subtree's pyramid and bounds: everything a
// shard step starts from.
class Subtree {
  public:
    // Reads the window (refusing inputs changed since the plan and windows with voids, naming
    // the shard) and measures every patch of the subtree bottom up.
    Subtree(const ShardPlan& plan, int64_t shard);

    const PlanShard& shard() const { return shard_; }
    const PyramidGeometry& geometry() const { return g_; }
    const SubtreeLayout& layout() const { return layout_; }
    // Level `l` (k..L−1) of the window, a strided view.
    const LevelView& view(int l) const { return views_[size_t(l - shard_.root.level)]; }
    // Err_Appr and the range of patch p (its own and its descendants').
    build_stages::PatchSummary summary(PatchId p) const;
    // Sample flags of patch p; null when the plan flags no water.
    bool hasFlags() const { return !flags_.empty(); }
    PatchSampleFlags flags(PatchId p) const;

    // The samples this shard owns (shared edges go to the shard west or north of them, the
    // raster's last row and column to the last shard): counted once over all shards.
    int64_t owned_samples = 0;
    int64_t owned_water = 0;
    double min_metres = 0; // over the window's samples
    double max_metres = 0;
    int64_t samples_read = 0;

  private:
    PlanShard shard_;
    PyramidGeometry g_;
    SubtreeLayout layout_;
    CodeGrid window_;
    std::vector<uint8_t> flags_;
    std::vector<LevelView> views_;
    PatchErrors errors_; // by SubtreeLayout::position
};

// Patch blobs appended to a shard file's BLOB section (opened by the constructor) and their
// index entries kept for its RECS section (written by finish()), sealed as ArchiveWriter
// seals them: offset (from the section's start), sizes, CRC-32 of the blob.
class BlobSink {
  public:
    explicit BlobSink(archive::ShardFileWriter& out);
    void add(build_stages::EncodedPatch& patch);
    void finish();

  private:
    archive::ShardFileWriter& out_;
    std::vector<uint8_t> records_;
};

// A file's INFO section as a JSON object.
nlohmann::json readInfo(const archive::ShardFileReader& file);

// The untrained codec and header of the plan's archive (the quantization of its 8/16-bit
// source), as `ridge build` makes them.
build_stages::BuildContext planContext(const ShardPlan& plan);

// The codec of a top file's training state.
void restoreCodec(build_stages::BuildContext& ctx, const archive::ShardFileReader& top);

// Peak resident memory of this process, bytes.
uint64_t peakRss();

} // namespace ridge::shard_internal
