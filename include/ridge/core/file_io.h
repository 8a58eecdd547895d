#pragma once
// Whole reads and writes on a file descriptor: short counts and EINTR retried, failures
// thrown as ridge::Error("WHAT: cannot write: REASON") / ("WHAT: cannot read N bytes at O:
// REASON"). The one loop every writer of raw files (GDAL side-cars, PMTiles, tile
// directories) shares.
#include <cstddef>
#include <cstdint>
#include <string>

namespace ridge {

// Writes `size` bytes at the descriptor's position.
void writeAll(int fd, const void* data, size_t size, const std::string& what);
// Writes `size` bytes at `offset` (pwrite), the position unchanged.
void writeAllAt(int fd, const void* data, size_t size, uint64_t offset, const std::string& what);
// Reads `size` bytes at `offset` (pread); the file ending first is an error.
void readAllAt(int fd, void* data, size_t size, uint64_t offset, const std::string& what);

// FNV-1a, 64 bits, of `size` bytes: a fast hash for cache keys, versions and deduplication
// (callers that must not confuse two inputs compare the bytes too). Not a checksum.
uint64_t fnv1a64(const void* data, size_t size);

} // namespace ridge
