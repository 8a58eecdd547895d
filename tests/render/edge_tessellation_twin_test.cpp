// The tessellation control shader and ridge::lod pick the same simplification d for the same
// edge: the GLSL twin of src/lod/edge_tessellation.cpp is checked against it on the GPU.
#include "ridge/gpu/context.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/shader_program.h"
#include "ridge/lod/edge_tessellation.h"

#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>

#include <random>

using namespace ridge;

TEST(EdgeTessellationTwin, ShaderAndCppPickTheSameSimplificationForRandomEdges)
{
    auto context = gpu::HeadlessContext::create();
    const gpu::ShaderProgram program({{GL_COMPUTE_SHADER, "test/edge_tessellation_twin.comp"}});
    const lod::Viewport vp{1280, 720};
    const lod::Camera camera({0, 0, 0}, {0.3, 1.0, -0.4}, 55.0, vp, 0.5, 1e5);
    const glm::dmat4 vp_matrix = camera.viewProjection();
    const double epsilon = 2.0;
    const int levels = 3;

    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int count = 4096;
    std::vector<glm::vec4> cases;
    std::vector<lod::EdgeErrors> errors(count);
    std::vector<glm::dvec3> centres(count);
    for (int i = 0; i < count; ++i) {
        // Ahead of the camera, 5 m to 20 km away; Λ^(d) increasing with d as real blocks do.
        const double dist = 5.0 * std::pow(4000.0, u(rng));
        centres[i] =
            glm::normalize(glm::dvec3(u(rng) - 0.5, 1.0, -0.4 + 0.6 * (u(rng) - 0.5))) * dist;
        float lambda = float(0.05 * std::pow(400.0, u(rng)));
        for (int d = 0; d < lod::kMaxBlockLevels; ++d) {
            errors[i].lambda[d] = lambda;
            lambda *= float(1.0 + 3.0 * u(rng));
        }
        cases.push_back(glm::vec4(glm::vec3(centres[i]), 0.f));
        cases.push_back(glm::vec4(errors[i].lambda[0], errors[i].lambda[1], errors[i].lambda[2],
                                  errors[i].lambda[3]));
    }
    gpu::GlBuffer in, out;
    glNamedBufferStorage(in.id(), GLsizeiptr(cases.size() * sizeof(glm::vec4)), cases.data(), 0);
    glNamedBufferStorage(out.id(), GLsizeiptr(count * sizeof(int32_t)), nullptr, 0);
    program.use();
    const glm::mat4 m(vp_matrix);
    glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(m));
    glUniform2f(program.uniform("u_viewport"), float(vp.width), float(vp.height));
    glUniform1f(program.uniform("u_epsilon"), float(epsilon));
    glUniform1i(program.uniform("u_block_levels"), levels);
    glUniform1i(program.uniform("u_case_count"), count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, out.id());
    glDispatchCompute((count + 63) / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<int32_t> gpu_d(count);
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(count * sizeof(int32_t)), gpu_d.data());
    gpu::checkGlError("edge tessellation twin");

    int agree = 0, near_threshold = 0, histogram[5] = {};
    for (int i = 0; i < count; ++i) {
        const int cpu_d =
            lod::edgeSimplification(vp_matrix, vp, centres[i], errors[i], levels, epsilon);
        ++histogram[cpu_d];
        if (gpu_d[i] == cpu_d) {
            ++agree;
            continue;
        }
        // Float (GPU) and double (CPU) may only disagree when a projected error is within a
        // hair of ε.
        bool close = false;
        for (int d = 1; d <= levels; ++d)
            close |= std::abs(lod::projectedVerticalSegment(vp_matrix, vp, centres[i],
                                                            errors[i].lambda[d - 1]) -
                              epsilon) < 1e-4 * epsilon;
        EXPECT_TRUE(close) << "case " << i << ": GPU d " << gpu_d[i] << ", C++ d " << cpu_d;
        near_threshold += close;
    }
    EXPECT_GE(agree, count - 4);
    for (int d = 0; d <= levels; ++d)
        EXPECT_GT(histogram[d], 50) << "the cases must exercise every d; d = " << d;
}
