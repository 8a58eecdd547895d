#pragma once
// The four programs every terrain scheme draws with (internal to ridge_render): its own
// surface stages, then either its fragment stage (terrain.frag unless it has its own) or
// transform feedback of
// Capture.tf_* (capture), each with or without terrain_clip.geom for patches that reach past
// the valid extent. Compiled on first use, so a renderer that never draws a scheme never
// compiles it. What the archive fixes is compiled in, not branched on: the surface (plane,
// geographic grid on the ellipsoid, projected grid: RIDGE_SURFACE, terrain_common.glsl) and
// its water rule (RIDGE_WATER_FROM_HEIGHT, before format 4); and, per draw, whether the
// patches drawn fade in (RIDGE_ARRIVAL_BLEND: a streaming renderer's fading variants, drawn
// for those patches alone). llvmpipe runs both sides of a branch on a uniform under an
// execution mask: the globe's trigonometry in every vertex made the plane's frames 2.2-2.4x
// slower (docs/PERF.md, "Like for like"), the fade's ancestor reads made every vertex of a
// streaming frame 8x slower ("Arrivals that fade in").
#include "ridge/gpu/shader_program.h"

#include <array>
#include <string>
#include <vector>

namespace ridge::render {

struct SchemeResources; // terrain_scheme.h

class SchemePrograms {
  public:
    // `surface`: the stages up to the tessellator or vertex shader, e.g. {terrain.vert,
    // terrain.tesc, terrain.tese}; every one must write the Vertex and Capture blocks that
    // terrain_clip.geom and the fragment stage read. `fragment`: the fragment shader's file
    // (a scheme whose surface is not drawn from patch layers brings its own).
    // `r`: the scheme's resources, whose archive the programs are built for.
    SchemePrograms(const SchemeResources& r, std::vector<gpu::ShaderStage> surface,
                   std::string fragment = "terrain.frag");
    // The same with variants: each a set of defines ("NAME VALUE") the scheme compiles in for
    // a choice it would otherwise branch on per frame (the tessellation rule); get() picks one.
    SchemePrograms(const SchemeResources& r, std::vector<gpu::ShaderStage> surface,
                   std::vector<std::vector<std::string>> variants,
                   std::string fragment = "terrain.frag");

    // {whole patches, clipped patches} of `variant` for drawing or for capture, for patches
    // that fade in (`fading`; the plain programs when the renderer fades nothing in) or not.
    // Throws ridge::Error for a variant it was not given.
    std::array<const gpu::ShaderProgram*, 2> get(bool capture, bool fading, size_t variant = 0);

  private:
    struct Variant {
        std::vector<std::string> defines;
        bool compiled[2][2] = {{false, false}, {false, false}}; // [capture][fading]
        gpu::ShaderProgram programs[2][2][2];                   // [capture][fading][clip]
    };
    bool fades_ = false; // the renderer's arrivals fade in (streaming, fades on)
    std::vector<gpu::ShaderStage> surface_;
    std::string fragment_;
    std::vector<Variant> variants_;
};

} // namespace ridge::render
