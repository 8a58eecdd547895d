// Geomorph targets, morph factor, block layout and the three vertex packers; see geomorph.h.
#include "ridge/lod/geomorph.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace ridge::lod {
namespace {

void checkQuadrant(const char* name, int q)
{
    if (q != 0 && q != 1)
        throw Error(std::string(name) + " is " + std::to_string(q) + ": must be 0 or 1");
}

void checkNotNull(const void* p, const char* name)
{
    if (p == nullptr)
        throw Error(std::string(name) + " is null");
}

void checkFrame(const GeomorphFrame& frame)
{
    checkParameter("frame.scale", frame.scale, ValueRange::any());
    if (frame.scale == 0.0)
        throw Error("frame.scale is 0: must be a finite number other than 0");
    checkParameter("frame.offset", frame.offset, ValueRange::any());
    checkParameter("frame.cell_x", frame.cell_x, ValueRange::positive());
    checkParameter("frame.cell_y", frame.cell_y, ValueRange::positive());
}

void checkPatch(const GeomorphPatchData& patch, GeomorphShading shading)
{
    checkGeomorphPatchSize(patch.n);
    checkNotNull(patch.codes, "patch.codes");
    checkNotNull(patch.target, "patch.target");
    if (shading == GeomorphShading::Lit)
        checkNotNull(patch.normals, "patch.normals (needed in Lit mode)");
    // Targets come from targetHeights() and are codes; anything else (NaN, out of range)
    // would silently become a wild vertex, so one pass refuses it here.
    const size_t samples = size_t(patch.n) * size_t(patch.n);
    for (size_t s = 0; s < samples; ++s)
        if (!(patch.target[s] >= 0.0 && patch.target[s] <= 65535.0))
            throw Error("patch.target[" + std::to_string(s) + "] is " +
                        formatNumber(patch.target[s]) + ": must be a code in [0, 65535]");
}

// The parent samples whose mean is the target of child sample (i, j): the same sample twice
// at even positions, an edge's ends, or the diagonal b–c of a parent cell. Every target is
// one of these means, which is what makes targetHeights exact and targetCodes ½-code close.
struct TargetPair {
    size_t first, second;
};

TargetPair targetPair(int n, int qx, int qy, int i, int j)
{
    const int m = (n - 1) / 2;
    const int x0 = qx * m + i / 2, y0 = qy * m + j / 2; // parent sample at or before (i/2, j/2)
    const int x1 = x0 + (i & 1), y1 = y0 + (j & 1);
    auto at = [n](int x, int y) { return size_t(y) * size_t(n) + size_t(x); };
    if ((i & 1) && (j & 1))
        return {at(x1, y0), at(x0, y1)}; // cell centre: on the diagonal b = (x+1, y), c = (x, y+1)
    return {at(x0, y0), at(x1, y1)};     // a sample (both even) or an edge midpoint
}

template <typename Write>
void forEachTarget(const uint16_t* parent_codes, int n, int qx, int qy, Write write)
{
    checkGeomorphPatchSize(n);
    checkQuadrant("qx", qx);
    checkQuadrant("qy", qy);
    checkNotNull(parent_codes, "parent_codes");
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const TargetPair p = targetPair(n, qx, qy, i, j);
            write(size_t(j) * size_t(n) + size_t(i), parent_codes[p.first], parent_codes[p.second]);
        }
}

// Ties up, as targetCodes documents; a + b + 1 <= 131071 cannot overflow.
uint16_t roundedMean(uint32_t a, uint32_t b)
{
    return uint16_t((a + b + 1) / 2);
}

// A target in codes (checked in [0, 65535] by checkPatch) rounded the way targetCodes()
// rounds: exact targets are k or k + ½, and k + ½ goes up.
uint16_t roundTargetCode(double target)
{
    return uint16_t(std::min(std::floor(target + 0.5), 65535.0));
}

// Calls visit(vertex, i, j, bx, by) for every vertex in vertex-buffer order.
template <typename Visit> void forEachVertex(int n, Visit visit)
{
    const int b = geomorphBlockCells(n), blocks = geomorphBlocksPerSide(n);
    size_t vertex = 0;
    for (int block_j = 0; block_j < blocks; ++block_j)
        for (int block_i = 0; block_i < blocks; ++block_i)
            for (int by = 0; by <= b; ++by)
                for (int bx = 0; bx <= b; ++bx)
                    visit(vertex++, block_i * b + bx, block_j * b + by, bx, by);
}

void checkShading(GeomorphShading shading)
{
    if (shading != GeomorphShading::ColourOnly && shading != GeomorphShading::Lit)
        throw Error("shading is not a GeomorphShading value");
}

} // namespace

void checkGeomorphPatchSize(int n)
{
    const bool power_plus_one = n >= 5 && n <= 4097 && ((n - 1) & (n - 2)) == 0;
    if (!power_plus_one)
        throw Error("patch size n is " + std::to_string(n) +
                    ": must be 2^k + 1 with 5 <= n <= 4097");
}

