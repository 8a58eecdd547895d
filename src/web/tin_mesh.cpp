#include "ridge/web/tin_mesh.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <string>
#include <utility>

namespace ridge::web {

namespace {

// In-circle determinants of grid points reach about 2^100 (see insideCircumcircle).
__extension__ typedef __int128 Int128;

// The bit budget. Grid line positions are integers in [0, 2^24] (kMaxPosition), so every
// coordinate difference below is at most 2^24 in magnitude, and:
//  - orientation: each product <= 2^48, their difference <= 2^49: exact in int64;
//  - in-circle: squared lengths and 2×2 minors <= 2^49, each term <= 2^98, the sum of three
//    < 2^100: exact in __int128 (127 bits);
//  - the scan's barycentric weights (orientations at samples, <= 2^49) and the sums that step
//    them from column to column (<= 2^50) are integers below 2^53: exact in doubles too.
constexpr int64_t kMaxPosition = int64_t(1) << 24;

// A vertex's position in the grid's real coordinates: x = xs[column], y = ys[row] (y grows
// SOUTH, like the row index).
struct Point {
    int64_t x, y;
};

// A sample's grid indices.
struct Cell {
    int64_t column, row;
};

// Twice the signed area of abc in (x, −y): positive when a, b, c turn counter-clockwise seen
// from above with north up, zero when they are collinear. Exact in int64 (see the budget).
int64_t orientation(Point a, Point b, Point c)
{
    return (b.y - a.y) * (c.x - a.x) - (b.x - a.x) * (c.y - a.y);
}

// Whether d lies strictly inside the circle through a, b, c (counter-clockwise): the sign of
// the classic 3×3 determinant in (x, −y). Exact in 128 bits (see the budget), so cocircular
// points (common on a grid) never flip back and forth.
bool insideCircumcircle(Point a, Point b, Point c, Point d)
{
    const int64_t adx = a.x - d.x, ady = d.y - a.y;
    const int64_t bdx = b.x - d.x, bdy = d.y - b.y;
    const int64_t cdx = c.x - d.x, cdy = d.y - c.y;
    const int64_t ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy,
                  cd = cdx * cdx + cdy * cdy;
    const Int128 det = Int128(ad) * (bdx * cdy - bdy * cdx) + Int128(bd) * (cdx * ady - cdy * adx) +
                       Int128(cd) * (adx * bdy - ady * bdx);
    return det > 0;
}

// The height num/den of the way from ha to hb (0 <= num <= den, both positions' differences in
// real coordinates, below 2^25: exact in doubles). The one formula for every point on a
// segment between two vertices: the 1-D border pass and both triangles beside an edge
// evaluate a sample on it identically, bit for bit, so the error the greedy passes measured is
// exactly the error buildTin reports. Ends are returned exactly.
double lerp(double ha, double hb, int64_t num, int64_t den)
{
    if (num == 0)
        return ha;
    if (num == den)
        return hb;
    return ha + (hb - ha) * double(num) / double(den);
}

// The height at s, a grid point on the edge uv: linear along the edge in real coordinates,
// read from its endpoint of lower row-major index (as the border pass reads a line: west to
// east, north to south; positions increase with the indices, so (y, x) orders them as (row,
// column) does), by x unless the edge is vertical. Both triangles beside an edge call this
// with the same two endpoints, whichever way round they hold them, so they agree on the edge
// bit for bit.
double edgeHeight(Point s, Point u, double hu, Point v, double hv)
{
    if (std::pair(v.y, v.x) < std::pair(u.y, u.x))
        std::swap(u, v), std::swap(hu, hv);
    int64_t along = s.x - u.x, length = v.x - u.x;
    if (length == 0)
        along = s.y - u.y, length = v.y - u.y;
    if (length < 0) // u north-east of v
        along = -along, length = -length;
    return lerp(hu, hv, along, length);
}

// The samples of one grid line (a border): count of them, `stride` apart from `first`, the
// i-th at position positions[i] along the line (xs for a row, ys for a column).
struct Line {
    const float* first;
    size_t stride;
    int64_t count;
    const int32_t* positions;

