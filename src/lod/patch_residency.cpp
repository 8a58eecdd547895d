#include "ridge/lod/patch_residency.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <numeric>

namespace ridge::lod {

PatchResidency::PatchResidency(const PyramidGeometry& geometry, int capacity)
    : geometry_(geometry), slot_owner_(capacity, -1), last_used_(capacity, 0)
{
    if (capacity <= 0)
        throw Error("patch residency: capacity must be positive");
    free_slots_.resize(capacity);
    // Pop from the back: slot 0 is handed out first.
    std::iota(free_slots_.rbegin(), free_slots_.rend(), 0);
}

int PatchResidency::slotOf(PatchId p) const
{
    auto it = slot_of_.find(geometry_.patchIndex(p));
    return it == slot_of_.end() ? -1 : it->second;
}

void PatchResidency::release(PatchId p)
{
    auto it = slot_of_.find(geometry_.patchIndex(p));
    if (it == slot_of_.end())
        return;
    slot_owner_[it->second] = -1;
    free_slots_.push_back(it->second);
    slot_of_.erase(it);
}

std::vector<PatchResidency::Load> PatchResidency::update(const std::vector<PatchId>& needed,
                                                         uint64_t frame)
{
    if (needed.size() > slot_owner_.size())
        throw Error("patch residency: " + std::to_string(needed.size()) + " patches needed, " +
                    std::to_string(slot_owner_.size()) + " slots");
    latest_frame_ = std::max(latest_frame_, frame);
    std::vector<PatchId> missing;
    for (PatchId p : needed) {
        auto it = slot_of_.find(geometry_.patchIndex(p));
        if (it != slot_of_.end())
            last_used_[it->second] = frame;
        else
            missing.push_back(p);
    }
    // Duplicates in `needed` would take two slots.
    std::sort(missing.begin(), missing.end(), [&](PatchId a, PatchId b) {
        return geometry_.patchIndex(a) < geometry_.patchIndex(b);
    });
    missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
    if (missing.size() > free_slots_.size()) {
        // Oldest first among slots not used this frame.
        std::vector<int> candidates;
        for (int s = 0; s < capacity(); ++s)
            if (slot_owner_[s] >= 0 && last_used_[s] != frame)
                candidates.push_back(s);
        const size_t want = missing.size() - free_slots_.size();
        std::partial_sort(candidates.begin(), candidates.begin() + want, candidates.end(),
                          [&](int a, int b) { return last_used_[a] < last_used_[b]; });
        for (size_t k = 0; k < want; ++k) {
            const int s = candidates[k];
            slot_of_.erase(slot_owner_[s]);
            slot_owner_[s] = -1;
            free_slots_.push_back(s);
            ++evictions_;
        }
    }
    std::vector<Load> loads;
    for (PatchId p : missing) {
        const int64_t key = geometry_.patchIndex(p);
        const int s = free_slots_.back();
        free_slots_.pop_back();
        slot_of_[key] = s;
        slot_owner_[s] = key;
        last_used_[s] = frame;
        loads.push_back({p, s});
    }
    return loads;
}

} // namespace ridge::lod
