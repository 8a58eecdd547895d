#include "gpu_test.h"
#include "ridge/gpu/gl_objects.h"
#include "ridge/gpu/render_target.h"
#include "ridge/gpu/shader_program.h"

#include <string>
#include <vector>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

// The message of the Error that compiling `stages` throws ("" if it does not throw).
std::string compileError(const std::vector<ShaderStage>& stages)
{
    try {
        ShaderProgram program(stages);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool contains(const std::string& text, const std::string& part)
{
    return text.find(part) != std::string::npos;
}

} // namespace

TEST(ShaderSource, ExpandsIncludesAfterVersionWithLineDirectives)
{
    const std::string source = shaderSource("test/quadrants.frag");
    EXPECT_EQ(source.rfind("#version 450 core\n#line ", 0), 0u) << source;
    EXPECT_FALSE(contains(source, "#include \"")) << source;
    EXPECT_TRUE(contains(source, "float pastMiddle(")) << source;
    // Line 2 of quadrants.frag, then line 1 of common.glsl, then line 5 of quadrants.frag
    // (after the include on line 4): K * 100000 + line, with the same K for both quadrants.
    std::vector<long> lines;
    for (std::size_t at = source.find("#line "); at != std::string::npos;
         at = source.find("#line ", at + 1))
        lines.push_back(std::stol(source.substr(at + 6)));
    ASSERT_EQ(lines.size(), 3u) << source;
    EXPECT_EQ(lines[0] % 100000, 2);
    EXPECT_EQ(lines[1] % 100000, 1);
    EXPECT_EQ(lines[2], lines[0] + 3);
    EXPECT_NE(lines[1] / 100000, lines[0] / 100000);
}

TEST(ShaderSource, PutsDefinesAfterVersionBeforeAnyIncludedLine)
{
    const std::string source = shaderSource("test/quadrants.frag", {"RIDGE_A 2", "RIDGE_B"});
    EXPECT_EQ(source.rfind("#version 450 core\n#define RIDGE_A 2\n#define RIDGE_B\n#line ", 0), 0u)
        << source;
    // Once only: an included file gets none of its own.
    EXPECT_EQ(source.find("#define RIDGE_A", 20), std::string::npos) << source;
    EXPECT_EQ(shaderSource("test/quadrants.frag", {}), shaderSource("test/quadrants.frag"));
}

TEST(ShaderSource, RejectsADefineThatIsEmptyOrMoreThanOneLine)
{
    for (const std::string define : {"", "  ", "A 1\n#version 100", "A\r"}) {
        try {
            shaderSource("test/quadrants.frag", {define});
            FAIL() << "no error thrown for '" << define << "'";
        } catch (const Error& e) {
            EXPECT_TRUE(contains(e.what(), "shader define")) << e.what();
        }
    }
}

TEST(ShaderSource, RejectsAnUnknownName)
{
    try {
        shaderSource("test/no_such_shader.frag");
        FAIL() << "no error thrown";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "test/no_such_shader.frag")) << e.what();
    }
}

TEST(ShaderSource, RejectsAnIncludeCycle)
{
    try {
        shaderSource("test/cycle_a.glsl");
        FAIL() << "no error thrown";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "cycle")) << e.what();
        EXPECT_TRUE(contains(e.what(), "test/cycle_b.glsl")) << e.what();
    }
}

TEST_F(GpuTest, CompileErrorNamesFileAndLine)
{
    const std::string message = compileError({{GL_FRAGMENT_SHADER, "test/bad.frag"}});
    EXPECT_TRUE(contains(message, "shaders/test/bad.frag:7: ")) << message;
}

TEST_F(GpuTest, CompileErrorInAnIncludedFileNamesThatFile)
{
    const std::string message = compileError({{GL_FRAGMENT_SHADER, "test/bad_include.frag"}});
    EXPECT_TRUE(contains(message, "shaders/test/broken.glsl:5: ")) << message;
    EXPECT_TRUE(contains(message, "compiling shaders/test/bad_include.frag")) << message;
    // The error is entirely in broken.glsl; no message may blame bad_include.frag's lines.
    EXPECT_FALSE(contains(message, "shaders/test/bad_include.frag:")) << message;
}

