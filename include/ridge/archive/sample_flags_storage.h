#pragma once
// Storage of a patch's sample flags (pyramid/sample_flags.h) inside a patch blob of format
// version 4 or later, right after the validity mask (docs/FORMAT.md, "Sample flags"):
//
//   u8 kind: 0 = no sample has a flag, 1 = every sample is water and none was filled,
//   2 = bitmaps (version 4), 3 = context-coded bitmaps (version 5 on).
//   Kind 2: u32 frame_size, then one zstd frame of frame_size bytes whose content (size
//   stored in the frame, exactly ceil(2·n² / 8) bytes) is the n² water bits then the n²
//   filled bits, row-major, least significant bit first; the bits past the last are 0.
//   Kind 3: u8 planes (bit 0 water, bit 1 filled: the planes coded, each with a set bit),
//   u32 stream_size, then the planes coded by context_bitmap.h in stream_size bytes.
//
// Canonical: a bitmap kind is written only when neither 0 nor 1 describes the patch, and each
// version has one bitmap kind, so every patch's flags have exactly one encoding.
#include "ridge/archive/format.h"
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive {

// Encodes `flags` (any kind; Mixed bytes are canonicalized first) for an archive of format
// `version` (>= 4). Empty when a Mixed patch does not hold patch_size² bytes, or zstd fails.
std::vector<uint8_t> packSampleFlags(const PatchSampleFlags& flags, int patch_size,
                                     uint32_t version = kFormatVersion);

// The one-byte encoding of a patch without flags (kind 0).
inline std::vector<uint8_t> noSampleFlags()
{
    return {0};
}

// Decodes the flags at data[0 .. size): `size` is what remains of the blob after the validity
// mask; `consumed` receives their length (the payload starts there). Returns an empty string
// on success, otherwise the problem naming the field ("sample flags kind is 7: must be ...").
// `validity`, when given, is the patch's validity mask: a sample that is not valid must have
// no flag (the rule holds at the finest level and, with decimation, at every level).
std::string unpackSampleFlags(const uint8_t* data, size_t size, int patch_size,
                              const PatchValidity* validity, PatchSampleFlags& out,
                              size_t& consumed, uint32_t version = kFormatVersion);

} // namespace ridge::archive
