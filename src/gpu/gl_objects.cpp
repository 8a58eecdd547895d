#include "ridge/gpu/gl_objects.h"

#include "ridge/core/error.h"

#include <cstdio>
#include <string>

namespace ridge::gpu {
namespace {

const char* glErrorName(GLenum error)
{
    switch (error) {
    case GL_INVALID_ENUM:
        return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
        return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
        return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
        return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
        return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW:
        return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW:
        return "GL_STACK_OVERFLOW";
    default:
        return "unknown GL error";
    }
}

// glCreate* yields 0 only when the call itself failed (bad target, no context).
GLuint checkCreated(GLuint id, const char* what)
{
    if (id == 0) {
        checkGlError(what);
        throw Error(std::string(what) + " returned no object (is a GL context current?)");
    }
    return id;
}

} // namespace

void checkGlError(const char* where)
{
    GLenum first = glGetError();
    if (first == GL_NO_ERROR)
        return;
    std::string message = std::string("GL error at ") + where + ": " + glErrorName(first);
    char code[16];
    std::snprintf(code, sizeof code, " (0x%04x)", first);
    message += code;
    // GL may queue one error per kind; a bounded drain so the next check starts clean even if
    // the context is lost (where glGetError can keep returning an error).
    for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
    }
    throw Error(message);
}

namespace detail {

void deleteBuffer(GLuint id)
{
    glDeleteBuffers(1, &id);
}
void deleteTexture(GLuint id)
{
    glDeleteTextures(1, &id);
}
void deleteVertexArray(GLuint id)
{
    glDeleteVertexArrays(1, &id);
}
void deleteFramebuffer(GLuint id)
{
    glDeleteFramebuffers(1, &id);
}
void deleteRenderbuffer(GLuint id)
{
    glDeleteRenderbuffers(1, &id);
}
void deleteQuery(GLuint id)
{
    glDeleteQueries(1, &id);
}
void deleteTransformFeedback(GLuint id)
{
    glDeleteTransformFeedbacks(1, &id);
}

} // namespace detail

namespace {

template <typename Create> GLuint createName(Create create, const char* what)
{
    GLuint id = 0;
    create(&id);
    return checkCreated(id, what);
}

} // namespace

GlBuffer::GlBuffer()
    : GlName(createName([](GLuint* id) { glCreateBuffers(1, id); }, "glCreateBuffers"))
{
}

GlTexture::GlTexture(GLenum target)
    : GlName(
          createName([target](GLuint* id) { glCreateTextures(target, 1, id); }, "glCreateTextures"))
{
}

GlVertexArray::GlVertexArray()
    : GlName(createName([](GLuint* id) { glCreateVertexArrays(1, id); }, "glCreateVertexArrays"))
{
}

GlFramebuffer::GlFramebuffer()
    : GlName(createName([](GLuint* id) { glCreateFramebuffers(1, id); }, "glCreateFramebuffers"))
{
}

GlRenderbuffer::GlRenderbuffer()
    : GlName(createName([](GLuint* id) { glCreateRenderbuffers(1, id); }, "glCreateRenderbuffers"))
{
}

GlQuery::GlQuery(GLenum target)
    : GlName(
          createName([target](GLuint* id) { glCreateQueries(target, 1, id); }, "glCreateQueries"))
{
}

GlTransformFeedback::GlTransformFeedback()
    : GlName(createName([](GLuint* id) { glCreateTransformFeedbacks(1, id); },
                        "glCreateTransformFeedbacks"))
{
}

} // namespace ridge::gpu
