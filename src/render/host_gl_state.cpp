#include "ridge/render/host_gl_state.h"

#include "ridge/core/error.h"
#include "ridge/gpu/gl_objects.h" // GL through libepoxy

#include <array>
#include <cstdio>
#include <string>

namespace ridge::render {
namespace {

// The texture units, image units and buffer binding points ridge's renderer uses
// (patch_textures.cpp, the schemes, the GPU decoders, capture): texture units up to 11 (the
// water maps on 6, the projected lattice's on 9 and 10, clipmaps' level windows on 11), image
// units up to 5 (the fractal decoder's heights), storage bindings up to 4 (the shading map,
// the fractal decoder's scratch).
constexpr int kTextureUnits = 12;
constexpr int kImageUnits = 6;
constexpr int kStorageBindings = 5;
constexpr GLenum kTextureTargets[] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_2D_ARRAY};
constexpr GLenum kTextureBindings[] = {GL_TEXTURE_BINDING_1D, GL_TEXTURE_BINDING_2D,
                                       GL_TEXTURE_BINDING_2D_ARRAY};
// Unpacking parameters ridge's uploads assume at GL's defaults (0, false); alignment is set
// by each upload and saved with them.
constexpr GLenum kUnpackParameters[] = {
    GL_UNPACK_ROW_LENGTH,  GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_ROWS,
    GL_UNPACK_SKIP_IMAGES, GL_UNPACK_SWAP_BYTES,   GL_UNPACK_LSB_FIRST};
constexpr GLenum kSwitches[] = {
    GL_DEPTH_TEST,          GL_CULL_FACE,           GL_BLEND,
    GL_RASTERIZER_DISCARD,  GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,
    GL_POLYGON_OFFSET_POINT};
// Switched off while ridge works (it enables what it needs itself).
constexpr GLenum kOffWhileRidgeWorks[] = {GL_CULL_FACE,           GL_BLEND,
                                          GL_RASTERIZER_DISCARD,  GL_POLYGON_OFFSET_FILL,
                                          GL_POLYGON_OFFSET_LINE, GL_POLYGON_OFFSET_POINT};

GLint integer(GLenum name)
{
    GLint v = 0;
    glGetIntegerv(name, &v);
    return v;
}

GLint integerAt(GLenum name, GLuint index)
{
    GLint v = 0;
    glGetIntegeri_v(name, index, &v);
    return v;
}

GLint64 integer64At(GLenum name, GLuint index)
{
    GLint64 v = 0;
    glGetInteger64i_v(name, index, &v);
    return v;
}

struct BufferBinding {
    GLint buffer = 0;
    GLint64 start = 0, size = 0; // size 0: bound whole (glBindBufferBase)
};

BufferBinding bufferBinding(GLenum binding, GLenum start, GLenum size, GLuint index)
{
    return {integerAt(binding, index), integer64At(start, index), integer64At(size, index)};
}

void restoreBuffer(GLenum target, GLuint index, const BufferBinding& b)
{
    if (b.buffer != 0 && b.size > 0)
        glBindBufferRange(target, index, GLuint(b.buffer), GLintptr(b.start), GLsizeiptr(b.size));
    else
        glBindBufferBase(target, index, GLuint(b.buffer));
}

struct ImageBinding {
    GLint texture = 0, level = 0, layered = 0, layer = 0, access = GL_READ_ONLY, format = GL_R8;
};

} // namespace

