#pragma once
// The GL-free core of the `geomorph` LOD scheme (Ma, Sun & Song, "Accelerate terrain rendering
// using programmable graphics hardware", JATIT 2013): every patch of the quadtree is drawn as
// its full regular grid, and its heights morph towards its parent's surface so that switching
// between levels never pops. The paper's point is where the morph happens and what it costs on
// the bus; the three vertex layouts it compares are here, with their packers:
//
//   (a) StandardVertex:   CPU morph, positions re-sent every frame     12 B colour-only, 24 B lit
//   (b) FloatMorphVertex: GPU morph, own and target heights as floats  16 B, 28 B
//   (c) CompactVertex:    GPU morph, block coordinates, 16-bit codes,
//                         normal as a hemisphere-texture index          6 B,  8 B
//
// (The paper's tables add 3 B of colour per sample; ridge colours by height in the shader.)
//
// Grid and triangulation. A patch has n×n samples, n = 2^k + 1 (5..4097), row-major, sample
// (i, j) at column i, row j. Cell (i, j) has corners a = (i, j), b = (i+1, j), c = (i, j+1),
// d = (i+1, j+1) and is split along the diagonal b–c into triangles (a, b, c) and (b, d, c),
// counter-clockwise in (i, j) (as ChunkMesh's). The same rule at every level makes every child
// triangle lie inside one parent triangle: the parent diagonal of parent cell (I, J) runs
// through child cells (2I+1, 2J) and (2I, 2J+1) exactly along their own b–c diagonals.
//
// Target heights. A child patch (level l) in quadrant (qx, qy) of its parent covers parent
// samples [qx·m, qx·m + m] × [qy·m, qy·m + m], m = (n − 1)/2; child sample (i, j) lies at
// parent position (qx·m + i/2, qy·m + j/2). Its target is the parent's drawn surface there:
//   i, j even: the parent sample;  one odd: the mean of the two parent samples of that edge;
//   both odd: the centre of a parent cell, on its diagonal b–c: the mean of b and c.
// A child at morph factor 1 therefore draws exactly its parent's surface.
//
// Morph. h_t = (1 − t)·h_own + t·h_target per sample (morphHeight). t comes from morphFactor.
//
// Positions. Patch-local metres in ridge's terrain frame (x east, y north, z up; rows grow
// south): sample (i, j) is at x = i·cell_x, y = −j·cell_y, z = offset + scale·code, with
// cell_x, cell_y the patch's cell size in metres (step · spacing). The renderer adds the
// patch's origin (camera-relative) per draw, e.g. in its model matrix, as chunk.vert does.
//
// Blocks and vertex order (all three layouts). A patch is cut into B×B blocks of b ≤ 128 cells
// per side (geomorphBlockCells), so in-block coordinates 0..b fit one byte. Vertex buffers hold
// the blocks in row-major block order, each block's (b+1)² vertices row-major; samples on block
// borders are repeated in both blocks ((b+1)²/b² − 1 = 1.6% more vertices at b = 128). One
// 16-bit index buffer (buildGeomorphBlockIndices) serves every block: draw block k with base
// vertex k·(b+1)².
//
// All functions are pure and thread-safe; outputs are caller-owned buffers sized by the
// *Count/*Bytes helpers. Invalid arguments throw ridge::Error naming the parameter.
#include "ridge/lod/hemisphere_normals.h"

#include <cstddef>
#include <cstdint>