// The terrain stages compile what the archive fixes in (RIDGE_SURFACE, RIDGE_WATER_FROM_HEIGHT):
// one built without it is a clear compile error, not a plane drawn where a globe was meant.
TEST_F(GpuTest, TerrainStagesWithoutTheArchivesDefinesAreACompileError)
{
    const std::string message = compileError({{GL_VERTEX_SHADER, "chunk.vert"}});
    EXPECT_TRUE(contains(message, "RIDGE_SURFACE is not defined")) << message;
    EXPECT_TRUE(contains(message, "shaders/terrain_common.glsl:")) << message;
    const std::vector<ShaderStage> stages = {{GL_VERTEX_SHADER, "chunk.vert"},
                                             {GL_FRAGMENT_SHADER, "terrain.frag"}};
    std::string water;
    try {
        ShaderProgram program(stages, {}, {"RIDGE_SURFACE 0"});
    } catch (const Error& e) {
        water = e.what();
    }
    EXPECT_TRUE(contains(water, "RIDGE_WATER_FROM_HEIGHT is not defined")) << water;
    for (const char* surface : {"0", "1", "2"}) {
        for (const char* from_height : {"0", "1"}) {
            try {
                ShaderProgram program(stages, {},
                                      {std::string("RIDGE_SURFACE ") + surface,
                                       std::string("RIDGE_WATER_FROM_HEIGHT ") + from_height});
            } catch (const Error& e) {
                ADD_FAILURE() << "RIDGE_SURFACE " << surface << ", RIDGE_WATER_FROM_HEIGHT "
                              << from_height << ": " << e.what();
            }
        }
    }
}

TEST_F(GpuTest, UniformLocationsAreFoundCachedAndMinusOneWhenAbsent)
{
    ShaderProgram program(
        {{GL_VERTEX_SHADER, "test/fullscreen.vert"}, {GL_FRAGMENT_SHADER, "test/quadrants.frag"}});
    EXPECT_NE(program.id(), 0u);
    const GLint size = program.uniform("u_size");
    EXPECT_GE(size, 0);
    EXPECT_EQ(program.uniform("u_size"), size);
    EXPECT_EQ(program.uniform("u_not_there"), -1);
    ShaderProgram moved = std::move(program);
    EXPECT_EQ(moved.uniform("u_size"), size);
    EXPECT_EQ(program.uniform("u_size"), -1); // NOLINT(bugprone-use-after-move)
}

TEST_F(GpuTest, TransformFeedbackCapturesTheNamedVaryings)
{
    ShaderProgram program({{GL_VERTEX_SHADER, "test/feedback.vert"}}, {"doubled_id"});
    constexpr int kVertices = 5;
    GlBuffer buffer;
    glNamedBufferStorage(buffer.id(), kVertices * sizeof(float), nullptr, GL_MAP_READ_BIT);
    GlTransformFeedback feedback;
    glTransformFeedbackBufferBase(feedback.id(), 0, buffer.id());
    GlVertexArray vao;
    glBindVertexArray(vao.id());
    // Even with rasterisation off, a draw in a surfaceless context needs a complete framebuffer
    // (Mesa reports GL_INVALID_FRAMEBUFFER_OPERATION otherwise).
    const RenderTarget target(1, 1);
    target.bind();
    program.use();
    glEnable(GL_RASTERIZER_DISCARD);
    glBindTransformFeedback(GL_TRANSFORM_FEEDBACK, feedback.id());
    glBeginTransformFeedback(GL_POINTS);
    glDrawArrays(GL_POINTS, 0, kVertices);
    glEndTransformFeedback();
    glDisable(GL_RASTERIZER_DISCARD);
    checkGlError("transform feedback draw");

    float captured[kVertices] = {};
    glGetNamedBufferSubData(buffer.id(), 0, sizeof captured, captured);
    for (int i = 0; i < kVertices; ++i)
        EXPECT_EQ(captured[i], 2.0f * static_cast<float>(i)) << "vertex " << i;
}
