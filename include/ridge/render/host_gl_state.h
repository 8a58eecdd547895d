#pragma once
// The GL state of a host application's context around ridge's work in it (ridge::Renderer):
// saved when a HostGlState is made, set to what ridge's code assumes, and put back when it
// dies, so that the host finds its context as it left it. docs/EMBEDDING.md lists the state.
//
// What is saved and restored: clip control (origin, depth mode); depth test, function, write
// mask and clear value; colour clear value; face culling; blending; rasterizer discard;
// polygon mode and offsets; the patch vertex count; the current program, vertex array and
// active texture unit; the 1D, 2D and 2D-array textures and the sampler objects of units
// 0–11; image units 0–5;
// shader-storage bindings 0–4 and transform-feedback binding 0 (each with its range); the
// pixel pack and unpack buffers and the unpack (and pack alignment) parameters.
// While it lives: blending, rasterizer discard, face culling and polygon offsets are off,
// polygon mode is fill, no sampler object is bound to units 0–11 (a texture's own filtering
// applies), no pixel buffer is bound and unpacking is tight (row length and skips
// 0, no byte swapping); the rest is left as the host set it — framebuffer, viewport, scissor,
// stencil, colour mask, sRGB conversion, multisampling — and applies to ridge's draws as to
// the host's own.
#include <memory>

namespace ridge::render {

class HostGlState {
  public:
    // Needs a current GL 4.5 context. Throws ridge::Error, naming `where` (e.g.
    // "Renderer::draw"), when a GL error is pending: ridge checks GL errors after its work and
    // would otherwise report the host's as its own (the pending error is cleared).
    explicit HostGlState(const char* where);
    ~HostGlState();
    HostGlState(const HostGlState&) = delete;
    HostGlState& operator=(const HostGlState&) = delete;

  private:
    struct Saved;
    std::unique_ptr<Saved> saved_;
};

} // namespace ridge::render
