#include "ridge/pyramid/tessellation_block_errors.h"

#include "ridge/core/target_clones.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace ridge {

int TessellationBlockLayout::levels() const
{
    int d = 0;
    while ((2 << d) <= block_cells && d < 4)
        ++d;
    return d;
}

bool TessellationBlockLayout::valid() const
{
    const int cells = patch_size - 1;
    const bool pow2 = block_cells >= 2 && (block_cells & (block_cells - 1)) == 0;
    return pow2 && cells > 0 && block_cells <= cells && cells % block_cells == 0;
}

namespace {

// Deviation of the samples of one patch row from the triangulations simplified by 2^d.
//
// With a simplified cell's corners a (0,0), b (st,0), c (0,st), e (st,st), k = a + e - b - c
// and the plane P(u,v) = a*st + (b-a)*u + (c-a)*v through a, b, c (values scaled by st):
//   diagonal a-e:  P + k * min(u, v)
//   diagonal b-c:  P + k * max(0, u + v - st)
//   bilinear:      P + k * u * v / st, which lies between the two triangulations, so the
//                  worst of the three is always reached by a triangulation.
// A sample on a cell edge gets the same value from either cell (both are linear along the
// edge), so every sample is evaluated once, with the cell to its lower right (clamped).
// Integer and exact: every term stays far below 2^31 for codes < 2^16 and st <= 16.
struct RowCorners {
    std::vector<int> a, b, c, e, u; // per sample x: its cell's corners and offset in the cell
};

void gatherCorners(const uint16_t* patch, int n, int cell_y, int d, RowCorners& rc)
{
    const int st = 1 << d;
    const int last_cell = n - 1 - st;
    for (int x = 0; x < n; ++x) {
        const int cx = std::min((x >> d) << d, last_cell);
        rc.u[x] = x - cx;
        rc.a[x] = patch[cell_y * n + cx];
        rc.b[x] = patch[cell_y * n + cx + st];
        rc.c[x] = patch[(cell_y + st) * n + cx];
        rc.e[x] = patch[(cell_y + st) * n + cx + st];
    }
}

// Hot loop: cloned for AVX2 (packed 32-bit min/max/abs, absent from baseline SSE2) with a
// portable default; the loader picks the clone for the running CPU.
RIDGE_TARGET_CLONES
void rowDeviation(const uint16_t* row, int n, int v, int st, const RowCorners& rc, int* dev)
{
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC ivdep
#endif
    for (int x = 0; x < n; ++x) {
        const int u = rc.u[x];
        const int k = rc.a[x] + rc.e[x] - rc.b[x] - rc.c[x];
        const int plane = rc.a[x] * st + (rc.b[x] - rc.a[x]) * u + (rc.c[x] - rc.a[x]) * v;
        const int h = row[x] * st;
        const int diag_ae = plane + k * std::min(u, v);
        const int diag_bc = plane + k * std::max(0, u + v - st);
        dev[x] = std::max(std::abs(h - diag_ae), std::abs(h - diag_bc));
    }
}

// Largest deviation within each block's columns [s*b, s*b + b] of one row.
RIDGE_TARGET_CLONES
void blockRowMax(const int* dev, int blocks, int b, int* out)
{
    for (int s = 0; s < blocks; ++s) {
        int m = dev[s * b + b];
        for (int x = 0; x < b; ++x)
            m = std::max(m, dev[s * b + x]);
        out[s] = m;
    }
}

} // namespace

void computeTessellationBlockErrors(const uint16_t* patch, const TessellationBlockLayout& layout,
                                    float* out)
{
    const int n = layout.patch_size;
    const int b = layout.block_cells;
    const int blocks = layout.blocksPerSide();
    const int levels = layout.levels();
    thread_local RowCorners rc;
    thread_local std::vector<int> dev, worst, row_max;
    for (auto* v : {&rc.a, &rc.b, &rc.c, &rc.e, &rc.u, &dev})
        v->resize(n);
    row_max.resize(blocks);
    for (int d = 1; d <= levels; ++d) {
        const int st = 1 << d;
        worst.assign(static_cast<size_t>(blocks) * blocks, 0);
        for (int cell_y = 0; cell_y < n - 1; cell_y += st) {
            gatherCorners(patch, n, cell_y, d, rc);
            for (int v = cell_y == 0 ? 0 : 1; v <= st; ++v) {
                const int y = cell_y + v;
                rowDeviation(patch + static_cast<size_t>(y) * n, n, v, st, rc, dev.data());
                // Row y belongs to block row y/b and, on a block border, to the one above.
                const int r_hi = std::min(y / b, blocks - 1);
                const int r_lo = (y % b == 0 && y > 0) ? y / b - 1 : r_hi;
                blockRowMax(dev.data(), blocks, b, row_max.data());
                for (int r = r_lo; r <= r_hi; ++r)
                    for (int s = 0; s < blocks; ++s)
                        worst[r * blocks + s] = std::max(worst[r * blocks + s], row_max[s]);
            }
        }
        for (int i = 0; i < blocks * blocks; ++i)
            out[static_cast<size_t>(i) * levels + d - 1] =
                static_cast<float>(double(worst[i]) / st);
    }
}

} // namespace ridge