    double at(int64_t i) const { return first[size_t(i) * stride]; }
    int64_t position(int64_t i) const { return positions[i]; }
};

// The interior samples of `line` (indices 1..count−2, ascending) that the 1-D greedy insertion
// chooses, starting from its two ends, so that every sample lies within max_error of the
// polyline through the chosen ones (linear in the samples' positions along the line). The global
// greedy (insert the worst sample of the whole line, ties to the lowest index) chooses exactly the
// samples this recursion does: inserting a sample changes only its own segment, so each segment is
// split at its own worst sample (ties: lowest index) as long as that is beyond the bound, in
// whatever order.
std::vector<int64_t> simplifyLine(const Line& line, double max_error)
{
    std::vector<int64_t> chosen;
    std::vector<std::pair<int64_t, int64_t>> segments{{0, line.count - 1}};
    while (!segments.empty()) {
        const auto [i0, i1] = segments.back();
        segments.pop_back();
        const double h0 = line.at(i0), h1 = line.at(i1);
        const int64_t p0 = line.position(i0), length = line.position(i1) - p0;
        double worst = max_error;
        int64_t split = -1;
        for (int64_t i = i0 + 1; i < i1; ++i) {
            const double error = std::abs(line.at(i) - lerp(h0, h1, line.position(i) - p0, length));
            if (error > worst) // strict: the lowest index wins a tie
                worst = error, split = i;
        }
        if (split < 0)
            continue;
        chosen.push_back(split);
        segments.push_back({i0, split});
        segments.push_back({split, i1});
    }
    std::sort(chosen.begin(), chosen.end());
    return chosen;
}

// Half-edges: triangle t owns half-edges 3t, 3t+1, 3t+2; half-edge e runs from vertex
// corners[e] to corners[next(e)], and twins[e] is the opposite half-edge of the neighbour
// across it, or kHull on the rectangle's border.
constexpr int64_t kHull = -1;
size_t nextEdge(size_t e)
{
    return e % 3 == 2 ? e - 2 : e + 1;
}
size_t prevEdge(size_t e)
{
    return e % 3 == 0 ? e + 2 : e - 1;
}

// The worst sample a scan found: its |grid − mesh| and row-major index (error −1: none).
struct Candidate {
    double error = -1.0;
    size_t sample = 0;
};

// The triangles whose worst sample is beyond the bound, worst first: a binary max-heap of
// triangle ids that remembers where each sits, so a rescanned triangle moves or leaves in
// place (as delatin's queue does). The heap never holds stale entries, so it stays as small
// as the number of triangles still to refine.
class TriangleQueue {
  public:
    bool empty() const { return heap_.empty(); }
    size_t top() const { return heap_.front(); }
    const Candidate& candidate(size_t t) const { return keys_[t]; }

    // Queues t with candidate c, or moves it there if queued.
    void set(size_t t, const Candidate& c)
    {
        if (t >= position_.size()) {
            position_.resize(t + 1, kAbsent);
            keys_.resize(t + 1);
        }
        keys_[t] = c;
        size_t i = position_[t];
        if (i == kAbsent) {
            i = heap_.size();
            heap_.push_back(t);
            position_[t] = i;
        }
        siftDown(siftUp(i));
    }

    // Drops t if queued.
    void erase(size_t t)
    {
        if (t >= position_.size() || position_[t] == kAbsent)
            return;
        const size_t i = position_[t];
        position_[t] = kAbsent;
        const size_t last = heap_.back();
        heap_.pop_back();
        if (i == heap_.size())
            return; // t was the last leaf
        heap_[i] = last;
        position_[last] = i;
        siftDown(siftUp(i));
    }

  private:
    static constexpr size_t kAbsent = SIZE_MAX;

    // Whether triangle a pops before b: the larger error, then the lower sample index (the
    // deterministic tie-break), then the lower triangle (both sides of an edge may offer the
    // same sample on it; either inserts the same point).
    bool before(size_t a, size_t b) const
    {
        const Candidate &x = keys_[a], &y = keys_[b];
        if (x.error != y.error)
            return x.error > y.error;
        if (x.sample != y.sample)
            return x.sample < y.sample;
        return a < b;
    }

    void place(size_t i, size_t t)
    {
        heap_[i] = t;
        position_[t] = i;
    }

    size_t siftUp(size_t i)
    {
        const size_t t = heap_[i];
        while (i > 0 && before(t, heap_[(i - 1) / 2])) {
            place(i, heap_[(i - 1) / 2]);
            i = (i - 1) / 2;
        }
        place(i, t);
        return i;
    }

    void siftDown(size_t i)
    {
        const size_t t = heap_[i];
        for (;;) {
            size_t child = 2 * i + 1;
            if (child >= heap_.size())
                break;
            if (child + 1 < heap_.size() && before(heap_[child + 1], heap_[child]))
                ++child;
            if (!before(heap_[child], t))
                break;
            place(i, heap_[child]);
            i = child;
        }
        place(i, t);
    }

