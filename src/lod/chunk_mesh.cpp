#include "ridge/lod/chunk_mesh.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace ridge::lod {

namespace {

struct Point {
    int x, y;
};

// A right triangle of the 4-8 hierarchy: right angle at `apex`, hypotenuse left–right.
struct Triangle {
    Point apex, left, right;

    Point midpoint() const { return {(left.x + right.x) / 2, (left.y + right.y) / 2}; }
    // The finest triangles (half cells) have their hypotenuse midpoint between samples.
    bool leaf() const { return ((left.x + right.x) | (left.y + right.y)) & 1; }
    // Split at the hypotenuse midpoint: two right triangles with their right angle there.
    std::array<Triangle, 2> children() const
    {
        const Point m = midpoint();
        return {Triangle{m, apex, left}, Triangle{m, right, apex}};
    }
};

int64_t cross(Point o, Point a, Point b)
{
    return int64_t(a.x - o.x) * (b.y - o.y) - int64_t(a.y - o.y) * (b.x - o.x);
}

class ChunkBuilder {
  public:
    ChunkBuilder(const uint16_t* codes, int n, int valid_x, int valid_y, const ChunkSag& sag)
        : codes_(codes), n_(n), valid_x_(valid_x), valid_y_(valid_y), sag_(sag)
    {
    }

    // The globe's sag of a flat triangle as large as t (0 without a sag): what it adds to
    // the heights' deviation. Non-decreasing in the size, so E stays nested.
    double sagOf(const Triangle& t) const
    {
        if (!sag_)
            return 0.0;
        const int extent = std::max(
            std::max({t.apex.x, t.left.x, t.right.x}) - std::min({t.apex.x, t.left.x, t.right.x}),
            std::max({t.apex.y, t.left.y, t.right.y}) - std::min({t.apex.y, t.left.y, t.right.y}));
        return sag_(extent);
    }

    double height(Point p) const { return codes_[size_t(p.y) * n_ + p.x]; }
    uint32_t vertex(Point p) const { return uint32_t(p.y) * uint32_t(n_) + uint32_t(p.x); }

    // Worst |sample − plane of t| over the samples inside t (its border included). Row by
    // row: the triangles of a 4-8 mesh have horizontal, vertical and 45° edges only, so each
    // row's span is where its edges cross it, at integer x, and the plane is linear in x.
    double deviation(const Triangle& t) const
    {
        const int x0 = std::min({t.apex.x, t.left.x, t.right.x}),
                  x1 = std::max({t.apex.x, t.left.x, t.right.x});
        const int ymin = std::min({t.apex.y, t.left.y, t.right.y}),
                  ymax = std::max({t.apex.y, t.left.y, t.right.y});
        if ((x0 < valid_x_ && valid_x_ < x1) || (ymin < valid_y_ && valid_y_ < ymax))
            return std::numeric_limits<double>::infinity(); // crosses the valid extent's border
        if (x0 > valid_x_ || ymin > valid_y_)
            return 0.0; // wholly outside: clipped away
        // Half the triangles split into half cells: besides their corners they hold only
        // the hypotenuse midpoint (when it is a valid sample; the general scan clamps).
        const Point m = t.midpoint();
        if (!t.leaf() && std::abs(t.left.x - t.right.x) + std::abs(t.left.y - t.right.y) == 2 &&
            m.x <= valid_x_ && m.y <= valid_y_)
            return std::abs(height(m) - 0.5 * (height(t.left) + height(t.right)));
        const Point p[3] = {t.apex, t.left, t.right};
        const double h[3] = {height(p[0]), height(p[1]), height(p[2])};
        // The plane h = h0 + gx·(x − x0) + gy·(y − y0) through the three vertices.
        const double d1x = p[1].x - p[0].x, d1y = p[1].y - p[0].y;
        const double d2x = p[2].x - p[0].x, d2y = p[2].y - p[0].y;
        const double det = d1x * d2y - d2x * d1y;
        const double gx = ((h[1] - h[0]) * d2y - (h[2] - h[0]) * d1y) / det;
        const double gy = ((h[2] - h[0]) * d1x - (h[1] - h[0]) * d2x) / det;
        struct Edge {
            int y0, y1, x_at_y0, slope; // x = x_at_y0 + slope·(y − y0) on rows [y0, y1]
        };
        Edge edges[3];
        int count = 0, y0 = INT32_MAX, y1 = INT32_MIN;
        for (int i = 0; i < 3; ++i) {
            Point a = p[i], b = p[i == 2 ? 0 : i + 1];
            y0 = std::min(y0, a.y), y1 = std::max(y1, a.y);
            if (a.y == b.y)
                continue; // horizontal: its ends are on the other two edges
            if (b.y < a.y)
                std::swap(a, b);
            edges[count++] = {a.y, b.y, a.x, (b.x > a.x) - (b.x < a.x)}; // |dx| is 0 or dy
        }
        double worst = 0.0;
        for (int y = y0; y <= std::min(y1, valid_y_); ++y) {
            int lo = INT32_MAX, hi = INT32_MIN;
            for (int i = 0; i < count; ++i)
                if (y >= edges[i].y0 && y <= edges[i].y1) {
                    const int x = edges[i].x_at_y0 + edges[i].slope * (y - edges[i].y0);
                    lo = std::min(lo, x);
                    hi = std::max(hi, x);
                }
            const uint16_t* row = codes_ + size_t(y) * n_;
            const double plane_row = h[0] + gy * (y - p[0].y) - gx * p[0].x;
            for (int x = lo; x <= std::min(hi, valid_x_); ++x)
                worst = std::max(worst, std::abs(double(row[x]) - (plane_row + gx * x)));
        }
        return worst;
    }

