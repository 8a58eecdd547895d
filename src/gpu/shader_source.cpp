// shaderSource(): #include expansion with #line bookkeeping over the embedded shader table.
#include "embedded_shaders.h"
#include "ridge/core/error.h"
#include "ridge/gpu/shader_program.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ridge::gpu {
namespace {

std::optional<std::size_t> findShader(std::string_view name)
{
    for (std::size_t i = 0; i < detail::embeddedShaderCount(); ++i) {
        if (detail::embeddedShaderName(i) == name)
            return i;
    }
    return std::nullopt;
}

std::size_t requireShader(std::string_view name, std::string_view included_from)
{
    if (const std::optional<std::size_t> index = findShader(name))
        return *index;
    std::string message = "unknown shader '" + std::string(name) + "'";
    if (!included_from.empty())
        message += " (included from shaders/" + std::string(included_from) + ")";
    throw Error(message + ": not embedded from shaders/ (a new file needs a rebuild; names are "
                          "relative to shaders/, e.g. \"test/common.glsl\")");
}

std::string_view trimLeft(std::string_view s)
{
    const std::size_t start = s.find_first_not_of(" \t");
    return start == std::string_view::npos ? std::string_view() : s.substr(start);
}

// Whether `line` is the preprocessor directive `directive` ("version", "include"); on true,
// `rest` is what follows the directive's name.
bool isDirective(std::string_view line, std::string_view directive, std::string_view& rest)
{
    line = trimLeft(line);
    if (line.empty() || line.front() != '#')
        return false;
    line = trimLeft(line.substr(1));
    if (line.substr(0, directive.size()) != directive)
        return false;
    rest = line.substr(directive.size());
    return rest.empty() || rest.front() == ' ' || rest.front() == '\t' || rest.front() == '"';
}

// The quoted name of an #include line's `rest`; throws for anything but `"name"` followed by
// blanks or a // comment.
std::string includedName(std::string_view rest, std::string_view file, int line_number)
{
    rest = trimLeft(rest);
    const std::size_t close = rest.size() > 1 ? rest.find('"', 1) : std::string_view::npos;
    const std::string_view after =
        close == std::string_view::npos ? std::string_view() : trimLeft(rest.substr(close + 1));
    if (rest.empty() || rest.front() != '"' || close == std::string_view::npos || close == 1 ||
        !(after.empty() || after.substr(0, 2) == "//"))
        throw Error("shaders/" + std::string(file) + ":" + std::to_string(line_number) +
                    ": malformed #include (expected #include \"name\")");
    return std::string(rest.substr(1, close - 1));
}

// The directive that makes the next line line `line` (1-based) of table entry `index`; see
// kLineStride. Source-string number 0 and small line numbers are left to the top-level file's
// lines before its #version, where no #line may precede.
std::string lineDirective(std::size_t index, int line)
{
    const long number = static_cast<long>(index + 1);
    return "#line " + std::to_string(number * detail::kLineStride + line) + " " +
           std::to_string(number) + "\n";
}

// `#define` lines for shaderSource's `defines`, each checked to be one non-empty line.
std::string defineLines(const std::vector<std::string>& defines)
{
    std::string lines;
    for (const std::string& define : defines) {
        if (trimLeft(define).empty() || define.find_first_of("\r\n") != std::string::npos)
            throw Error("a shader define must be one non-empty line (\"NAME\" or \"NAME VALUE\"), "
                        "not '" +
                        define + "'");
        lines += "#define " + define + "\n";
    }
    return lines;
}

// Appends entry `index` to `out` with its includes expanded. `stack` holds the entries being
// expanded (outermost first) to detect cycles; `defines` (#define lines, empty for included
// files) go after the file's #version, or first when it has none.
void expand(std::size_t index, std::vector<std::size_t>& stack, std::string& out,
            const std::string& defines)
{
    if (std::find(stack.begin(), stack.end(), index) != stack.end()) {
        std::string cycle;
        for (std::size_t i : stack)
            cycle += std::string(detail::embeddedShaderName(i)) + " -> ";
        throw Error("#include cycle: " + cycle + std::string(detail::embeddedShaderName(index)));
    }
    stack.push_back(index);
    const std::string_view name = detail::embeddedShaderName(index);
    const std::string_view source = detail::embeddedShaderSource(index);
    const bool top_level = stack.size() == 1;
    std::string_view rest;
    // The top level's numbering starts after its #version, when it has one.
    bool numbered = !top_level || source.find("#version") == std::string_view::npos;
    if (numbered)
        out += defines + lineDirective(index, 1);

    int line_number = 0;
    for (std::size_t pos = 0; pos < source.size();) {
        const std::size_t end = std::min(source.find('\n', pos), source.size());
        std::string_view line = source.substr(pos, end - pos);
        pos = end + 1;
        ++line_number;
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);

        if (isDirective(line, "include", rest)) {
            const std::string included = includedName(rest, name, line_number);
            expand(requireShader(included, name), stack, out, std::string());
            out += lineDirective(index, line_number + 1);
            continue;
        }
        out += line;
        out += '\n';
        if (!numbered && isDirective(line, "version", rest)) {
            out += defines + lineDirective(index, line_number + 1);
            numbered = true;
        }
    }
    stack.pop_back();
}

} // namespace

std::string shaderSource(const std::string& name, const std::vector<std::string>& defines)
{
    std::vector<std::size_t> stack;
    std::string out;
    expand(requireShader(name, {}), stack, out, defineLines(defines));
    return out;
}

} // namespace ridge::gpu
