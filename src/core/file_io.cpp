#include "ridge/core/file_io.h"

#include "ridge/core/error.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ridge {

void writeAll(int fd, const void* data, size_t size, const std::string& what)
{
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            throw Error(what + ": cannot write: " + std::strerror(n < 0 ? errno : EIO));
        p += n;
        size -= size_t(n);
    }
}

void writeAllAt(int fd, const void* data, size_t size, uint64_t offset, const std::string& what)
{
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        const ssize_t n = ::pwrite(fd, p, size, off_t(offset));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            throw Error(what + ": cannot write: " + std::strerror(n < 0 ? errno : EIO));
        p += n;
        size -= size_t(n);
        offset += uint64_t(n);
    }
}

void readAllAt(int fd, void* data, size_t size, uint64_t offset, const std::string& what)
{
    char* p = static_cast<char*>(data);
    while (size > 0) {
        const ssize_t n = ::pread(fd, p, size, off_t(offset));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            throw Error(
                what + ": cannot read " + std::to_string(size) + " bytes at " +
                std::to_string(offset) +
                (n < 0 ? std::string(": ") + std::strerror(errno) : std::string(": past its end")));
        p += n;
        size -= size_t(n);
        offset += uint64_t(n);
    }
}

uint64_t fnv1a64(const void* data, size_t size)
{
    const auto* p = static_cast<const unsigned char*>(data);
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < size; ++i)
        h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

} // namespace ridge