    // E(m) for every hypotenuse midpoint m, nested: E(m) >= E of both children's midpoints
    // of each triangle m splits.
    std::vector<double> nestedErrors(const std::array<Triangle, 2>& roots) const
    {
        std::vector<std::vector<Triangle>> depths{{roots.begin(), roots.end()}};
        while (!depths.back().front().leaf()) {
            std::vector<Triangle> next;
            next.reserve(depths.back().size() * 2);
            for (const Triangle& t : depths.back())
                for (const Triangle& c : t.children())
                    next.push_back(c);
            depths.push_back(std::move(next));
        }
        std::vector<double> e(size_t(n_) * n_, 0.0);
        for (size_t d = depths.size() - 1; d-- > 0;) // leaves split nothing
            for (const Triangle& t : depths[d]) {
                double& em = e[vertex(t.midpoint())];
                em = std::max(em, deviation(t) + sagOf(t));
                for (const Triangle& c : t.children())
                    if (!c.leaf())
                        em = std::max(em, e[vertex(c.midpoint())]);
            }
        return e;
    }

    void emit(const Triangle& t, const std::vector<double>& e, double tolerance, ChunkMesh& out)
    {
        if (!t.leaf() && e[vertex(t.midpoint())] > tolerance) {
            for (const Triangle& c : t.children())
                emit(c, e, tolerance, out);
            return;
        }
        const bool ccw = cross(t.apex, t.left, t.right) > 0;
        out.indices.insert(out.indices.end(), {vertex(t.apex), vertex(ccw ? t.left : t.right),
                                               vertex(ccw ? t.right : t.left)});
        if (!t.leaf()) // a half cell holds only its corners
            out.max_deviation = std::max(out.max_deviation, deviation(t));
    }

  private:
    const uint16_t* codes_;
    int n_;
    int valid_x_, valid_y_; // samples beyond these are padding
    const ChunkSag& sag_;
};

// Sample k of the border ring (the order of shaders/chunk.vert's skirt feet).
Point ringSample(int k, int c)
{
    if (k < c)
        return {k, 0};
    if (k < 2 * c)
        return {c, k - c};
    if (k < 3 * c)
        return {c - (k - 2 * c), c};
    return {0, c - (k - 3 * c)};
}

} // namespace

ChunkMesh buildChunkMesh(const uint16_t* codes, int n, double tolerance)
{
    return buildChunkMesh(codes, n, tolerance, n - 1, n - 1);
}

ChunkMesh buildChunkMesh(const uint16_t* codes, int n, double tolerance, int valid_x, int valid_y,
                         const ChunkSag& sag)
{
    const int c = n - 1;
    if (c < 1 || (c & (c - 1)) != 0)
        throw Error("chunk mesh: patch size " + std::to_string(n) + " is not 2^k + 1");
    if (!(tolerance >= 0.0))
        throw Error("chunk mesh: the tolerance must be >= 0");
    if (valid_x < 0 || valid_x > c || valid_y < 0 || valid_y > c)
        throw Error("chunk mesh: the valid extent must lie within the patch");
    ChunkBuilder builder(codes, n, valid_x, valid_y, sag);
    const Point nw{0, 0}, ne{c, 0}, se{c, c}, sw{0, c};
    const std::array<Triangle, 2> roots{Triangle{ne, nw, se}, Triangle{sw, se, nw}};
    const std::vector<double> e = builder.nestedErrors(roots);

    ChunkMesh mesh;
    for (const Triangle& t : roots)
        builder.emit(t, e, tolerance, mesh);
    mesh.surface_indices = uint32_t(mesh.indices.size());

    // The skirt: a quad under each border edge of the mesh, between consecutive border
    // samples the surface uses (the corners always are).
    std::vector<bool> used(size_t(n) * n, false);
    for (const uint32_t v : mesh.indices)
        used[v] = true;
    std::vector<int> ring;
    for (int k = 0; k < 4 * c; ++k)
        if (used[builder.vertex(ringSample(k, c))])
            ring.push_back(k);
    const uint32_t feet = uint32_t(n) * uint32_t(n);
    for (size_t i = 0; i < ring.size(); ++i) {
        const int k0 = ring[i], k1 = ring[(i + 1) % ring.size()];
        const uint32_t t0 = builder.vertex(ringSample(k0, c)),
                       t1 = builder.vertex(ringSample(k1, c));
        mesh.indices.insert(mesh.indices.end(), {feet + uint32_t(k0), t0, t1, feet + uint32_t(k0),
                                                 t1, feet + uint32_t(k1)});
    }
    return mesh;
}

} // namespace ridge::lod