    std::vector<size_t> heap_;     // triangle ids, heap-ordered by before()
    std::vector<size_t> position_; // per triangle: its index in heap_, or kAbsent
    std::vector<Candidate> keys_;  // per triangle: its candidate while queued
};

// The samples a scan looks at: rows [row0, row1] × columns [column0, column1] (indices).
struct Window {
    int64_t row0, row1, column0, column1;
};

class TinBuilder {
  public:
    // The caller has checked the input: xs and ys strictly increasing in [0, kMaxPosition].
    TinBuilder(std::span<const float> heights, std::span<const int32_t> xs,
               std::span<const int32_t> ys, double max_error, double border_error)
        : heights_(heights), xs_(xs), ys_(ys), steady_until_(xs.size()), width_(int64_t(xs.size())),
          height_(int64_t(ys.size())), max_error_(max_error), border_error_(border_error)
    {
        // The median gap: the interior spacing of a tile cut from an archive, the only one
        // on a uniform grid.
        std::vector<int64_t> gaps(xs.size() - 1);
        for (size_t c = 0; c < gaps.size(); ++c)
            gaps[c] = int64_t(xs[c + 1]) - xs[c];
        std::nth_element(gaps.begin(), gaps.begin() + ptrdiff_t(gaps.size() / 2), gaps.end());
        common_gap_ = gaps[gaps.size() / 2];
        steady_until_.back() = width_ - 1;
        for (size_t c = xs.size() - 1; c-- > 0;)
            steady_until_[c] =
                int64_t(xs[c + 1]) - xs[c] == common_gap_ ? steady_until_[c + 1] : int64_t(c);
    }

    Tin build()
    {
        insertCorners();
        insertBorders();
        refineInterior();
        return output();
    }

  private:
    double sampleHeight(size_t sample) const { return heights_[sample]; }
    size_t sampleOf(Cell g) const { return size_t(g.row) * size_t(width_) + size_t(g.column); }
    Point pointOf(Cell g) const { return {xs_[size_t(g.column)], ys_[size_t(g.row)]}; }

    uint32_t addVertex(Cell g)
    {
        cells_.push_back(g);
        points_.push_back(pointOf(g));
        hull_start_.push_back(kHull);
        return uint32_t(points_.size() - 1);
    }

    size_t addTriangle()
    {
        corners_.resize(corners_.size() + 3);
        twins_.resize(twins_.size() + 3, kHull);
        dirty_flags_.push_back(false);
        return dirty_flags_.size() - 1;
    }

    // Joins half-edge e with `twin` (both ways); on the hull, remembers e as the hull edge
    // leaving its start vertex, which is how border insertion finds the edge to split.
    void link(size_t e, int64_t twin)
    {
        twins_[e] = twin;
        if (twin != kHull)
            twins_[size_t(twin)] = int64_t(e);
        else
            hull_start_[corners_[e]] = int64_t(e);
    }

    // Triangle t becomes (a, b, c) with the given twins across ab, bc, ca. Callers read every
    // twin they need before rewriting any triangle.
    void setTriangle(size_t t, uint32_t a, uint32_t b, uint32_t c, int64_t twin_ab, int64_t twin_bc,
                     int64_t twin_ca)
    {
        corners_[3 * t] = a, corners_[3 * t + 1] = b, corners_[3 * t + 2] = c;
        link(3 * t, twin_ab);
        link(3 * t + 1, twin_bc);
        link(3 * t + 2, twin_ca);
        markDirty(t);
    }

    // A changed triangle: its queued candidate is stale, and it needs scanning again.
    void markDirty(size_t t)
    {
        if (!dirty_flags_[t]) {
            dirty_flags_[t] = true;
            dirty_.push_back(t);
        }
    }

    // The corners, as two triangles split by the north-west to south-east diagonal (the four
    // corners of a rectangle are cocircular, so either diagonal is Delaunay; this one is
    // fixed).
    void insertCorners()
    {
        const int64_t east = width_ - 1, south = height_ - 1;
        const uint32_t nw = addVertex({0, 0}), sw = addVertex({0, south});
        const uint32_t se = addVertex({east, south}), ne = addVertex({east, 0});
        const size_t t0 = addTriangle(), t1 = addTriangle();
        setTriangle(t0, nw, sw, se, kHull, kHull, int64_t(3 * t1));
        setTriangle(t1, nw, se, ne, int64_t(3 * t0 + 2), kHull, kHull);
    }

