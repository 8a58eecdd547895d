#include "gpu_fractal_decoder.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge::render {
namespace {

int paddedSide(int n)
{
    return (n + 3) / 4 * 4; // fractal::Partition::of(n).side
}

} // namespace

GpuFractalDecoder::GpuFractalDecoder(int patch_size, int slots)
    : n_(patch_size), m_(paddedSide(patch_size)), ranges_(m_ / 4),
      program_({{GL_COMPUTE_SHADER, "fractal_iterate.comp"}}), steps_(size_t(slots), 0),
      full_steps_(size_t(slots), 0), step_unit_(size_t(slots), 1), pinned_(size_t(slots), 1)
{
    const auto ints = [](size_t count) { return GLsizeiptr(count * sizeof(int32_t)); };
    const size_t s = size_t(slots);
    glNamedBufferStorage(state_.id(), ints(s * size_t(m_) * m_), nullptr, 0);
    glNamedBufferStorage(transforms_.id(), ints(s * size_t(ranges_) * ranges_ * 4), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(samples_.id(), ints(s * size_t(n_) * n_), nullptr, GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferStorage(scratch_.id(), ints(size_t(m_) * m_), nullptr, 0);
    gpu::checkGlError("fractal decoder: buffers");
}

double GpuFractalDecoder::bytesPerSlot(int patch_size)
{
    const double m = paddedSide(patch_size), r = m / 4, n = patch_size;
    return 4.0 * (m * m + 4.0 * r * r + n * n);
}

void GpuFractalDecoder::decode(const GpuPayload& payload, const Target& t, int steps)
{
    const auto& f = static_cast<const FractalPayload&>(payload);
    const size_t slot = size_t(t.layer);
    const size_t transform_ints = size_t(ranges_) * ranges_ * 4, sample_ints = size_t(n_) * n_;
    if (f.transforms.size() != transform_ints || f.samples.size() != sample_ints)
        throw Error("internal error: a fractal payload of another patch size");
    glNamedBufferSubData(transforms_.id(), GLintptr(slot * transform_ints * sizeof(int32_t)),
                         GLsizeiptr(transform_ints * sizeof(int32_t)), f.transforms.data());
    glNamedBufferSubData(samples_.id(), GLintptr(slot * sample_ints * sizeof(int32_t)),
                         GLsizeiptr(sample_ints * sizeof(int32_t)), f.samples.data());
    full_steps_[slot] = f.iterations;
    step_unit_[slot] = f.step;
    pinned_[slot] = f.pinned ? 1 : 0;
    steps_[slot] = 0;
    iterate(t, -1, std::clamp(steps, 0, f.iterations));
}

void GpuFractalDecoder::refine(const Target& t, int steps)
{
    const size_t slot = size_t(t.layer);
    const int to = std::clamp(steps, 0, full_steps_[slot]);
    if (to > steps_[slot])
        iterate(t, steps_[slot], to);
}

// Iterations from+1..to on the slot's state (from = −1: the start image first), then its codes.
void GpuFractalDecoder::iterate(const Target& t, int from, int to)
{
    const size_t slot = size_t(t.layer);
    program_.use();
    glUniform1i(program_.uniform("u_n"), n_);
    glUniform1i(program_.uniform("u_m"), m_);
    glUniform1i(program_.uniform("u_ranges"), ranges_);
    glUniform1i(program_.uniform("u_slot"), t.layer);
    glUniform1i(program_.uniform("u_layer"), t.layer);
    glUniform1i(program_.uniform("u_pinned"), pinned_[slot]);
    glUniform1i(program_.uniform("u_step"), step_unit_[slot]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, state_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, transforms_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, samples_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, scratch_.id());
    glBindImageTexture(5, t.heights, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R16UI);
    const auto pass = [&](int which, int side) {
        glUniform1i(program_.uniform("u_pass"), which);
        glDispatchCompute(GLuint(side + 7) / 8, GLuint(side + 7) / 8, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    };
    if (from < 0) {
        pass(0, m_);
        from = 0;
    }
    for (int i = from; i < to; ++i) {
        pass(1, m_);
        pass(2, m_);
    }
    pass(3, n_);
    steps_[slot] = to;
    gpu::checkGlError("fractal decoder: iterate");
}

GpuDecoderInfo fractalGpuDecoder()
{
    return {
        .codec = "fractal",
        .make = [](const HeightCodec& codec, int patch_size,
                   int slots) -> std::unique_ptr<GpuPatchDecoder> {
            if (!dynamic_cast<const FractalCodec*>(&codec))
                throw Error("internal error: the fractal GPU decoder given another codec");
            return std::make_unique<GpuFractalDecoder>(patch_size, slots);
        },
        .bytes_per_slot = &GpuFractalDecoder::bytesPerSlot,
    };
}

} // namespace ridge::render