namespace ridge::lod {

// ---- Target heights ---------------------------------------------------------------------

// Throws ridge::Error unless n = 2^k + 1 with 5 <= n <= 4097.
void checkGeomorphPatchSize(int n);

// The n×n target heights of child quadrant (qx, qy) ∈ {0,1}² of the n×n parent
// `parent_codes`, in codes (exact: integers or halves), row-major into `out` (n² doubles).
void targetHeights(const uint16_t* parent_codes, int n, int qx, int qy, double* out);

// The same rounded to the nearest code, ties up ((a + b + 1) / 2): at most ½ code off the
// exact target, 0 at even positions. What CompactVertex::target carries.
void targetCodes(const uint16_t* parent_codes, int n, int qx, int qy, uint16_t* out);

// ---- Morph factor -----------------------------------------------------------------------

// The largest t ∈ [0, 1] with (1 − t)·s_own + t·s_parent <= ε:
//   1 when s_parent <= ε;  else 0 when s_own >= ε;  else (ε − s_own)/(s_parent − s_own).
// s_own, s_parent: screen-space errors (pixels, screen_space_error()) of the patch and of its
// parent; ε: the selection threshold (pixels).
//
// Why it cannot pop. The quadtree draws a patch while s_own < ε <= s_parent (roughly: while
// its parent is too coarse and it is not). A patch appears when s_parent rises past ε, where
// t = 1: it starts in exactly its parent's shape (see "Target heights"). It is replaced by
// its children when s_own rises past ε, where t = 0: it ends in its own shape, which is each
// child's parent surface, where the children start (their t is 1 as their s_parent = s_own
// >= ε). t is continuous in s_own, s_parent in between, so the surface never jumps.
// Why it keeps the bound. h_t − h_finest = (1−t)(h_own − h_finest) + t(h_target − h_finest),
// so |h_t − h_finest| <= (1−t)·Err_own + t·Err_parent, whose projection is
// (1−t)·s_own + t·s_parent <= ε at every state.
//
// Throws ridge::Error unless ε is finite and > 0 and s_own, s_parent are >= 0 (NaN refused;
// +inf accepted: screen_space_error() returns it when the camera is inside the box, and an
// infinite s_parent gives t = 0, an infinite s_own t = 0 as well unless s_parent <= ε).
double morphFactor(double own_screen_error, double parent_screen_error, double epsilon);

// h·(1 − t) + target·t in float, the operations of GLSL's mix() in that order; the twin of
// geomorphMix() in shaders/geomorph_common.glsl (which pins them with `precise`), so CPU and
// GPU morphs agree bit for bit on IEEE hardware. No check of t: this is the inner loop.
inline float morphHeight(float h, float target, float t)
{
    const float keep = 1.0f - t;
    const float own_part = h * keep;
    const float target_part = target * t;
    return own_part + target_part;
}

// ---- Blocks -----------------------------------------------------------------------------

inline constexpr int kGeomorphMaxBlockCells = 128;

// Cells per block side, b = min(n − 1, 128); blocks per side, (n − 1)/b. Both check n.
int geomorphBlockCells(int n);
int geomorphBlocksPerSide(int n);
// Vertices of a patch in every layout: blocks² · (b + 1)².
size_t geomorphVertexCount(int n);

// 6·b² indices of one block's (b+1)² vertices (vertex bx + by·(b+1)): for each cell
// (bx, by) row-major, triangles (a, b, c) and (b, d, c) as above. b in 1..128.
size_t geomorphBlockIndexCount(int block_cells);
void buildGeomorphBlockIndices(int block_cells, uint16_t* out);

// ---- Vertex layouts ---------------------------------------------------------------------

enum class GeomorphLayout { Standard, FloatMorph, Compact };
enum class GeomorphShading {
    ColourOnly, // positions (and targets) only: each vertex is the struct's prefix before
                // nx/normal_u
    Lit,        // the whole struct
};

// (a) The standard OpenGL layout: the morphed position, computed on the CPU every frame.
struct StandardVertex {
    float x, y, z;    // patch-local metres, z morphed
    float nx, ny, nz; // unit normal
};
static_assert(sizeof(StandardVertex) == 24 && offsetof(StandardVertex, nx) == 12);

// (b) GPU morph with floats: the shader computes z = morphHeight(z, target_z, t).
struct FloatMorphVertex {
    float x, y, z;    // patch-local metres, own height
    float target_z;   // metres, exact target (targetHeights) rounded to float
    float nx, ny, nz; // unit normal
};
static_assert(sizeof(FloatMorphVertex) == 28 && offsetof(FloatMorphVertex, nx) == 16);

// (c) The paper's compact vertex. The sample is block origin + (bx, by); heights are codes
// (metres = offset + scale·code in the shader); the normal is texel (normal_u, normal_v) of
// the hemisphere normal texture (hemisphere_normals.h), which the fragment stage may sample
// with linear filtering at the interpolated index.
struct CompactVertex {
    uint8_t bx, by;             // in-block sample coordinates, 0..b
    uint16_t height;            // own code
    uint16_t target;            // target code (targetCodes: <= ½ code off the exact target)
    uint8_t normal_u, normal_v; // hemisphere texture texel
};
static_assert(sizeof(CompactVertex) == 8 && offsetof(CompactVertex, normal_u) == 6);

// What the compact layout sends once per block instead of per vertex (the paper's "block
// identifier"): upload as `uniform ivec4 u_geomorph_block` before each block's draw, or as
// one std430 `ivec4` per block indexed by gl_DrawID under multi-draw (geomorph_common.glsl
// reads the ivec4 either way). 16 B, i.e. < 0.001 B per vertex at b = 128.
struct CompactBlock {
    int32_t origin_i, origin_j; // patch sample of in-block (0, 0): multiples of b
    int32_t patch;              // the renderer's patch-instance index (not interpreted here)
    int32_t block_cells;        // b
};
static_assert(sizeof(CompactBlock) == 16);

// Bytes per vertex as uploaded: 12/24, 16/28, 6/8 (colour-only/lit).
int geomorphVertexBytes(GeomorphLayout layout, GeomorphShading shading);
// Bytes per patch sample for the benchmark tables: vertex bytes × repeated block-border
// vertices, plus (compact) the CompactBlock records, over the n² samples of an n×n patch.
double geomorphBytesPerSample(GeomorphLayout layout, GeomorphShading shading, int n);

// ---- Packing ----------------------------------------------------------------------------

// What the packers read. `target` are the targetHeights() of this patch within its parent
// (for the root, which has no parent, pass its own codes converted: t is then irrelevant).
struct GeomorphPatchData {
    int n = 0;
    const uint16_t* codes = nullptr; // n² own codes
    const double* target = nullptr;  // n² target heights in codes (targetHeights)
    const float* normals = nullptr;  // 3·n² unit normals (patchNormals); read in Lit mode only
};

// Code → metres and the cell size; see "Positions". scale, offset finite, scale ≠ 0;
// cell_x, cell_y finite and > 0.
struct GeomorphFrame {
    double scale = 1.0;  // metres per code (HeightQuantization::scale)
    double offset = 0.0; // metres of code 0 (HeightQuantization::offset, maybe camera-relative)
    double cell_x = 1.0; // metres per patch cell east (step · spacing_x)
    double cell_y = 1.0; // metres per patch cell south (step · spacing_y)
};

// Height in metres of code (or target) `code` as float, offset + scale·code rounded like the
// shader's geomorphMetres(): float(offset) + float(scale)·float(code), each step rounded.
float geomorphMetres(const GeomorphFrame& frame, double code);

// Unit normals of every sample, 3 floats each into `out` (3·n² floats): central differences
// of the heights in metres, one-sided at the patch border (a seam between patches may then
// shade slightly differently; patch_normals.comp reads neighbours, this core does not).
// n = normalize(−dz/dx, −dz/dy, 1) in the terrain frame. Computed from the patch's own heights
// and used unchanged at every t (no layout morphs normals: the compact one cannot).
void patchNormals(const uint16_t* codes, int n, const GeomorphFrame& frame, float* out);

// The packers write geomorphVertexCount(n) vertices of geomorphVertexBytes(layout, shading)
// bytes each, tightly, into `out` (in Lit mode exactly an array of the struct). Throw
// ridge::Error for a bad n, frame or t (t must be finite in [0, 1]), or a null input needed.
void packStandard(const GeomorphPatchData& patch, const GeomorphFrame& frame, double t,
                  GeomorphShading shading, void* out);
void packFloatMorph(const GeomorphPatchData& patch, const GeomorphFrame& frame,
                    GeomorphShading shading, void* out);
// Heights stay codes (the frame's code → metres goes to the shader as uniforms); targets are
// rounded like targetCodes(); normals encoded with encodeHemisphereNormal(map).
void packCompact(const GeomorphPatchData& patch, HemisphereMap map, GeomorphShading shading,
                 void* out);
// The blocks² CompactBlock records, in vertex-buffer order.
void buildCompactBlocks(int n, int32_t patch_index, CompactBlock* out);

} // namespace ridge::lod
