#include "ridge/gpu/shader_program.h"

#include "embedded_shaders.h"
#include "ridge/core/error.h"

#include <deque>
#include <regex>
#include <sstream>
#include <utility>

namespace ridge::gpu {
namespace {

const char* stageName(GLenum type)
{
    switch (type) {
    case GL_VERTEX_SHADER:
        return "vertex";
    case GL_TESS_CONTROL_SHADER:
        return "tessellation control";
    case GL_TESS_EVALUATION_SHADER:
        return "tessellation evaluation";
    case GL_GEOMETRY_SHADER:
        return "geometry";
    case GL_FRAGMENT_SHADER:
        return "fragment";
    case GL_COMPUTE_SHADER:
        return "compute";
    default:
        return "unknown";
    }
}

// "<file>:<line>" for a driver message at `line` of source string `number` (see
// detail::kLineStride). The line decides when it encodes a file, as Mesa reports source 0 for
// most messages; else source 0 is the top-level file before its #version and K > 0 is embedded
// entry K - 1.
std::string sourceLocation(unsigned long number, unsigned long line, const std::string& top_level)
{
    const auto stride = static_cast<unsigned long>(detail::kLineStride);
    if (line >= stride) {
        number = line / stride;
        line %= stride;
    }
    std::string file = "<source " + std::to_string(number) + ">";
    if (number == 0)
        file = top_level;
    else if (number <= detail::embeddedShaderCount())
        file = std::string(detail::embeddedShaderName(number - 1));
    return file + ":" + std::to_string(line);
}

// Rewrites one driver message line to "shaders/<file>:<line>: <message>"; other lines pass.
std::string translateLogLine(const std::string& line, const std::string& top_level)
{
    // Mesa "0:42(10): error: ...", NVIDIA "0(42) : error C0000: ...", AMD "ERROR: 0:42: ...".
    static const std::regex mesa(R"(^(\d+):(\d+)\(\d+\): (.*)$)");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\) : (.*)$)");
    static const std::regex amd(R"(^(ERROR|WARNING): (\d+):(\d+): (.*)$)");
    std::smatch m;
    std::string number, line_number, message;
    if (std::regex_match(line, m, mesa) || std::regex_match(line, m, nvidia)) {
        number = m[1];
        line_number = m[2];
        message = m[3];
    } else if (std::regex_match(line, m, amd)) {
        number = m[2];
        line_number = m[3];
        message = (m[1] == "ERROR" ? "error: " : "warning: ") + m[4].str();
    } else {
        return line;
    }
    return "shaders/" + sourceLocation(std::stoul(number), std::stoul(line_number), top_level) +
           ": " + message;
}

std::string translateLog(const std::string& log, const std::string& top_level)
{
    std::istringstream in(log);
    std::string out;
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.empty())
            continue;
        out += "\n" + translateLogLine(line, top_level);
    }
    return out;
}

std::string shaderLog(GLuint shader)
{
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

std::string programLog(GLuint program)
{
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
    return log;
}

// Owns a shader object for the duration of a link.
class Shader {
  public:
    Shader(const ShaderStage& stage, const std::vector<std::string>& defines)
        : id_(glCreateShader(stage.type))
    {
        if (id_ == 0)
            throw Error("glCreateShader failed for shaders/" + stage.file + " (" +
                        stageName(stage.type) + " shader; is a GL 4.5 context current?)");
        const std::string source = shaderSource(stage.file, defines);
        const char* text = source.c_str();
        const auto length = static_cast<GLint>(source.size());
        glShaderSource(id_, 1, &text, &length);
        glCompileShader(id_);
        GLint ok = GL_FALSE;
        glGetShaderiv(id_, GL_COMPILE_STATUS, &ok);
        if (ok != GL_TRUE)
            throw Error("compiling shaders/" + stage.file + " (" + stageName(stage.type) +
                        " shader) failed:" + translateLog(shaderLog(id_), stage.file));
    }
    ~Shader() { glDeleteShader(id_); }
    Shader(const Shader&) = delete;
    Shader& operator=(const Shader&) = delete;
    GLuint id() const { return id_; }

  private:
    GLuint id_;
};

std::string stageList(const std::vector<ShaderStage>& stages)
{
    std::string list;
    for (const ShaderStage& stage : stages)
        list += (list.empty() ? "shaders/" : ", shaders/") + stage.file;
    return list;
}

} // namespace

ShaderProgram::ShaderProgram(const std::vector<ShaderStage>& stages,
                             const std::vector<std::string>& feedback_varyings,
                             const std::vector<std::string>& defines)
{
    if (stages.empty())
        throw Error("a shader program needs at least one stage");
    // Compile everything first so that a compile error is reported before any link attempt.
    std::deque<Shader> shaders; // deque: Shader is immovable
    for (const ShaderStage& stage : stages)
        shaders.emplace_back(stage, defines);

    id_ = glCreateProgram();
    if (id_ == 0)
        throw Error("glCreateProgram failed for " + stageList(stages));
    for (const Shader& shader : shaders)
        glAttachShader(id_, shader.id());
    if (!feedback_varyings.empty()) {
        std::vector<const char*> names;
        for (const std::string& name : feedback_varyings)
            names.push_back(name.c_str());
        glTransformFeedbackVaryings(id_, static_cast<GLsizei>(names.size()), names.data(),
                                    GL_INTERLEAVED_ATTRIBS);
    }
    glLinkProgram(id_);
    for (const Shader& shader : shaders)
        glDetachShader(id_, shader.id());
    GLint ok = GL_FALSE;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = programLog(id_);
        glDeleteProgram(std::exchange(id_, 0));
        throw Error("linking " + stageList(stages) +
                    " failed:" + translateLog(log, stages.front().file));
    }
}

ShaderProgram::~ShaderProgram()
{
    if (id_ != 0) // an empty program may outlive every context
        glDeleteProgram(id_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept
    : id_(std::exchange(other.id_, 0)), uniforms_(std::move(other.uniforms_))
{
    other.uniforms_.clear();
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept
{
    if (this != &other) {
        if (id_ != 0)
            glDeleteProgram(id_);
        id_ = std::exchange(other.id_, 0);
        uniforms_ = std::move(other.uniforms_);
        other.uniforms_.clear();
    }
    return *this;
}

void ShaderProgram::use() const
{
    glUseProgram(id_);
}

GLint ShaderProgram::uniform(const char* name) const
{
    if (id_ == 0)
        return -1;
    const auto found = uniforms_.find(name);
    if (found != uniforms_.end())
        return found->second;
    const GLint location = glGetUniformLocation(id_, name);
    uniforms_.emplace(name, location);
    return location;
}

} // namespace ridge::gpu
