#include "ridge/core/crc32.h"

#include <zlib.h>

namespace ridge {

// zlib's crc32 is a well-tested, table-driven (braided) implementation; documented in
// FORMAT.md as the standard CRC-32 so that readers in any language can check it.
uint32_t crc32(const void* data, size_t size, uint32_t crc)
{
    const auto* p = static_cast<const Bytef*>(data);
    while (size > 0) {
        uInt chunk = size > 0x40000000u ? 0x40000000u : static_cast<uInt>(size);
        crc = static_cast<uint32_t>(::crc32(crc, p, chunk));
        p += chunk;
        size -= chunk;
    }
    return crc;
}

} // namespace ridge
