#pragma once
#include <cstddef>
#include <cstdint>

namespace ridge {

// CRC-32 (ISO-HDLC / zlib / PNG polynomial 0xEDB88320, init and final xor 0xFFFFFFFF).
// crc32(data, n) of an empty buffer is 0; pass a previous result as `crc` to continue.
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

} // namespace ridge
