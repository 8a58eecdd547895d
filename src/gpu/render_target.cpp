#include "ridge/gpu/render_target.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace ridge::gpu {
namespace {

GLint glInteger(GLenum name)
{
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

const char* framebufferStatusName(GLenum status)
{
    switch (status) {
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT:
        return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT:
        return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_UNSUPPORTED:
        return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE:
        return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    default:
        return "status";
    }
}

// Within GL_MAX_TEXTURE_SIZE and GL_MAX_RENDERBUFFER_SIZE a target can still be too large
// for the implementation to allocate (llvmpipe refuses a 16384 x 16384 target with 4 samples,
// 8 GiB of colour and depth): the attachment is then incomplete, and the message says so in
// those terms rather than as a GL status code alone.
void requireComplete(GLuint fbo, const char* what, int width, int height, int samples)
{
    const GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        checkGlError(what);
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", status);
        const double gib = double(width) * height * samples * 8.0 / (1024.0 * 1024.0 * 1024.0);
        char size[64];
        std::snprintf(size, sizeof size, "%.2g GiB", gib);
        throw Error("a " + std::to_string(width) + "x" + std::to_string(height) +
                    " render target with " + std::to_string(samples) + " sample(s) per pixel (" +
                    size + " of colour and depth) cannot be allocated by this GL implementation (" +
                    what + " framebuffer incomplete: " + framebufferStatusName(status) + ", " +
                    code + "): use fewer samples or a smaller size");
    }
}

// Reverses the row order of `rows` rows of `row_size` elements each, in place.
template <typename T> void flipRows(std::vector<T>& pixels, std::size_t row_size, std::size_t rows)
{
    for (std::size_t top = 0, bottom = rows - 1; top < bottom; ++top, --bottom)
        std::swap_ranges(pixels.begin() + top * row_size, pixels.begin() + (top + 1) * row_size,
                         pixels.begin() + bottom * row_size);
}

} // namespace

RenderTarget::RenderTarget(int width, int height, int samples)
    : width_(width), height_(height), samples_(samples)
{
    const GLint max_size =
        std::min(glInteger(GL_MAX_TEXTURE_SIZE), glInteger(GL_MAX_RENDERBUFFER_SIZE));
    if (width <= 0 || height <= 0 || width > max_size || height > max_size)
        throw Error(
            "render target size " + std::to_string(width) + "x" + std::to_string(height) +
            " is outside 1.." + std::to_string(max_size) +
            " (GL_MAX_TEXTURE_SIZE and GL_MAX_RENDERBUFFER_SIZE of this GL implementation)");
    const GLint max_samples = glInteger(GL_MAX_SAMPLES);
    if (samples < 1 || samples > max_samples)
        throw Error("render target sample count " + std::to_string(samples) + " is outside 1.." +
                    std::to_string(max_samples));

    glTextureStorage2D(colour_.id(), 1, GL_RGBA8, width, height);
    glTextureStorage2D(depth_.id(), 1, GL_DEPTH_COMPONENT32F, width, height);
    glNamedFramebufferTexture(resolved_fbo_.id(), GL_COLOR_ATTACHMENT0, colour_.id(), 0);
    glNamedFramebufferTexture(resolved_fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
    checkGlError("RenderTarget storage");
    requireComplete(resolved_fbo_.id(), "RenderTarget", width, height, 1);

    if (samples > 1) {
        glNamedRenderbufferStorageMultisample(msaa_colour_.id(), samples, GL_RGBA8, width, height);
        glNamedRenderbufferStorageMultisample(msaa_depth_.id(), samples, GL_DEPTH_COMPONENT32F,
                                              width, height);
        glNamedFramebufferRenderbuffer(msaa_fbo_.id(), GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                       msaa_colour_.id());
        glNamedFramebufferRenderbuffer(msaa_fbo_.id(), GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                       msaa_depth_.id());
        checkGlError("RenderTarget multisampled storage");
        requireComplete(msaa_fbo_.id(), "RenderTarget multisampled", width, height, samples);
    }
}

GLuint RenderTarget::framebuffer() const
{
    return samples_ > 1 ? msaa_fbo_.id() : resolved_fbo_.id();
}

void RenderTarget::bind() const
{
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer());
    glViewport(0, 0, width_, height_);
}

void RenderTarget::resolve(GLbitfield mask) const
{
    if (samples_ == 1)
        return;
    // NEAREST: required for depth, and exact for colour at equal sizes (a plain resolve).
    glBlitNamedFramebuffer(msaa_fbo_.id(), resolved_fbo_.id(), 0, 0, width_, height_, 0, 0, width_,
                           height_, mask, GL_NEAREST);
    checkGlError("RenderTarget resolve");
}

std::vector<uint8_t> RenderTarget::readRgba() const
{
    resolve(GL_COLOR_BUFFER_BIT);
    const std::size_t row = static_cast<std::size_t>(width_) * 4;
    std::vector<uint8_t> pixels(row * static_cast<std::size_t>(height_));
    // Rows of 4-byte pixels are always 4-aligned, the default GL_PACK_ALIGNMENT.
    glGetTextureImage(colour_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE,
                      static_cast<GLsizei>(pixels.size()), pixels.data());
    checkGlError("RenderTarget::readRgba");
    flipRows(pixels, row, static_cast<std::size_t>(height_));
    return pixels;
}

std::vector<float> RenderTarget::readDepth() const
{
    resolve(GL_DEPTH_BUFFER_BIT);
    const auto row = static_cast<std::size_t>(width_);
    std::vector<float> depths(row * static_cast<std::size_t>(height_));
    glGetTextureImage(depth_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      static_cast<GLsizei>(depths.size() * sizeof(float)), depths.data());
    checkGlError("RenderTarget::readDepth");
    flipRows(depths, row, static_cast<std::size_t>(height_));
    return depths;
}

} // namespace ridge::gpu
