#pragma once
// What a host application brings to ridge's Renderer in the API tests: a headless OpenGL 4.5
// core context through EGL (Mesa's llvmpipe here), its own framebuffer, its own matrices
// (column-major doubles, written out as a host would, no ridge or glm code), and its own
// object drawn with its own shader.
#include <ridge/ridge.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace host {

using Mat4 = std::array<double, 16>; // column-major: [column · 4 + row]
using Vec3 = std::array<double, 3>;

// Makes a current GL 4.5 core context (surfaceless, else a 1x1 pbuffer); false without one.
// Kept for the process (tests share it).
bool makeContext();

Mat4 multiply(const Mat4& a, const Mat4& b);
// Right-handed look-at (the view maps `eye` to the origin, looking down −z, z up in the
// world) and perspective projections in the three depth conventions: near → −1 and far → 1
// (Standard), near → 0 and far → 1 (ZeroToOne), near → 1 and infinity → 0 (ReverseZ).
Mat4 lookAt(const Vec3& eye, const Vec3& target);
Mat4 perspective(double fov_y_degrees, double aspect, double near_m, double far_m,
                 ridge::DepthConvention convention);
// Window position of a world point (x right, y down from the top-left, pixels) and its
// view depth; false behind the eye.
bool project(const Mat4& view, const Mat4& projection, int width, int height, const Vec3& p,
             double& x, double& y);

// An RGBA8 + DEPTH32F framebuffer object, bound with its viewport on construction.
class Framebuffer {
  public:
    Framebuffer(int width, int height);
    ~Framebuffer();
    void bind() const;
    // Rows top first (as window coordinates), 4 bytes a pixel.
    std::vector<uint8_t> readRgba() const;
    int width() const { return width_; }
    int height() const { return height_; }

  private:
    int width_, height_;
    unsigned fbo_ = 0, colour_ = 0, depth_ = 0;
};

// The GL state a host sets for its own draws in `convention`: clip control, depth test and
// function; and clears to `rgba` and the convention's far depth.
void beginHostFrame(ridge::DepthConvention convention, const std::array<float, 4>& rgba);

// A solid axis-aligned box (a pole, a building) drawn with the host's own program in one
// colour, depth-tested in the current state.
class Box {
  public:
    Box();
    ~Box();
    void draw(const Mat4& view, const Mat4& projection, const Vec3& min, const Vec3& max,
              const std::array<float, 3>& rgb) const;

  private:
    unsigned program_ = 0, vao_ = 0, buffer_ = 0;
};

} // namespace host