    // Each border's 1-D choice, inserted on its hull edge walking the hull counter-clockwise
    // (west side southwards, south side eastwards, east side northwards, north side
    // westwards), so each point splits the hull edge leaving the previous one.
    void insertBorders()
    {
        const int64_t east = width_ - 1, south = height_ - 1;
        const float* h = heights_.data();
        const size_t w = size_t(width_);
        const Line west{h, w, height_, ys_.data()};
        const Line southern{h + size_t(south) * w, 1, width_, xs_.data()};
        const Line eastern{h + east, w, height_, ys_.data()};
        const Line north{h, 1, width_, xs_.data()};

        uint32_t from = 0; // the north-west corner
        for (const int64_t row : simplifyLine(west, border_error_))
            from = insertOnHull(from, {0, row});
        from = 1; // south-west
        for (const int64_t column : simplifyLine(southern, border_error_))
            from = insertOnHull(from, {column, south});
        from = 2; // south-east
        const std::vector<int64_t> east_rows = simplifyLine(eastern, border_error_);
        for (auto row = east_rows.rbegin(); row != east_rows.rend(); ++row)
            from = insertOnHull(from, {east, *row});
        from = 3; // north-east
        const std::vector<int64_t> north_columns = simplifyLine(north, border_error_);
        for (auto column = north_columns.rbegin(); column != north_columns.rend(); ++column)
            from = insertOnHull(from, {*column, 0});
    }

    // Inserts sample g on the hull edge leaving vertex `from`, makes the mesh Delaunay again,
    // and returns g's vertex (the start of the hull edge beyond it).
    uint32_t insertOnHull(uint32_t from, Cell g)
    {
        const uint32_t v = addVertex(g);
        splitHullEdge(size_t(hull_start_[from]), v);
        legalise();
        return v;
    }

    // Splits the triangle (u, v, c) owning hull edge e = uv at p on it into (c, u, p) and
    // (v, c, p); up and pv stay hull edges.
    void splitHullEdge(size_t e, uint32_t p)
    {
        const size_t t = e / 3, t2 = addTriangle();
        const uint32_t u = corners_[e], v = corners_[nextEdge(e)], c = corners_[prevEdge(e)];
        const int64_t twin_vc = twins_[nextEdge(e)], twin_cu = twins_[prevEdge(e)];
        setTriangle(t, c, u, p, twin_cu, kHull, int64_t(3 * t2 + 1));
        setTriangle(t2, v, c, p, twin_vc, int64_t(3 * t + 2), kHull);
        pending_.push_back(3 * t);
        pending_.push_back(3 * t2);
    }

    // Splits triangle t = (a, b, c) at p strictly inside it into (a, b, p), (b, c, p),
    // (c, a, p).
    void splitTriangle(size_t t, uint32_t p)
    {
        const uint32_t a = corners_[3 * t], b = corners_[3 * t + 1], c = corners_[3 * t + 2];
        const int64_t twin_ab = twins_[3 * t], twin_bc = twins_[3 * t + 1],
                      twin_ca = twins_[3 * t + 2];
        const size_t t1 = addTriangle(), t2 = addTriangle();
        setTriangle(t, a, b, p, twin_ab, int64_t(3 * t1 + 2), int64_t(3 * t2 + 1));
        setTriangle(t1, b, c, p, twin_bc, int64_t(3 * t2 + 2), int64_t(3 * t + 1));
        setTriangle(t2, c, a, p, twin_ca, int64_t(3 * t + 2), int64_t(3 * t1 + 1));
        pending_.push_back(3 * t);
        pending_.push_back(3 * t1);
        pending_.push_back(3 * t2);
    }

    // Splits interior edge e = ab at p on it: its triangle (a, b, c) and the neighbour
    // (b, a, d) become (c, a, p), (b, c, p), (a, d, p), (d, b, p).
    void splitEdge(size_t e, uint32_t p)
    {
        const size_t f = size_t(twins_[e]);
        const size_t t = e / 3, u = f / 3, t3 = addTriangle(), t4 = addTriangle();
        const uint32_t a = corners_[e], b = corners_[nextEdge(e)], c = corners_[prevEdge(e)];
        const uint32_t d = corners_[prevEdge(f)];
        const int64_t twin_bc = twins_[nextEdge(e)], twin_ca = twins_[prevEdge(e)];
        const int64_t twin_ad = twins_[nextEdge(f)], twin_db = twins_[prevEdge(f)];
        setTriangle(t, c, a, p, twin_ca, int64_t(3 * u + 2), int64_t(3 * t3 + 1));
        setTriangle(t3, b, c, p, twin_bc, int64_t(3 * t + 2), int64_t(3 * t4 + 1));
        setTriangle(u, a, d, p, twin_ad, int64_t(3 * t4 + 2), int64_t(3 * t + 1));
        setTriangle(t4, d, b, p, twin_db, int64_t(3 * t3 + 2), int64_t(3 * u + 1));
        for (const size_t outer : {3 * t, 3 * t3, 3 * u, 3 * t4})
            pending_.push_back(outer);
    }

