#pragma once
// Storage of a patch's sample flags (pyramid/sample_flags.h) inside a patch blob of format
// version 4, right after the validity mask (docs/FORMAT.md, "Sample flags"):
//
//   u8 kind: 0 = no sample has a flag, 1 = every sample is water and none was filled,
//   2 = bitmaps; kind 2 only: u32 frame_size, then one zstd frame of frame_size bytes whose
//   content (size stored in the frame, exactly ceil(2·n² / 8) bytes) is the n² water bits
//   then the n² filled bits, row-major, least significant bit first; the bits past the last
//   are 0.
//
// Canonical: kind 2 is written only when neither 0 nor 1 describes the patch, so every patch's
// flags have exactly one encoding.
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive {

// Encodes `flags` (any kind; Mixed bytes are canonicalized first). Empty when a Mixed patch
// does not hold patch_size² bytes, or zstd fails.
std::vector<uint8_t> packSampleFlags(const PatchSampleFlags& flags, int patch_size);

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
                              size_t& consumed);

} // namespace ridge::archive