struct HostGlState::Saved {
    GLint clip_origin = 0, clip_depth_mode = 0;
    std::array<GLboolean, std::size(kSwitches)> switches{};
    GLint depth_func = 0;
    GLboolean depth_mask = GL_TRUE;
    GLdouble depth_clear = 1.0;
    std::array<GLfloat, 4> colour_clear{};
    std::array<GLint, 2> polygon_mode{GL_FILL, GL_FILL};
    GLfloat offset_factor = 0.f, offset_units = 0.f;
    GLint patch_vertices = 3;
    GLint program = 0, vertex_array = 0, active_texture = GL_TEXTURE0;
    std::array<std::array<GLint, std::size(kTextureTargets)>, kTextureUnits> textures{};
    std::array<GLint, kTextureUnits> samplers{};
    std::array<ImageBinding, kImageUnits> images{};
    std::array<BufferBinding, kStorageBindings> storage{};
    GLint storage_generic = 0;
    BufferBinding feedback;
    GLint feedback_generic = 0;
    GLint pack_buffer = 0, unpack_buffer = 0, pack_alignment = 4, unpack_alignment = 4;
    std::array<GLint, std::size(kUnpackParameters)> unpack{};
};

HostGlState::HostGlState(const char* where) : saved_(std::make_unique<Saved>())
{
    if (const GLenum pending = glGetError(); pending != GL_NO_ERROR) {
        for (int i = 0; i < 16 && glGetError() != GL_NO_ERROR; ++i) {
        }
        char code[16];
        std::snprintf(code, sizeof code, "0x%04x", pending);
        throw Error(std::string(where) + ": a GL error (" + code +
                    ") was pending before ridge's call: the host's own GL call raised it "
                    "(check glGetError() before calling ridge)");
    }
    Saved& s = *saved_;
    // Save everything first.
    s.clip_origin = integer(GL_CLIP_ORIGIN);
    s.clip_depth_mode = integer(GL_CLIP_DEPTH_MODE);
    for (size_t k = 0; k < std::size(kSwitches); ++k)
        s.switches[k] = glIsEnabled(kSwitches[k]);
    s.depth_func = integer(GL_DEPTH_FUNC);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depth_mask);
    glGetDoublev(GL_DEPTH_CLEAR_VALUE, &s.depth_clear);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s.colour_clear.data());
    glGetIntegerv(GL_POLYGON_MODE, s.polygon_mode.data()); // one value in core, two before
    glGetFloatv(GL_POLYGON_OFFSET_FACTOR, &s.offset_factor);
    glGetFloatv(GL_POLYGON_OFFSET_UNITS, &s.offset_units);
    s.patch_vertices = integer(GL_PATCH_VERTICES);
    s.program = integer(GL_CURRENT_PROGRAM);
    s.vertex_array = integer(GL_VERTEX_ARRAY_BINDING);
    s.active_texture = integer(GL_ACTIVE_TEXTURE);
    for (int unit = 0; unit < kTextureUnits; ++unit) {
        glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        for (size_t t = 0; t < std::size(kTextureBindings); ++t)
            s.textures[size_t(unit)][t] = integer(kTextureBindings[t]);
        s.samplers[size_t(unit)] = integer(GL_SAMPLER_BINDING);
    }
    for (GLuint i = 0; i < GLuint(kImageUnits); ++i) {
        ImageBinding& b = s.images[i];
        b.texture = integerAt(GL_IMAGE_BINDING_NAME, i);
        b.level = integerAt(GL_IMAGE_BINDING_LEVEL, i);
        b.layered = integerAt(GL_IMAGE_BINDING_LAYERED, i);
        b.layer = integerAt(GL_IMAGE_BINDING_LAYER, i);
        b.access = integerAt(GL_IMAGE_BINDING_ACCESS, i);
        b.format = integerAt(GL_IMAGE_BINDING_FORMAT, i);
    }
    for (GLuint i = 0; i < GLuint(kStorageBindings); ++i)
        s.storage[i] =
            bufferBinding(GL_SHADER_STORAGE_BUFFER_BINDING, GL_SHADER_STORAGE_BUFFER_START,
                          GL_SHADER_STORAGE_BUFFER_SIZE, i);
    s.storage_generic = integer(GL_SHADER_STORAGE_BUFFER_BINDING);
    s.feedback =
        bufferBinding(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING, GL_TRANSFORM_FEEDBACK_BUFFER_START,
                      GL_TRANSFORM_FEEDBACK_BUFFER_SIZE, 0);
    s.feedback_generic = integer(GL_TRANSFORM_FEEDBACK_BUFFER_BINDING);
    s.pack_buffer = integer(GL_PIXEL_PACK_BUFFER_BINDING);
    s.unpack_buffer = integer(GL_PIXEL_UNPACK_BUFFER_BINDING);
    s.pack_alignment = integer(GL_PACK_ALIGNMENT);
    s.unpack_alignment = integer(GL_UNPACK_ALIGNMENT);
    for (size_t k = 0; k < std::size(kUnpackParameters); ++k)
        s.unpack[k] = integer(kUnpackParameters[k]);

    // Then the state ridge's code assumes.
    for (GLenum cap : kOffWhileRidgeWorks)
        glDisable(cap);
    // A sampler object overrides a texture's own filtering: a linear one on ridge's integer
    // height arrays would leave them incomplete (sampled as 0).
    for (int unit = 0; unit < kTextureUnits; ++unit)
        glBindSampler(GLuint(unit), 0);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    for (GLenum p : kUnpackParameters)
        glPixelStorei(p, 0);
    gpu::checkGlError("saving the host's GL state");
}

