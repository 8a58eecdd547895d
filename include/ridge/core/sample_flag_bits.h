#pragma once
// The bits of a sample's flags byte (docs/FORMAT.md, "Sample flags"; pyramid/sample_flags.h
// has the per-patch and per-level types). In core so that ingest (io) can set them.
#include <cstdint>

namespace ridge {

inline constexpr uint8_t kSampleWater = 1;  // water (sea, lake, river) at this sample
inline constexpr uint8_t kSampleFilled = 2; // a void of the source, its height invented
inline constexpr uint8_t kSampleFlagBits = kSampleWater | kSampleFilled;

} // namespace ridge
