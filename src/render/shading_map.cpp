#include "shading_map.h"

#include <algorithm>
#include <cstring>

namespace ridge::render {

namespace {
constexpr size_t kTilesPerSlot = lod::ShadingTiles().size();
}

ShadingMap::ShadingMap(int slots) : tiles_(size_t(std::max(slots, 1)) * kTilesPerSlot, 0u)
{
    glNamedBufferStorage(buffer_.id(), GLsizeiptr(tiles_.size() * sizeof(uint32_t)), tiles_.data(),
                         GL_DYNAMIC_STORAGE_BIT);
}

size_t ShadingMap::update(const std::vector<lod::SelectedPatch>& drawn,
                          const lod::PatchResidency& residency, const PyramidGeometry& geometry,
                          bool detail)
{
    const auto slot_of = [&](PatchId p) { return residency.slotOf(p); };
    if (!detail)
        scratch_.fill(0u); // every tile the drawn patch itself: no walk of its descendants
    size_t first = tiles_.size(), last = 0; // the changed range, in tiles
    for (const lod::SelectedPatch& d : drawn) {
        const int slot = residency.slotOf(d.id);
        if (slot < 0 || size_t(slot + 1) * kTilesPerSlot > tiles_.size())
            continue; // not drawn from a slot (or a scheme's own pieces): nothing to shade from
        if (detail)
            lod::shadingTiles(d.id, geometry, slot_of, scratch_);
        uint32_t* own = tiles_.data() + size_t(slot) * kTilesPerSlot;
        if (std::memcmp(own, scratch_.data(), sizeof(scratch_)) == 0)
            continue;
        std::memcpy(own, scratch_.data(), sizeof(scratch_));
        first = std::min(first, size_t(slot) * kTilesPerSlot);
        last = std::max(last, size_t(slot + 1) * kTilesPerSlot);
    }
    if (first >= last)
        return 0;
    // One range: the slots between two changed ones are sent too, which costs less than a
    // call per slot when the changes are many (a new view) and nothing when they are few.
    const size_t bytes = (last - first) * sizeof(uint32_t);
    glNamedBufferSubData(buffer_.id(), GLintptr(first * sizeof(uint32_t)), GLsizeiptr(bytes),
                         tiles_.data() + first);
    return bytes;
}

void ShadingMap::bind() const
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, buffer_.id());
}

} // namespace ridge::render