HostGlState::~HostGlState()
{
    const Saved& s = *saved_;
    glClipControl(GLenum(s.clip_origin), GLenum(s.clip_depth_mode));
    for (size_t k = 0; k < std::size(kSwitches); ++k)
        (s.switches[k] ? glEnable : glDisable)(kSwitches[k]);
    glDepthFunc(GLenum(s.depth_func));
    glDepthMask(s.depth_mask);
    glClearDepth(s.depth_clear);
    glClearColor(s.colour_clear[0], s.colour_clear[1], s.colour_clear[2], s.colour_clear[3]);
    glPolygonMode(GL_FRONT_AND_BACK, GLenum(s.polygon_mode[0]));
    glPolygonOffset(s.offset_factor, s.offset_units);
    glPatchParameteri(GL_PATCH_VERTICES, s.patch_vertices);
    // A program the host deleted while it was current lived on only until ridge switched
    // programs: there is none to go back to.
    glUseProgram(glIsProgram(GLuint(s.program)) ? GLuint(s.program) : 0);
    glBindVertexArray(GLuint(s.vertex_array));
    for (int unit = 0; unit < kTextureUnits; ++unit) {
        glActiveTexture(GLenum(GL_TEXTURE0 + unit));
        for (size_t t = 0; t < std::size(kTextureTargets); ++t)
            glBindTexture(kTextureTargets[t], GLuint(s.textures[size_t(unit)][t]));
        glBindSampler(GLuint(unit), GLuint(s.samplers[size_t(unit)]));
    }
    glActiveTexture(GLenum(s.active_texture));
    for (GLuint i = 0; i < GLuint(kImageUnits); ++i) {
        const ImageBinding& b = s.images[i];
        glBindImageTexture(i, GLuint(b.texture), b.level, GLboolean(b.layered), b.layer,
                           GLenum(b.access), GLenum(b.format));
    }
    for (GLuint i = 0; i < GLuint(kStorageBindings); ++i)
        restoreBuffer(GL_SHADER_STORAGE_BUFFER, i, s.storage[i]);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, GLuint(s.storage_generic));
    restoreBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, 0, s.feedback);
    glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, GLuint(s.feedback_generic));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, GLuint(s.pack_buffer));
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, GLuint(s.unpack_buffer));
    glPixelStorei(GL_PACK_ALIGNMENT, s.pack_alignment);
    glPixelStorei(GL_UNPACK_ALIGNMENT, s.unpack_alignment);
    for (size_t k = 0; k < std::size(kUnpackParameters); ++k)
        glPixelStorei(kUnpackParameters[k], s.unpack[k]);
    // A destructor cannot throw: a failed restore (a lost context) is left to the host's own
    // glGetError.
}

} // namespace ridge::render
