#include "gpu_test.h"
#include "ridge/gpu/gl_objects.h"

#include <epoxy/gl.h>

#include <cstdlib>
#include <optional>
#include <string>

using namespace ridge;
using namespace ridge::gpu;
using ridge::gpu::test::GpuTest;

namespace {

GLint glInteger(GLenum name)
{
    GLint value = 0;
    glGetIntegerv(name, &value);
    return value;
}

// Unsets an environment variable for the scope, restoring the old value afterwards.
class ScopedUnsetEnv {
  public:
    explicit ScopedUnsetEnv(const char* name) : name_(name)
    {
        if (const char* value = std::getenv(name))
            old_ = value;
        unsetenv(name);
    }
    ~ScopedUnsetEnv()
    {
        if (old_)
            setenv(name_, old_->c_str(), 1);
    }

  private:
    const char* name_;
    std::optional<std::string> old_;
};

} // namespace

TEST_F(GpuTest, HeadlessContextIsOpenGl45CoreWithTessellation)
{
    EXPECT_GE(glInteger(GL_MAJOR_VERSION) * 10 + glInteger(GL_MINOR_VERSION), 45);
    EXPECT_NE(glInteger(GL_CONTEXT_PROFILE_MASK) & GL_CONTEXT_CORE_PROFILE_BIT, 0);
    EXPECT_GE(glInteger(GL_MAX_TESS_GEN_LEVEL), 64);
    EXPECT_GE(glInteger(GL_MAX_PATCH_VERTICES), 4);
    EXPECT_FALSE(context_->rendererName().empty());
    const std::string platform = context_->platformName();
    EXPECT_TRUE(platform == "EGL device" || platform == "EGL surfaceless" ||
                platform == "EGL default display")
        << platform;
    std::printf("renderer: %s via %s\n", context_->rendererName().c_str(), platform.c_str());
}

TEST_F(GpuTest, ContextsCoexistAndOutliveEachOther)
{
    {
        const std::unique_ptr<HeadlessContext> second = HeadlessContext::create();
        GlBuffer buffer;
        EXPECT_NE(buffer.id(), 0u);
    }
    // The second context shared the EGL display; destroying it must not end this one.
    context_->makeCurrent();
    GlBuffer buffer;
    EXPECT_NE(buffer.id(), 0u);
    EXPECT_NO_THROW(checkGlError("after a second context"));
}

TEST_F(GpuTest, CheckGlErrorNamesTheCallSiteAndError)
{
    glEnable(0xFFFF); // not a capability
    try {
        checkGlError("enabling nonsense");
        FAIL() << "no error thrown";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("enabling nonsense"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("GL_INVALID_ENUM"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(checkGlError("the error was drained"));
}

TEST_F(GpuTest, GlObjectsMoveTheirName)
{
    GlTexture a(GL_TEXTURE_2D);
    const GLuint id = a.id();
    GlTexture b = std::move(a);
    EXPECT_EQ(b.id(), id);
    EXPECT_EQ(a.id(), 0u); // NOLINT(bugprone-use-after-move): the contract under test
    GlVertexArray vao;
    GlFramebuffer fbo;
    GlQuery query(GL_TIME_ELAPSED);
    GlTransformFeedback feedback;
    for (GLuint name : {vao.id(), fbo.id(), query.id(), feedback.id()})
        EXPECT_NE(name, 0u);
}

TEST(HeadlessContext, DebugContextReportsErrorsOnStderr)
{
    std::unique_ptr<HeadlessContext> context;
    try {
        context = HeadlessContext::create(true);
    } catch (const Error& e) {
        FAIL() << e.what();
    }
    EXPECT_NE(glInteger(GL_CONTEXT_FLAGS) & GL_CONTEXT_FLAG_DEBUG_BIT, 0);
    ::testing::internal::CaptureStderr();
    glEnable(0xFFFF);
    const std::string output = ::testing::internal::GetCapturedStderr();
    glGetError();
    EXPECT_NE(output.find("[gl high"), std::string::npos) << output;
}

TEST(WindowContext, ThrowsWithoutADisplay)
{
    const ScopedUnsetEnv display("DISPLAY");
    const ScopedUnsetEnv wayland("WAYLAND_DISPLAY");
    EXPECT_THROW(WindowContext(64, 64, "no display"), Error);
}

TEST(WindowContext, OpensA45CoreWindowWhenThereIsADisplay)
{
    if (std::getenv("DISPLAY") == nullptr)
        GTEST_SKIP() << "no DISPLAY (run under xvfb-run to cover WindowContext)";
    WindowContext window(64, 48, "ridge test", false);
    EXPECT_NE(window.window(), nullptr);
    EXPECT_FALSE(window.rendererName().empty());
    EXPECT_GE(glInteger(GL_MAJOR_VERSION) * 10 + glInteger(GL_MINOR_VERSION), 45);
    int width = 0;
    int height = 0;
    window.framebufferSize(width, height);
    EXPECT_GT(width, 0);
    EXPECT_GT(height, 0);
    EXPECT_FALSE(window.shouldClose());
    glClear(GL_COLOR_BUFFER_BIT);
    window.swapBuffers();
    window.pollEvents();
    EXPECT_NO_THROW(checkGlError("window frame"));
}

TEST(WindowContext, SharesAThreadWithHeadlessContexts)
{
    if (std::getenv("DISPLAY") == nullptr)
        GTEST_SKIP() << "no DISPLAY (run under xvfb-run to cover WindowContext)";
    // GLVND refuses a GLX context while an EGL one is current on the thread (BadAccess, which
    // Xlib turns into exit()), so each makeCurrent must release the other API's context.
    std::unique_ptr<HeadlessContext> headless = HeadlessContext::create();
    WindowContext window(32, 32, "ridge test", false);
    {
        GlBuffer in_window;
    }
    headless->makeCurrent();
    {
        GlBuffer in_headless;
    }
    window.makeCurrent();
    const std::unique_ptr<HeadlessContext> second = HeadlessContext::create();
    EXPECT_NO_THROW(checkGlError("switching contexts"));
}
