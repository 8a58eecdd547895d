#pragma once
// The shader table generated at build time by cmake/EmbedShaders.cmake (internal to ridge_gpu).
// Entries are the files of shaders/ named relative to it ("terrain.tesc", "test/bad.frag"),
// sorted by name; indices are stable within one build only.
#include <cstddef>
#include <string_view>

namespace ridge::gpu::detail {

std::size_t embeddedShaderCount();
// For i < embeddedShaderCount(); views of static storage.
std::string_view embeddedShaderName(std::size_t i);
std::string_view embeddedShaderSource(std::size_t i);

// shaderSource() numbers line N of entry i as (i + 1) * kLineStride + N, besides giving it
// source-string number i + 1: Mesa drops the source-string number from most messages (bison's
// default location merge does not copy it; "0:5(14): error" for an included file) but keeps
// line numbers, so the line alone must identify the file. Files are shorter than kLineStride
// lines, and (i + 1) * kLineStride stays far below INT_MAX for any plausible shader count.
constexpr long kLineStride = 100000;

} // namespace ridge::gpu::detail