    // Lawson's flips after inserting a point p: each pending half-edge ab lies opposite p in
    // its triangle (a, b, p); while the vertex q across it lies strictly inside the
    // circumcircle of (a, b, p), flip ab to pq and check the two edges now opposite p. Hull
    // edges are never flipped (they have no twin), which keeps the borders as chosen. A q
    // strictly inside the circle makes the quad strictly convex, so no flip makes a
    // degenerate triangle.
    void legalise()
    {
        while (!pending_.empty()) {
            const size_t e = pending_.back();
            pending_.pop_back();
            const int64_t f = twins_[e];
            if (f == kHull)
                continue;
            const uint32_t a = corners_[e], b = corners_[nextEdge(e)], p = corners_[prevEdge(e)];
            const uint32_t q = corners_[prevEdge(size_t(f))];
            if (insideCircumcircle(points_[a], points_[b], points_[p], points_[q]))
                flip(e);
        }
    }

    // Flips edge e = ab between (a, b, p) and (b, a, q), whose quad a q b p is convex, into
    // (q, p, a) and (p, q, b), keeping both triangles' slots.
    void flip(size_t e)
    {
        const size_t e1 = nextEdge(e), e2 = prevEdge(e);
        const size_t f = size_t(twins_[e]), f1 = nextEdge(f), f2 = prevEdge(f);
        const uint32_t a = corners_[e], b = corners_[e1], p = corners_[e2], q = corners_[f2];
        const int64_t twin_bp = twins_[e1], twin_pa = twins_[e2];
        const int64_t twin_aq = twins_[f1], twin_qb = twins_[f2];
        corners_[e] = q, corners_[e1] = p, corners_[e2] = a;
        corners_[f] = p, corners_[f1] = q, corners_[f2] = b;
        link(e, int64_t(f));
        link(e1, twin_pa);
        link(e2, twin_aq);
        link(f1, twin_qb);
        link(f2, twin_bp);
        markDirty(e / 3);
        markDirty(f / 3);
        pending_.push_back(e2); // aq, opposite p
        pending_.push_back(f1); // qb, opposite p
    }

