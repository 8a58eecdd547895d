#pragma once
// The bitmap frame that validity masks and sample flags share (docs/FORMAT.md): after a kind
// byte, u32 frame_size, then exactly one zstd frame of frame_size bytes, stating its content
// size, whose content is a bitmap of `bits` bits, least significant bit of each byte first,
// the bits past the last 0. Internal to ridge_archive.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ridge::archive::detail {

// The kind byte of `kind`, then frame_size and the zstd frame of `planes` (each byte one bit,
// non-zero = 1, planes one after the other). Empty on a zstd failure.
std::vector<uint8_t> packBitmapFrame(uint8_t kind,
                                     const std::vector<const std::vector<uint8_t>*>& planes);

// Reads frame_size and the frame at data[1 ..) (data[0] is the kind byte the caller has read)
// within `size` bytes, checks it as stated above for `bits` bits and expands it into `planes`
// (resized by the caller: their sizes sum to `bits`), one byte 0/1 per bit. `what` names the
// mask in messages ("validity", "sample flags"); `bits_formula` says how `bits` is derived.
// Returns the problem, or empty with `consumed` = 1 + 4 + frame_size.
std::string unpackBitmapFrame(const uint8_t* data, size_t size, const char* what,
                              const char* bits_formula,
                              const std::vector<std::vector<uint8_t>*>& planes, size_t& consumed);

} // namespace ridge::archive::detail
