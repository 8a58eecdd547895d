#pragma once
// Move-only RAII owners of one GL object name each, created with direct state access
// (glCreate*), so that a new object is fully initialised without binding it.
//
// Contract for all of them: a GL context must be current when one is constructed or destroyed,
// and it must be the context (or share group) the object was created in. A moved-from object
// owns nothing and has id() 0. Not thread-safe (GL contexts are per thread).
#include <epoxy/gl.h>

#include <utility>

namespace ridge::gpu {

// Throws ridge::Error naming `where` and the GL error (e.g. "GL_INVALID_OPERATION") when
// glGetError reports one; drains all queued errors first so that the next check starts clean.
void checkGlError(const char* where);

namespace detail {

// Owns one name; `Delete` frees it. Name 0 (moved-from) is never passed to GL, so an empty
// object may be destroyed without a current context.
template <void (*Delete)(GLuint)> class GlName {
  public:
    GLuint id() const { return id_; }

    GlName(const GlName&) = delete;
    GlName& operator=(const GlName&) = delete;
    GlName(GlName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    GlName& operator=(GlName&& other) noexcept
    {
        if (this != &other) {
            release();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }

  protected:
    explicit GlName(GLuint id) : id_(id) {}
    ~GlName() { release(); }

  private:
    void release()
    {
        if (id_ != 0)
            Delete(id_);
    }

    GLuint id_ = 0;
};

void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteVertexArray(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteRenderbuffer(GLuint id);
void deleteQuery(GLuint id);
void deleteTransformFeedback(GLuint id);

} // namespace detail

// A buffer object with no storage yet (use glNamedBufferStorage/glNamedBufferData).
class GlBuffer : public detail::GlName<&detail::deleteBuffer> {
  public:
    GlBuffer();
};

// A texture whose target (GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY, ...) is fixed at creation.
class GlTexture : public detail::GlName<&detail::deleteTexture> {
  public:
    explicit GlTexture(GLenum target);
};

class GlVertexArray : public detail::GlName<&detail::deleteVertexArray> {
  public:
    GlVertexArray();
};

class GlFramebuffer : public detail::GlName<&detail::deleteFramebuffer> {
  public:
    GlFramebuffer();
};

// A renderbuffer (multisampled render targets).
class GlRenderbuffer : public detail::GlName<&detail::deleteRenderbuffer> {
  public:
    GlRenderbuffer();
};

// A query object of `target` (GL_TIME_ELAPSED, GL_SAMPLES_PASSED, GL_PRIMITIVES_GENERATED...).
class GlQuery : public detail::GlName<&detail::deleteQuery> {
  public:
    explicit GlQuery(GLenum target);
};

class GlTransformFeedback : public detail::GlName<&detail::deleteTransformFeedback> {
  public:
    GlTransformFeedback();
};

} // namespace ridge::gpu