    // The worst sample of triangle t (closed: its edges and vertices included) within
    // `window`, ties to the lowest row-major index. The same code measures the candidates and
    // the final error, so the two agree bit for bit.
    //
    // Weight k, the orientation of the edge opposite vertex k with the sample (twice a
    // sub-triangle's area in real coordinates), is an exact integer; the sample is inside when
    // no weight is negative, and the weights sum to det (twice t's area). Strictly inside, the
    // mesh is S / det with S = Σ weight·height, and the error is measured as |height·det − S|
    // (no division per sample), divided by det once at the end. A sample with a zero weight
    // lies on an edge and takes the edge's own lerp, so the two triangles beside an edge agree
    // on it exactly; a vertex (two zero weights) has error 0 by construction and is skipped.
    //
    // Every vertex is a sample, so t's bounding box is the samples between its vertices' least
    // and greatest rows and columns. Each row walks the box's columns from the west until the
    // first sample inside, then to the last: triangles are convex. Most triangles are small,
    // where this beats computing each row's span exactly (divisions and searches per row); in
    // wide ones the walk first jumps to just short of the span (by arithmetic over the
    // columns common_gap_ apart, by a binary search on xs beyond them).
    Candidate scan(size_t t, const Window& window) const
    {
        const uint32_t ids[3] = {corners_[3 * t], corners_[3 * t + 1], corners_[3 * t + 2]};
        const Point v[3] = {points_[ids[0]], points_[ids[1]], points_[ids[2]]};
        const Cell g[3] = {cells_[ids[0]], cells_[ids[1]], cells_[ids[2]]};
        const double h[3] = {sampleHeight(sampleOf(g[0])), sampleHeight(sampleOf(g[1])),
                             sampleHeight(sampleOf(g[2]))};
        const double det = double(orientation(v[0], v[1], v[2]));
        // Edge k runs from v[k+1] to v[k+2], opposite vertex k.
        const Point from[3] = {v[1], v[2], v[0]}, to[3] = {v[2], v[0], v[1]};
        Candidate on_edges;          // the worst sample on an edge
        double inside_scaled = -1.0; // the worst |height·det − S| strictly inside
        size_t inside_sample = 0;    // and its sample
        auto visitEdge = [&](Cell s, int64_t wa, int64_t wb, int64_t wc) {
            if ((wa == 0) + (wb == 0) + (wc == 0) > 1)
                return; // a vertex
            const int k = wa == 0 ? 0 : wb == 0 ? 1 : 2;
            const double mesh = edgeHeight(pointOf(s), from[k], h[k == 2 ? 0 : k + 1], to[k],
                                           h[k == 0 ? 2 : k - 1]);
            const size_t sample = sampleOf(s);
            const double error = std::abs(sampleHeight(sample) - mesh);
            if (error > on_edges.error) // strict: the lowest index wins a tie
                on_edges = {error, sample};
        };

        const int64_t row0 = std::max(window.row0, std::min({g[0].row, g[1].row, g[2].row}));
        const int64_t row1 = std::min(window.row1, std::max({g[0].row, g[1].row, g[2].row}));
        const int64_t column0 =
            std::max(window.column0, std::min({g[0].column, g[1].column, g[2].column}));
        const int64_t column1 =
            std::min(window.column1, std::max({g[0].column, g[1].column, g[2].column}));
        if (row0 > row1 || column0 > column1)
            return on_edges;
        // Weight k = orientation(from[k], to[k], (x, y)) = per_x[k]·x + per_y[k]·y + constant:
        // affine in x along a row. Stepping one column east over a gap of common_gap_ (the
        // grid's usual spacing) adds step[k] = per_x[k]·common_gap_; over any other gap the
        // weights are recomputed from the column's own x; stepping a row south adds
        // per_y[k]·(its gap). Every value reached is the exact orientation at a sample
        // (<= 2^49), held in int64 and, for S, in doubles beside (integers below 2^53 add
        // exactly, see the budget), so S never depends on the walk that reached a sample.
        int64_t per_x[3], per_y[3], step[3], row_start[3];
        double step_d[3];
        const int32_t* xs = xs_.data();
        for (int k = 0; k < 3; ++k) {
            per_x[k] = to[k].y - from[k].y;
            per_y[k] = from[k].x - to[k].x;
            step[k] = per_x[k] * common_gap_;
            step_d[k] = double(step[k]);
            // The weights at the bounding box's west column on the current row.
            row_start[k] = orientation(from[k], to[k], {xs[column0], ys_[size_t(row0)]});
        }
        // In a wide triangle the walk to each row's span would be long.
        const bool wide = column1 - column0 > 16;
        for (int64_t row = row0; row <= row1; ++row) {
            if (row > row0) {
                const int64_t gap = int64_t(ys_[size_t(row)]) - ys_[size_t(row - 1)];
                for (int k = 0; k < 3; ++k)
                    row_start[k] += per_y[k] * gap;
            }
            int64_t column = column0, steady_until = steady_until_[size_t(column0)];
            int64_t wa = row_start[0], wb = row_start[1], wc = row_start[2];
            double da = double(wa), db = double(wb), dc = double(wc);
            auto recompute = [&] { // at `column`, from the row's start
                const int64_t dx = xs[column] - xs[column0];
                wa = row_start[0] + per_x[0] * dx, da = double(wa);
                wb = row_start[1] + per_x[1] * dx, db = double(wb);
                wc = row_start[2] + per_x[2] * dx, dc = double(wc);
                steady_until = steady_until_[size_t(column)];
            };
            // To the next column by the common gap: right up to steady_until (beyond it the
            // weights are wrong until recomputed).
            auto advance = [&] {
                ++column;
                wa += step[0], wb += step[1], wc += step[2];
                da += step_d[0], db += step_d[1], dc += step_d[2];
            };
            if (wide) {
                // Jump close to the span: each edge whose weight grows eastwards admits the x
                // from xs[column0] − row_start/per_x on. The double estimate is within 2^-2
                // of the exact bound (operands below 2^50), so the columns at x < west, one
                // short of it, are all outside.
                double west = 0.0; // east of xs[column0]
                for (int k = 0; k < 3; ++k)
                    if (per_x[k] > 0)
                        west = std::max(west, -double(row_start[k]) / double(per_x[k]));
                west += double(xs[column0]) - 1.0;
                if (west > double(xs[column0])) {
                    // Over the steady run from column0 the columns are common_gap_ apart: the
                    // columns before column0 + ⌊(west − xs[column0]) / common_gap_⌋ lie west
                    // of `west`. Beyond the run, a binary search on xs.
                    column = column0 + int64_t((west - double(xs[column0])) / double(common_gap_));
                    const int64_t run_end = std::min(steady_until, column1);
                    if (column > run_end) {
                        column =
                            std::lower_bound(xs + run_end, xs + column1 + 1, west,
                                             [](int32_t x, double bound) { return x < bound; }) -
                            xs;
                    }
                    if (column <= column1)
                        recompute();
                }
            }
            // Each loop below runs over one steady run at a time (to `stop`), and stops
            // inside it when the weights' signs say so; past the run's end (an irregular gap
            // crossed) the weights are recomputed and the loop goes on.
            for (;;) { // the walk, while some weight is negative
                const int64_t stop = std::min(column1, steady_until);
                while (column <= stop && (wa | wb | wc) < 0)
                    advance();
                if (column <= stop || column > column1)
                    break;
                recompute();
            }
            // Inside (or on an edge) until a weight turns negative: triangles are convex.
            const float* samples = heights_.data() + size_t(row) * size_t(width_);
            for (;;) {
                const int64_t stop = std::min(column1, steady_until);
                // (A while loop: advance() moves column and the weights, which a for
                // statement's condition would hide from clang's loop analysis.)
                while (column <= stop && (wa | wb | wc) >= 0) {
                    if (wa == 0 || wb == 0 || wc == 0) {
                        visitEdge({column, row}, wa, wb, wc);
                    } else {
                        const double scaled = std::abs(double(samples[column]) * det -
                                                       (da * h[0] + db * h[1] + dc * h[2]));
                        if (scaled > inside_scaled) { // strict: the lowest index wins a tie
                            inside_scaled = scaled;
                            inside_sample = size_t(row) * size_t(width_) + size_t(column);
                        }
                    }
                    advance();
                }
                if (column <= stop || column > column1)
                    break;
                recompute();
            }
        }
        if (inside_scaled < 0.0)
            return on_edges;
        const Candidate inside{inside_scaled / det, inside_sample};
        const bool inside_worse =
            inside.error > on_edges.error ||
            (inside.error == on_edges.error && inside.sample < on_edges.sample);
        return inside_worse ? inside : on_edges;
    }

