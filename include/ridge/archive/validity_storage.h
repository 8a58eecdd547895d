#pragma once
// Storage of a patch's validity mask (pyramid/validity_pyramid.h) inside a patch blob of
// format version 2, right after the block-error frame (docs/FORMAT.md, "Validity mask"):
//
//   u8 kind: 0 = every sample valid and every cell drawable, 1 = none, 2 = bitmaps;
//   kind 2 only: u32 frame_size, then one zstd frame of frame_size bytes whose content
//   (size stored in the frame, exactly ceil((n² + (n−1)²) / 8) bytes) is the n² sample bits
//   then the (n−1)² cell bits, row-major, least significant bit first; the bits past the
//   last are 0.
//
// Canonical: kind 2 is written only when the bitmaps are not uniform (all ones is kind 0,
// all zeros kind 1), so every mask has exactly one encoding.
#include "ridge/pyramid/validity_pyramid.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive {

// Encodes `validity` (any kind; Mixed bitmaps are canonicalized first).
std::vector<uint8_t> packValidity(const PatchValidity& validity, int patch_size);

// The one-byte mask of a patch with every sample valid (kind 0): what v2 writers store for
// sources without kept nodata.
inline std::vector<uint8_t> allValidMask()
{
    return {0};
}

// Decodes the mask at data[0 .. size): `size` is what remains of the blob after the block
// errors; `consumed` receives the mask's length (the payload starts there). Returns an empty
// string on success, otherwise the problem naming the field ("validity kind is 7: must be 0,
// 1 or 2", "validity frame ... "). `corners_rule`: also check that every drawable cell's four
// corner samples are valid (true for decimation at every level and at the finest level of
// either filter).
std::string unpackValidity(const uint8_t* data, size_t size, int patch_size, bool corners_rule,
                           PatchValidity& out, size_t& consumed);

} // namespace ridge::archive
