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
    std::vector<glm::dvec3> ends_a(count), centres(count), ends_b(count);
    for (int i = 0; i < count; ++i) {
        // Ahead of the camera, 5 m to 20 km away; Λ^(d) increasing with d as real blocks do.
        const double dist = 5.0 * std::pow(4000.0, u(rng));
        centres[i] =
            glm::normalize(glm::dvec3(u(rng) - 0.5, 1.0, -0.4 + 0.6 * (u(rng) - 0.5))) * dist;
        // An edge of 8 to 2000 m along x or y through it, with some relief.
        const double half = 4.0 * std::pow(250.0, u(rng));
        const glm::dvec3 along = u(rng) < 0.5 ? glm::dvec3(half, 0, 0) : glm::dvec3(0, half, 0);
        ends_a[i] = glm::dvec3(
            glm::vec3(centres[i] - along + glm::dvec3(0, 0, 0.3 * half * (u(rng) - 0.5))));
        ends_b[i] = glm::dvec3(
            glm::vec3(centres[i] + along + glm::dvec3(0, 0, 0.3 * half * (u(rng) - 0.5))));
        centres[i] = glm::dvec3(glm::vec3(centres[i]));
        float lambda = float(0.05 * std::pow(400.0, u(rng)));
        // Err(P) is part of every Λ^(d): from none to all of Λ^(1).
        errors[i].patch_error = float(u(rng)) * lambda;
        for (int d = 0; d < lod::kMaxBlockLevels; ++d) {
            errors[i].lambda[d] = lambda;
            lambda *= float(1.0 + 3.0 * u(rng));
        }
        cases.push_back(glm::vec4(glm::vec3(ends_a[i]), errors[i].patch_error));
        for (const glm::dvec3& p : {centres[i], ends_b[i]})
            cases.push_back(glm::vec4(glm::vec3(p), 0.f));
        cases.push_back(glm::vec4(errors[i].lambda[0], errors[i].lambda[1], errors[i].lambda[2],
                                  errors[i].lambda[3]));
    }
    gpu::GlBuffer in;
    glNamedBufferStorage(in.id(), GLsizeiptr(cases.size() * sizeof(glm::vec4)), cases.data(), 0);
    for (const lod::TessellationRule rule :
         {lod::TessellationRule::Conservative, lod::TessellationRule::Paper}) {
        // The rule is compiled in, as SchemePrograms does; on the plane (RIDGE_SURFACE 0): the twin
        // compares the rules, not the globe's bulge term.
        const gpu::ShaderProgram program(
            {{GL_COMPUTE_SHADER, "test/edge_tessellation_twin.comp"}}, {},
            {"RIDGE_SURFACE 0", "RIDGE_TESSELLATION_RULE " + std::to_string(int(rule))});
        program.use();
        const glm::mat4 m(vp_matrix);
        glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, glm::value_ptr(m));
        // The LOD camera is the camera here (the renderer sets both; twins test the edge rule).
        glUniformMatrix4fv(program.uniform("u_lod_view_projection"), 1, GL_FALSE,
                           glm::value_ptr(m));
        glUniform3f(program.uniform("u_lod_camera"), 0.f, 0.f, 0.f);
        glUniform2f(program.uniform("u_viewport"), float(vp.width), float(vp.height));
        glUniform1f(program.uniform("u_epsilon"), float(epsilon));
        glUniform1i(program.uniform("u_block_levels"), levels);
        glUniform1i(program.uniform("u_case_count"), count);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, in.id());

        // Float (GPU) and double (CPU) may only disagree when a projected error is within a hair
        // of ε at one of the points the rule tests.
        // `doubled`: the conservative rule's 2Λ − Err(P) instead of Λ.
        auto nearThreshold = [&](int i, bool doubled) {
            bool close = false;
            for (const glm::dvec3& p : {ends_a[i], centres[i], ends_b[i],
                                        lod::nearestPointOfSegment(ends_a[i], ends_b[i])})
                for (int d = 1; d <= levels; ++d) {
                    const double lambda = errors[i].lambda[d - 1];
                    const double length = doubled ? 2.0 * lambda - errors[i].patch_error : lambda;
                    close |= std::abs(lod::projectedVerticalSegment(vp_matrix, vp, p, length) -
                                      epsilon) < 1e-4 * epsilon;
                }
            return close;
        };
        gpu::GlBuffer out;
        glNamedBufferStorage(out.id(), GLsizeiptr(count * sizeof(glm::ivec2)), nullptr, 0);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, out.id());
        glDispatchCompute((count + 63) / 64, 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::ivec2> gpu_d(count);
        glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(count * sizeof(glm::ivec2)), gpu_d.data());
        gpu::checkGlError("edge tessellation twin");

        const bool paper = rule == lod::TessellationRule::Paper;
        int agree = 0, histogram[5] = {}, finer = 0;
        for (int i = 0; i < count; ++i) {
            const int cpu_centre =
                lod::edgeSimplification(vp_matrix, vp, centres[i], errors[i], levels, epsilon);
            const int cpu_edge = lod::edgeSimplification(
                vp_matrix, vp, ends_a[i], centres[i], ends_b[i], errors[i], levels, epsilon, rule);
            ++histogram[cpu_edge];
            finer += cpu_edge < cpu_centre;
            // The conservative rule never simplifies more than the paper's.
            EXPECT_LE(cpu_edge, cpu_centre) << i;
            if (paper) {
                EXPECT_EQ(cpu_edge, cpu_centre) << i;
            }
            if (gpu_d[i].x == cpu_centre && gpu_d[i].y == cpu_edge) {
                ++agree;
                continue;
            }
            EXPECT_TRUE(nearThreshold(i, false) || (!paper && nearThreshold(i, true)))
                << "case " << i << ": GPU d " << gpu_d[i].x << " / " << gpu_d[i].y << ", C++ d "
                << cpu_centre << " / " << cpu_edge;
        }
        EXPECT_GE(agree, count - 8);
        for (int d = 0; d <= levels; ++d)
            EXPECT_GT(histogram[d], 50) << "the cases must exercise every d; d = " << d;
        if (!paper) {
            EXPECT_GT(finer, count / 10) << "the conservative rule must differ from the paper's";
        }
    }
}
