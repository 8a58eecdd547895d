#pragma once
// Context-coded bit planes (docs/FORMAT.md, "Sample flags", kind 3): the bitmaps of a patch's
// sample flags coded bit by bit with the adaptive binary range coder of codec/range_coder.h,
// each bit's probability learned per context, the context being the ten bits of the same
// plane around it that are already coded (the template of JBIG's three-line mode: two to the
// west, five in the row above, three two rows above), and for every plane after the first
// the bit of the first plane at the same sample (water predicts filled). Bits outside the
// patch read as 0. A coastline costs a few bits per sample on it and almost nothing
// elsewhere: about 0.4× the zstd frame of kind 2 on the coasts and voids of the test DEMs
// (docs/PERF.md). Internal to ridge_archive.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge::archive::detail {

// The range-coded stream of `planes` (each n·n bytes, non-zero = 1, row-major), plane after
// plane.
std::vector<uint8_t> encodeContextBitmap(const std::vector<const std::vector<uint8_t>*>& planes,
                                         int n);

// Decodes exactly `size` bytes into `planes` (each resized to n·n, 0/1 bytes). False when
// the stream is not one encodeContextBitmap wrote for that many planes of n·n bits: it ends
// early, leaves bytes unread or leaves the coder's range.
bool decodeContextBitmap(const uint8_t* data, size_t size, int n,
                         const std::vector<std::vector<uint8_t>*>& planes);

} // namespace ridge::archive::detail
