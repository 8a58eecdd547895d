#pragma once
// A shader storage buffer of per-frame records (internal to ridge_render): the instance records
// every terrain program reads, and a scheme's own per-instance records (rings' tiles, clipmaps'
// pieces). Rewritten every frame; its storage is reallocated only when a frame needs more than
// it holds (room for at least 256 records), never shrunk.
#include "ridge/gpu/gl_objects.h"

#include <algorithm>
#include <cstddef>
#include <vector>

namespace ridge::render {

template <class Record> class RecordBuffer {
  public:
    // Sends `records`; returns the bytes sent.
    size_t upload(const std::vector<Record>& records)
    {
        const size_t bytes = std::max<size_t>(records.size(), 1) * sizeof(Record);
        if (bytes > capacity_) {
            buffer_ = gpu::GlBuffer();
            capacity_ = std::max(bytes, size_t(256) * sizeof(Record));
            glNamedBufferStorage(buffer_.id(), GLsizeiptr(capacity_), nullptr,
                                 GL_DYNAMIC_STORAGE_BIT);
        }
        if (!records.empty())
            glNamedBufferSubData(buffer_.id(), 0, GLsizeiptr(records.size() * sizeof(Record)),
                                 records.data());
        return records.size() * sizeof(Record);
    }
    // Binds the buffer to shader storage binding `index`.
    void bind(GLuint index) const
    {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, index, buffer_.id());
    }

  private:
    gpu::GlBuffer buffer_;
    size_t capacity_ = 0; // bytes
};

} // namespace ridge::render