    // Interior samples only: border samples are settled by the border pass.
    Window interior() const { return {1, height_ - 2, 1, width_ - 2}; }

    // Rescans every changed triangle: queued (or moved) when its worst sample is beyond the
    // bound, else dropped.
    void queueDirty()
    {
        for (const size_t t : dirty_) {
            dirty_flags_[t] = false;
            const Candidate c = scan(t, interior());
            if (c.error > max_error_)
                queue_.set(t, c);
            else
                queue_.erase(t);
        }
        dirty_.clear();
    }

    // The greedy loop: insert the worst interior sample until none exceeds the bound.
    void refineInterior()
    {
        queueDirty(); // every triangle so far
        while (!queue_.empty()) {
            const size_t t = queue_.top();
            insertSample(queue_.candidate(t).sample, t); // t changes, so it is rescanned
            legalise();
            queueDirty();
        }
    }

    // Inserts grid sample `sample` into triangle t, which contains it: on one of t's edges
    // (never a hull edge: the sample is interior) the edge splits, else the triangle. It is
    // never one of t's vertices, whose error is exactly 0.
    void insertSample(size_t sample, size_t t)
    {
        const Cell g{int64_t(sample % size_t(width_)), int64_t(sample / size_t(width_))};
        const uint32_t p = addVertex(g);
        const Point s = points_[p];
        for (int k = 0; k < 3; ++k) {
            const size_t e = 3 * t + size_t(k);
            if (orientation(points_[corners_[e]], points_[corners_[nextEdge(e)]], s) == 0) {
                splitEdge(e, p);
                return;
            }
        }
        splitTriangle(t, p);
    }

    Tin output() const
    {
        Tin tin;
        tin.columns.reserve(cells_.size());
        tin.rows.reserve(cells_.size());
        tin.heights.reserve(cells_.size());
        for (const Cell& g : cells_) {
            tin.columns.push_back(uint32_t(g.column));
            tin.rows.push_back(uint32_t(g.row));
            tin.heights.push_back(heights_[sampleOf(g)]);
        }
        tin.triangles = corners_;
        // Every sample lies in some closed triangle; border samples on hull edges get the
        // border pass's lerp, so this is also what that pass bounded.
        const Window all{0, height_ - 1, 0, width_ - 1};
        for (size_t t = 0; t < dirty_flags_.size(); ++t)
            tin.max_error = std::max(tin.max_error, scan(t, all).error);
        return tin;
    }

