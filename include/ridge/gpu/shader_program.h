#pragma once
// GLSL 450 programs built from the shaders embedded at build time from shaders/
// (cmake/EmbedShaders.cmake): binaries never read shader files at run time.
#include <epoxy/gl.h>

#include <string>
#include <unordered_map>
#include <vector>

namespace ridge::gpu {

struct ShaderStage {
    GLenum type;      // GL_VERTEX_SHADER, GL_TESS_CONTROL_SHADER, ...
    std::string file; // path relative to shaders/, e.g. "terrain.tesc"
};

// The embedded source of shaders/<name>, with every `#include "other.glsl"` line expanded
// recursively (names relative to shaders/) and `#line N K` directives inserted so that compiler
// messages can be mapped back to files: K is 1 + the file's index in the embedded table and N is
// K * 100000 + the line in that file (the file is encoded in the line too, because Mesa reports
// source string 0 for most messages). The first `#line` follows the `#version` line (GLSL
// allows nothing before #version). Consequently __LINE__ is not the plain file line.
// `defines` ("NAME" or "NAME VALUE") become `#define` lines right after the #version line,
// before any included file, so a program can compile a choice in (a shader variant) rather
// than branch on a uniform. Throws ridge::Error for an unknown name (a new file needs a re-run
// of the build, which re-globs shaders/), an include cycle, or a define that is empty or not
// one line.
std::string shaderSource(const std::string& name, const std::vector<std::string>& defines = {});

// A linked program. Needs a current GL context for its whole life (see context.h); move-only.
class ShaderProgram {
  public:
    ShaderProgram() = default; // owns nothing; id() 0
    // Compiles every stage from shaderSource(file) and links them. A compile error throws
    // ridge::Error whose message has one line per driver message, in the form
    // "shaders/test/broken.glsl:4: error: ..." (Mesa "0:42(10): error", NVIDIA "0(42) : error"
    // and AMD "ERROR: 0:42:" forms are translated through the #line source numbers).
    // Link errors throw ridge::Error with the driver's log and the stage files.
    // `feedback_varyings`, when non-empty, are captured with GL_INTERLEAVED_ATTRIBS
    // (glTransformFeedbackVaryings before linking). `defines` go to every stage (shaderSource).
    ShaderProgram(const std::vector<ShaderStage>& stages,
                  const std::vector<std::string>& feedback_varyings = {},
                  const std::vector<std::string>& defines = {});
    ~ShaderProgram();
    ShaderProgram(ShaderProgram&& other) noexcept;
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    GLuint id() const { return id_; }
    void use() const; // glUseProgram(id())
    // Location of uniform `name`, or -1 when the program has none by that name (or the linker
    // removed it as unused); never throws. Cached per name: the first call per name costs a
    // glGetUniformLocation, later ones a hash lookup.
    GLint uniform(const char* name) const;

  private:
    GLuint id_ = 0;
    mutable std::unordered_map<std::string, GLint> uniforms_;
};

} // namespace ridge::gpu
