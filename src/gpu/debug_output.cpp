#include "debug_output.h"

#include "ridge/core/error.h"

#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace ridge::gpu::detail {
namespace {

const char* sourceName(GLenum source)
{
    switch (source) {
    case GL_DEBUG_SOURCE_API:
        return "api";
    case GL_DEBUG_SOURCE_WINDOW_SYSTEM:
        return "window system";
    case GL_DEBUG_SOURCE_SHADER_COMPILER:
        return "shader compiler";
    case GL_DEBUG_SOURCE_THIRD_PARTY:
        return "third party";
    case GL_DEBUG_SOURCE_APPLICATION:
        return "application";
    default:
        return "other";
    }
}

const char* typeName(GLenum type)
{
    switch (type) {
    case GL_DEBUG_TYPE_ERROR:
        return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR:
        return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR:
        return "undefined behaviour";
    case GL_DEBUG_TYPE_PORTABILITY:
        return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE:
        return "performance";
    default:
        return "other";
    }
}

void GLAPIENTRY printDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity,
                                  GLsizei /*length*/, const GLchar* message, const void* /*user*/)
{
    const char* level = severity == GL_DEBUG_SEVERITY_HIGH ? "high" : "medium";
    std::fprintf(stderr, "[gl %s %s %s #%u] %s\n", level, sourceName(source), typeName(type), id,
                 message);
}

} // namespace

bool debugRequestedByEnv()
{
    const char* value = std::getenv("RIDGE_GL_DEBUG");
    return value != nullptr && std::strcmp(value, "1") == 0;
}

void installDebugOutput()
{
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(printDebugMessage, nullptr);
    // Everything off, then high and medium on: low and notification are mostly noise
    // (buffer placement hints and the like).
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_FALSE);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_HIGH, 0, nullptr, GL_TRUE);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_MEDIUM, 0, nullptr,
                          GL_TRUE);
}

void requireGl45Core(const char* what)
{
    GLint major = 0;
    GLint minor = 0;
    GLint profile = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    if (major * 10 + minor < 45 || (profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0) {
        const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
        throw Error(std::string(what) + ": got OpenGL " + (version ? version : "(unknown)") +
                    ", ridge needs 4.5 core");
    }
}

} // namespace ridge::gpu::detail
