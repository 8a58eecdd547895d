#pragma once
// Unit normals of the upper hemisphere (z >= 0) as two bytes: an index (u, v) into a 256×256
// normal texture (Ma, Sun & Song, "Accelerate terrain rendering using programmable graphics
// hardware", JATIT 2013, §3.2). Terrain normals never point down, so the hemisphere can be laid
// over a square without a singularity and the texture coordinates interpolated across triangles.
//
// Index u (v) stands for the texel centre s = (u + ½)/256 (t = (v + ½)/256) of the unit square,
// which is where the GPU samples texel (u, v); a = 2s − 1, b = 2t − 1 ∈ (−1, 1).
//
//  * Orthographic: (a, b) = (x, y), z = sqrt(max(0, 1 − x² − y²)), the paper's "orthotic
//    projection". Texels outside the inscribed disk (21% of them) decode to the horizon
//    direction (x, y)/|(x, y)|. Texel density is uniform in (x, y), so it is worst at the
//    horizon, where dz/dr is unbounded: one texel of (x, y) spans ~6° of elevation there, but
//    < 1° within 60° of vertical, where terrain normals are.
//  * Concentric: Shirley & Chiu's concentric square→disk map ("A low distortion map between
//    disk and square", JGT 1997) gives (x, y), lifted orthographically, z = sqrt(1 − r²).
//    Why this lift: Shirley & Chiu's map exists to carry stratified square samples to the disk,
//    and its use for directions in rendering is cosine-weighted hemisphere sampling, which
//    projects disk points straight up (Malley's method); the paper attributes the concentric
//    texture's artifacts to "the stretch at the corners of the square", i.e. to the square→disk
//    step, which this lift isolates: both maps are then the same orthographic projection of the
//    hemisphere onto the disk and differ only in how the disk covers the square. The
//    concentric map uses every texel (4/π as many inside the disk) but shears cells along the
//    square's diagonals and, like the orthographic map, is worst at the horizon. (Not checked
//    against the JGT text, which we do not have: its hemisphere extension may be the
//    equal-area lift z = 1 − r², (x, y)·sqrt(2 − r²), which would remove the horizon
//    blow-up but is not what the JATIT paper's figure suggests it compared.)
//
// Measured round trip (tests/lod/hemisphere_normals_test.cpp, 100k normals each, exact decode;
// orthographic / concentric): within 60° of vertical max 0.48° / 0.47°, mean 0.20° / 0.19°;
// uniform hemisphere max 5.0° / 5.1° (both at the horizon), mean 0.34° / 0.52° — the
// concentric map's outermost texel centres sit at zenith 84.9°, so steeper normals round to
// them, while orthographic rim texels straddle the circle. Through the RGBA8 texture add
// ≤ 0.35° (max 0.72° / 0.80° within 60°).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace ridge::lod {

enum class HemisphereMap : int {
    Orthographic = 0, // shaders/geomorph_common.glsl: GEOMORPH_MAP_ORTHOGRAPHIC
    Concentric = 1,   // GEOMORPH_MAP_CONCENTRIC
};

inline constexpr int kHemisphereTextureSize = 256;

struct NormalIndex {
    uint8_t u = 0; // texture column
    uint8_t v = 0; // texture row
};

// The texel whose decoded normal is closest in angle to `normal` (searched among the 3×3
// texels around the projected point). `normal` need not be unit length; throws ridge::Error
// unless it is finite, non-zero and has z >= 0 (terrain normals never point down).
NormalIndex encodeHemisphereNormal(HemisphereMap map, glm::vec3 normal);

// The unit normal of texel (u, v)'s centre, computed in double and rounded to float.
glm::vec3 decodeHemisphereNormal(HemisphereMap map, uint8_t u, uint8_t v);

// The 256×256 RGBA8 texture (GL_RGBA8, unsigned normalized) the shaders sample: texel (u, v)
// at byte 4·(v·256 + u), RGB = round(255·(n + 1)/2) of decodeHemisphereNormal(u, v), A = 255.
// Shaders decode n = normalize(2·rgb − 1) (the renormalisation also undoes linear filtering's
// shortening). 8-bit channels add up to ~0.3° to the index's own error.
std::vector<uint8_t> buildHemisphereNormalTexture(HemisphereMap map);

} // namespace ridge::lod
