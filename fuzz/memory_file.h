#pragma once
// A file in memory (memfd) for fuzz targets whose code under test reads a path: no disk I/O,
// and no predictable name in /tmp that a symlink could be planted at.
#include <cstdint>
#include <string>
#include <sys/mman.h>
#include <unistd.h>
#include <vector>

namespace ridge::fuzz {

class MemoryFile {
  public:
    MemoryFile() : fd_(::memfd_create("ridge-fuzz", MFD_CLOEXEC))
    {
        if (fd_ < 0)
            __builtin_trap();
        path_ = "/proc/self/fd/" + std::to_string(fd_);
    }
    MemoryFile(const MemoryFile&) = delete;
    MemoryFile& operator=(const MemoryFile&) = delete;

    // Replaces the content with `size` bytes of `data`.
    void write(const uint8_t* data, size_t size) const
    {
        if (::ftruncate(fd_, 0) != 0 || ::pwrite(fd_, data, size, 0) != ssize_t(size))
            __builtin_trap();
    }
    // A path that opens this file (the descriptor's magic link).
    const std::string& path() const { return path_; }

  private:
    int fd_;
    std::string path_;
};

} // namespace ridge::fuzz
