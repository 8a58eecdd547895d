#include "ridge/stream/patch_loader.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge::stream {

void DecodedPatch::setDrawableCells(const PatchValidity& validity)
{
    const size_t cells = size_t(validity.patch_size - 1) * size_t(validity.patch_size - 1);
    switch (validity.kind) {
    case PatchValidity::Kind::AllValid:
        drawable_cells.clear();
        break;
    case PatchValidity::Kind::NoneValid:
        drawable_cells.assign(cells, 0);
        break;
    case PatchValidity::Kind::Mixed:
        drawable_cells = validity.cells;
        break;
    }
}

void prepareProducts(DecodedPatch& patch, const std::vector<PatchPreparation>& preparations)
{
    patch.prepared.clear();
    for (const PatchPreparation& prepare : preparations)
        patch.prepared.push_back(prepare(patch.id, patch.codes.data()));
}

PatchLoader::PatchLoader(const archive::ArchiveReader& reader, size_t cache_patches,
                         std::vector<PatchPreparation> preparations)
    : reader_(reader), preparations_(std::move(preparations)),
      cache_(std::max<size_t>(cache_patches, size_t(reader.geometry().levelCount()) + 1))
{
}

std::shared_ptr<const DecodedPatch> PatchLoader::load(PatchId p)
{
    const int64_t key = reader_.geometry().patchIndex(p);
    if (const auto* hit = cache_.find(key)) {
        ++stats_.cache_hits;
        return *hit;
    }
    std::shared_ptr<const DecodedPatch> patch = decode(p);
    cache_.insert(key, patch);
    return patch;
}

std::shared_ptr<const DecodedPatch> PatchLoader::decode(PatchId p)
{
    // The parent stays referenced until the child is decoded, even if the cache drops it.
    std::shared_ptr<const DecodedPatch> parent;
    if (p.level > 0 && reader_.codec().needsParent(p.level))
        parent = load(p.parent());
    auto out = std::make_shared<DecodedPatch>();
    out->id = p;
    const int n = reader_.geometry().patchSize();
    out->codes.resize(size_t(n) * n);
    if (!parent && reader_.codec().needsParent(p.level))
        throw Error(reader_.describe(p) + ": internal error: no parent to decode from");
    PatchValidity validity;
    reader_.decodeBlob(p, reader_.readBlob(p), out->codes.data(),
                       parent ? parent->codes.data() : nullptr, &out->block_errors, &validity,
                       &out->sample_flags);
    out->setDrawableCells(validity);
    prepareProducts(*out, preparations_);
    ++stats_.decoded;
    stats_.bytes_read += reader_.record(p).size;
    stats_.bytes_decoded += out->bytes();
    return out;
}

} // namespace ridge::stream
