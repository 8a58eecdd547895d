#pragma once
// Frame-to-frame reuse of resident patches: which patch lives in which texture-array slot
// (the paper's "list of unused subresources"), with least-recently-used replacement by frame
// timestamps (as the fractal-rings paper's tile cache). Plain bookkeeping, no GL: the
// renderer uploads what `update` asks for into the slots it names.
#include "ridge/pyramid/pyramid_geometry.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ridge::lod {

class PatchResidency {
  public:
    PatchResidency(const PyramidGeometry& geometry, int capacity);

    struct Load {
        PatchId id;
        int slot = 0;
    };
    // Marks every patch of `needed` as used at `frame` and returns those not yet resident, each
    // with a free slot, evicting the least recently used patches not needed at `frame` when
    // no slot is free. Throws ridge::Error when `needed` has more patches than slots.
    std::vector<Load> update(const std::vector<PatchId>& needed, uint64_t frame);

    // Slot of `p`, or −1 when it is not resident.
    int slotOf(PatchId p) const;
    int capacity() const { return int(slot_owner_.size()); }
    int residentCount() const { return int(slot_of_.size()); }
    uint64_t evictions() const { return evictions_; }
    // The latest `frame` passed to update (0 before the first): users that share a residency
    // continue from it, so that frames keep increasing and LRU order holds.
    uint64_t latestFrame() const { return latest_frame_; }
    // Forgets `p` (e.g. its upload failed); its slot becomes free.
    void release(PatchId p);

  private:
    PyramidGeometry geometry_;
    std::unordered_map<int64_t, int> slot_of_; // patch index -> slot
    std::vector<int64_t> slot_owner_;          // slot -> patch index, −1 free
    std::vector<uint64_t> last_used_;          // slot -> frame
    std::vector<int> free_slots_;
    uint64_t evictions_ = 0;
    uint64_t latest_frame_ = 0;
};

} // namespace ridge::lod