void targetHeights(const uint16_t* parent_codes, int n, int qx, int qy, double* out)
{
    checkNotNull(out, "out");
    forEachTarget(parent_codes, n, qx, qy, [out](size_t k, uint16_t a, uint16_t b) {
        out[k] = (double(a) + double(b)) * 0.5;
    });
}

void targetCodes(const uint16_t* parent_codes, int n, int qx, int qy, uint16_t* out)
{
    checkNotNull(out, "out");
    forEachTarget(parent_codes, n, qx, qy,
                  [out](size_t k, uint16_t a, uint16_t b) { out[k] = roundedMean(a, b); });
}

double morphFactor(double own_screen_error, double parent_screen_error, double epsilon)
{
    checkParameter("epsilon", epsilon, ValueRange::positive());
    // `!(x >= 0)` refuses NaN as well as negatives; +inf is a valid screen error.
    for (const auto& [name, value] : {std::pair{"own_screen_error", own_screen_error},
                                      std::pair{"parent_screen_error", parent_screen_error}})
        if (!(value >= 0.0))
            throw Error(std::string(name) + " is " + formatNumber(value) +
                        ": must be a number >= 0 (inf allowed)");
    if (parent_screen_error <= epsilon)
        return 1.0; // the parent's shape already meets ε: t = 1 is the largest admissible
    if (own_screen_error >= epsilon)
        return 0.0; // even the own shape misses ε: the patch should be refined; 0 is closest
    // s_own < ε < s_parent, so the denominator is > 0; an infinite s_parent gives 0.
    const double t = (epsilon - own_screen_error) / (parent_screen_error - own_screen_error);
    return std::clamp(t, 0.0, 1.0);
}

int geomorphBlockCells(int n)
{
    checkGeomorphPatchSize(n);
    return std::min(n - 1, kGeomorphMaxBlockCells);
}

int geomorphBlocksPerSide(int n)
{
    return (n - 1) / geomorphBlockCells(n);
}

size_t geomorphVertexCount(int n)
{
    const size_t blocks = size_t(geomorphBlocksPerSide(n));
    const size_t side = size_t(geomorphBlockCells(n)) + 1;
    return blocks * blocks * side * side;
}

size_t geomorphBlockIndexCount(int block_cells)
{
    checkParameter("block_cells", int64_t(block_cells), 1, kGeomorphMaxBlockCells);
    return 6 * size_t(block_cells) * size_t(block_cells);
}

void buildGeomorphBlockIndices(int block_cells, uint16_t* out)
{
    geomorphBlockIndexCount(block_cells); // checks block_cells
    checkNotNull(out, "out");
    const int side = block_cells + 1; // (129)² = 16641 vertices: 16-bit indices suffice
    size_t k = 0;
    for (int y = 0; y < block_cells; ++y)
        for (int x = 0; x < block_cells; ++x) {
            const auto a = uint16_t(y * side + x), b = uint16_t(a + 1);
            const auto c = uint16_t(a + side), d = uint16_t(c + 1);
            for (uint16_t v : {a, b, c, b, d, c})
                out[k++] = v;
        }
}

int geomorphVertexBytes(GeomorphLayout layout, GeomorphShading shading)
{
    checkShading(shading);
    const bool lit = shading == GeomorphShading::Lit;
    switch (layout) {
    case GeomorphLayout::Standard:
        return lit ? int(sizeof(StandardVertex)) : int(offsetof(StandardVertex, nx));
    case GeomorphLayout::FloatMorph:
        return lit ? int(sizeof(FloatMorphVertex)) : int(offsetof(FloatMorphVertex, nx));
    case GeomorphLayout::Compact:
        return lit ? int(sizeof(CompactVertex)) : int(offsetof(CompactVertex, normal_u));
    }
    throw Error("layout is not a GeomorphLayout value");
}

double geomorphBytesPerSample(GeomorphLayout layout, GeomorphShading shading, int n)
{
    const double vertices = double(geomorphVertexCount(n));
    double bytes = vertices * geomorphVertexBytes(layout, shading);
    if (layout == GeomorphLayout::Compact) {
        const double blocks = geomorphBlocksPerSide(n);
        bytes += blocks * blocks * double(sizeof(CompactBlock));
    }
    return bytes / (double(n) * double(n));
}

float geomorphMetres(const GeomorphFrame& frame, double code)
{
    // Three roundings, the shader's: float uniforms, then a correctly rounded * and +.
    const float scale = float(frame.scale), offset = float(frame.offset);
    const float product = scale * float(code);
    return offset + product;
}

