#include "ridge/core/atomic_output.h"

#include "ridge/core/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <unistd.h>

namespace ridge {

AtomicOutput::AtomicOutput(std::string final_path)
    : final_path_(std::move(final_path)),
      temp_path_(final_path_ + ".tmp." + std::to_string(::getpid()))
{
}

AtomicOutput::~AtomicOutput()
{
    if (!committed_)
        std::remove(temp_path_.c_str());
}

void AtomicOutput::commit()
{
    // fsync before rename so that a crash after the rename cannot expose an empty file.
    int fd = ::open(temp_path_.c_str(), O_RDONLY);
    if (fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
    if (std::rename(temp_path_.c_str(), final_path_.c_str()) != 0)
        throw Error(final_path_ + ": cannot create output: " + std::strerror(errno));
    committed_ = true;
}

void checkOutputWritable(const std::string& path)
{
    const std::string probe = path + ".tmp.check." + std::to_string(::getpid());
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0)
        throw Error(path + ": cannot write: " + std::strerror(errno));
    ::close(fd);
    std::remove(probe.c_str());
}

void writeFileAtomically(const std::string& path, const std::string& text)
{
    AtomicOutput output(path);
    {
        std::ofstream out(output.temporaryPath(), std::ios::binary);
        out << text;
        out.flush();
        if (!out)
            throw Error(path + ": cannot write");
    }
    output.commit();
}

} // namespace ridge
