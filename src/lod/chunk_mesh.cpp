#include "ridge/lod/chunk_mesh.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>

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
    ChunkBuilder(const uint16_t* codes, int n) : codes_(codes), n_(n) {}

    double height(Point p) const { return codes_[size_t(p.y) * n_ + p.x]; }
    uint32_t vertex(Point p) const { return uint32_t(p.y) * uint32_t(n_) + uint32_t(p.x); }

    // Worst |sample − plane of t| over the samples inside t (its border included).
    double deviation(const Triangle& t) const
    {
        const Point p0 = t.apex, p1 = t.left, p2 = t.right;
        const int64_t area2 = cross(p0, p1, p2);
        const double h0 = height(p0), h1 = height(p1), h2 = height(p2);
        const int x0 = std::min({p0.x, p1.x, p2.x}), x1 = std::max({p0.x, p1.x, p2.x});
        const int y0 = std::min({p0.y, p1.y, p2.y}), y1 = std::max({p0.y, p1.y, p2.y});
        double worst = 0.0;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const Point p{x, y};
                // Edge functions, each zero on the edge opposite one vertex: barycentrics
                // times area2.
                const int64_t w0 = cross(p1, p2, p), w1 = cross(p2, p0, p), w2 = cross(p0, p1, p);
                const bool inside =
                    area2 > 0 ? (w0 >= 0 && w1 >= 0 && w2 >= 0) : (w0 <= 0 && w1 <= 0 && w2 <= 0);
                if (!inside)
                    continue;
                const double plane =
                    (double(w0) * h0 + double(w1) * h1 + double(w2) * h2) / double(area2);
                worst = std::max(worst, std::abs(height(p) - plane));
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
                em = std::max(em, deviation(t));
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
        out.max_deviation = std::max(out.max_deviation, deviation(t));
    }

  private:
    const uint16_t* codes_;
    int n_;
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
    const int c = n - 1;
    if (c < 1 || (c & (c - 1)) != 0)
        throw Error("chunk mesh: patch size " + std::to_string(n) + " is not 2^k + 1");
    if (!(tolerance >= 0.0))
        throw Error("chunk mesh: the tolerance must be >= 0");
    ChunkBuilder builder(codes, n);
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