void patchNormals(const uint16_t* codes, int n, const GeomorphFrame& frame, float* out)
{
    checkGeomorphPatchSize(n);
    checkFrame(frame);
    checkNotNull(codes, "codes");
    checkNotNull(out, "out");
    auto code = [&](int i, int j) { return double(codes[size_t(j) * size_t(n) + size_t(i)]); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            // Central where both neighbours exist, one-sided at the border.
            const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, n - 1);
            const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, n - 1);
            const double dz_di = frame.scale * (code(i1, j) - code(i0, j)) / (i1 - i0);
            const double dz_dj = frame.scale * (code(i, j1) - code(i, j0)) / (j1 - j0);
            // x = i·cell_x, y = −j·cell_y: dz/dx = dz_di/cell_x, dz/dy = −dz_dj/cell_y.
            const double nx = -dz_di / frame.cell_x, ny = dz_dj / frame.cell_y;
            const double length = std::sqrt(nx * nx + ny * ny + 1.0);
            float* o = out + 3 * (size_t(j) * size_t(n) + size_t(i));
            o[0] = float(nx / length), o[1] = float(ny / length), o[2] = float(1.0 / length);
        }
}

void packStandard(const GeomorphPatchData& patch, const GeomorphFrame& frame, double t,
                  GeomorphShading shading, void* out)
{
    checkShading(shading);
    checkPatch(patch, shading);
    checkFrame(frame);
    checkParameter("t", t, ValueRange::closed(0.0, 1.0));
    checkNotNull(out, "out");
    const size_t stride = size_t(geomorphVertexBytes(GeomorphLayout::Standard, shading));
    const int n = patch.n;
    const float tf = float(t), cell_x = float(frame.cell_x), cell_y = float(frame.cell_y);
    auto* bytes = static_cast<unsigned char*>(out);
    forEachVertex(n, [&](size_t vertex, int i, int j, int, int) {
        const size_t s = size_t(j) * size_t(n) + size_t(i);
        StandardVertex v{};
        v.x = float(i) * cell_x;
        v.y = -(float(j) * cell_y);
        v.z = morphHeight(geomorphMetres(frame, patch.codes[s]),
                          geomorphMetres(frame, patch.target[s]), tf);
        if (shading == GeomorphShading::Lit)
            v.nx = patch.normals[3 * s], v.ny = patch.normals[3 * s + 1],
            v.nz = patch.normals[3 * s + 2];
        std::memcpy(bytes + vertex * stride, &v, stride);
    });
}

void packFloatMorph(const GeomorphPatchData& patch, const GeomorphFrame& frame,
                    GeomorphShading shading, void* out)
{
    checkShading(shading);
    checkPatch(patch, shading);
    checkFrame(frame);
    checkNotNull(out, "out");
    const size_t stride = size_t(geomorphVertexBytes(GeomorphLayout::FloatMorph, shading));
    const int n = patch.n;
    const float cell_x = float(frame.cell_x), cell_y = float(frame.cell_y);
    auto* bytes = static_cast<unsigned char*>(out);
    forEachVertex(n, [&](size_t vertex, int i, int j, int, int) {
        const size_t s = size_t(j) * size_t(n) + size_t(i);
        FloatMorphVertex v{};
        v.x = float(i) * cell_x;
        v.y = -(float(j) * cell_y);
        v.z = geomorphMetres(frame, patch.codes[s]);
        v.target_z = geomorphMetres(frame, patch.target[s]);
        if (shading == GeomorphShading::Lit)
            v.nx = patch.normals[3 * s], v.ny = patch.normals[3 * s + 1],
            v.nz = patch.normals[3 * s + 2];
        std::memcpy(bytes + vertex * stride, &v, stride);
    });
}

void packCompact(const GeomorphPatchData& patch, HemisphereMap map, GeomorphShading shading,
                 void* out)
{
    checkShading(shading);
    checkPatch(patch, shading);
    checkNotNull(out, "out");
    if (map != HemisphereMap::Orthographic && map != HemisphereMap::Concentric)
        throw Error("map is not a HemisphereMap value");
    const size_t stride = size_t(geomorphVertexBytes(GeomorphLayout::Compact, shading));
    const int n = patch.n;
    auto* bytes = static_cast<unsigned char*>(out);
    forEachVertex(n, [&](size_t vertex, int i, int j, int bx, int by) {
        const size_t s = size_t(j) * size_t(n) + size_t(i);
        CompactVertex v{};
        v.bx = uint8_t(bx), v.by = uint8_t(by);
        v.height = patch.codes[s];
        v.target = roundTargetCode(patch.target[s]);
        if (shading == GeomorphShading::Lit) {
            const float* nrm = patch.normals + 3 * s;
            const NormalIndex index = encodeHemisphereNormal(map, {nrm[0], nrm[1], nrm[2]});
            v.normal_u = index.u, v.normal_v = index.v;
        }
        std::memcpy(bytes + vertex * stride, &v, stride);
    });
}

void buildCompactBlocks(int n, int32_t patch_index, CompactBlock* out)
{
    const int b = geomorphBlockCells(n), blocks = geomorphBlocksPerSide(n);
    checkNotNull(out, "out");
    size_t k = 0;
    for (int block_j = 0; block_j < blocks; ++block_j)
        for (int block_i = 0; block_i < blocks; ++block_i)
            out[k++] = CompactBlock{block_i * b, block_j * b, patch_index, b};
}

} // namespace ridge::lod