    std::span<const float> heights_;
    std::span<const int32_t> xs_, ys_;
    // The median of the column gaps xs[c + 1] − xs[c], which the scan steps over by adding,
    // and per column c the first column from c on whose gap eastwards is not that one.
    int64_t common_gap_;
    std::vector<int64_t> steady_until_;
    int64_t width_, height_;
    double max_error_;
    double border_error_; // the border lines' bound (border_error)

    std::vector<Point> points_;       // per vertex: its real coordinates
    std::vector<Cell> cells_;         // per vertex: its grid indices
    std::vector<int64_t> hull_start_; // per vertex: the hull half-edge leaving it, if any
    std::vector<uint32_t> corners_;   // per half-edge: its start vertex
    std::vector<int64_t> twins_;      // per half-edge: its twin, or kHull
    std::vector<bool> dirty_flags_;   // per triangle: listed in dirty_
    std::vector<size_t> dirty_;       // triangles changed since their last scan
    std::vector<size_t> pending_;     // half-edges left to legalise
    TriangleQueue queue_;
};

void checkHeights(std::span<const float> heights, size_t width, double max_error)
{
    checkParameter("max_error", max_error, ValueRange::nonNegative());
    for (size_t i = 0; i < heights.size(); ++i)
        if (!std::isfinite(heights[i]))
            throw Error("heights at row " + std::to_string(i / width) + ", column " +
                        std::to_string(i % width) + " is " + formatNumber(heights[i]) +
                        ": must be a finite number");
}

void checkInput(std::span<const float> heights, int width, int height, double max_error)
{
    checkParameter("width", int64_t(width), 2, 65536);
    checkParameter("height", int64_t(height), 2, 65536);
    const size_t expected = size_t(width) * size_t(height);
    if (heights.size() != expected)
        throw Error("heights has " + std::to_string(heights.size()) +
                    " samples: must be width * height = " + std::to_string(expected));
    checkHeights(heights, size_t(width), max_error);
}

// One axis of a rectilinear grid: 2 to 65536 strictly increasing positions in [0, 2^24].
void checkPositions(const char* name, std::span<const int32_t> positions)
{
    checkParameter(std::string(name) + ".size()", int64_t(positions.size()), 2, 65536);
    for (size_t i = 0; i < positions.size(); ++i) {
        const int64_t position = positions[i];
        if (position < 0 || position > kMaxPosition)
            checkParameter(std::string(name) + "[" + std::to_string(i) + "]", position, 0,
                           kMaxPosition);
        if (i > 0 && position <= positions[i - 1])
            throw Error(std::string(name) + "[" + std::to_string(i) + "] is " +
                        std::to_string(position) + ": must be greater than " + name + "[" +
                        std::to_string(i - 1) + "] = " + std::to_string(positions[i - 1]) +
                        " (strictly increasing)");
    }
}

void checkInput(std::span<const float> heights, std::span<const int32_t> xs,
                std::span<const int32_t> ys, double max_error)
{
    checkPositions("xs", xs);
    checkPositions("ys", ys);
    const size_t expected = xs.size() * ys.size();
    if (heights.size() != expected)
        throw Error("heights has " + std::to_string(heights.size()) +
                    " samples: must be xs.size() * ys.size() = " + std::to_string(expected));
    checkHeights(heights, xs.size(), max_error);
}

} // namespace

Tin buildTin(std::span<const float> heights, std::span<const int32_t> xs,
             std::span<const int32_t> ys, double max_error, std::optional<double> border_error)
{
    checkInput(heights, xs, ys, max_error);
    if (border_error)
        checkParameter("border_error", *border_error, ValueRange::nonNegative());
    return TinBuilder(heights, xs, ys, max_error, border_error.value_or(max_error)).build();
}

Tin buildTin(std::span<const float> heights, int width, int height, double max_error)
{
    checkInput(heights, width, height, max_error);
    std::vector<int32_t> xs(static_cast<size_t>(width)), ys(static_cast<size_t>(height));
    std::iota(xs.begin(), xs.end(), 0);
    std::iota(ys.begin(), ys.end(), 0);
    return TinBuilder(heights, xs, ys, max_error, max_error).build();
}

} // namespace ridge::web
