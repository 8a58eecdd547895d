#include "ridge/web/tin_mesh.h"

#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

namespace ridge::web {

namespace {

// In-circle determinants of grid points reach about 2^68 (see insideCircumcircle).
__extension__ typedef __int128 Int128;

// A grid position. Coordinates are below 2^16, so the predicates below are exact in integers.
struct Point {
    int64_t column, row;
};

// Twice the signed area of abc in (x, y) = (column, −row): positive when a, b, c turn
// counter-clockwise seen from above with north up, zero when they are collinear. Each product
// is below 2^32, so int64 is exact.
int64_t orientation(Point a, Point b, Point c)
{
    return (b.row - a.row) * (c.column - a.column) - (b.column - a.column) * (c.row - a.row);
}

// Whether d lies strictly inside the circle through a, b, c (counter-clockwise): the sign of
// the classic 3×3 determinant in (x, y) = (column, −row). The squared lengths and the 2×2
// minors are below 2^33 each, their products below 2^66 and the sum below 2^68: exact in
// 128 bits, so cocircular points (common on a grid) never flip back and forth.
bool insideCircumcircle(Point a, Point b, Point c, Point d)
{
    const int64_t adx = a.column - d.column, ady = d.row - a.row;
    const int64_t bdx = b.column - d.column, bdy = d.row - b.row;
    const int64_t cdx = c.column - d.column, cdy = d.row - c.row;
    const int64_t ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy,
                  cd = cdx * cdx + cdy * cdy;
    const Int128 det = Int128(ad) * (bdx * cdy - bdy * cdx) + Int128(bd) * (cdx * ady - cdy * adx) +
                       Int128(cd) * (adx * bdy - ady * bdx);
    return det > 0;
}

// The height num/den of the way from ha to hb (0 <= num <= den). The one formula for every
// point on a segment between two vertices: the 1-D border pass and both triangles beside an
// edge evaluate a sample on it identically, bit for bit, so the error the greedy passes
// measured is exactly the error buildTin reports. Ends are returned exactly.
double lerp(double ha, double hb, int64_t num, int64_t den)
{
    if (num == 0)
        return ha;
    if (num == den)
        return hb;
    return ha + (hb - ha) * double(num) / double(den);
}

// The height at s, a grid point on the edge uv: linear along the edge, read from its endpoint
// of lower row-major index (as the border pass reads a line: west to east, north to south), by
// column unless the edge is vertical. Both triangles beside an edge call this with the same
// two endpoints, whichever way round they hold them, so they agree on the edge bit for bit.
double edgeHeight(Point s, Point u, double hu, Point v, double hv)
{
    if (std::pair(v.row, v.column) < std::pair(u.row, u.column))
        std::swap(u, v), std::swap(hu, hv);
    int64_t along = s.column - u.column, length = v.column - u.column;
    if (length == 0)
        along = s.row - u.row, length = v.row - u.row;
    if (length < 0) // u north-east of v
        along = -along, length = -length;
    return lerp(hu, hv, along, length);
}

// The samples of one grid line (a border): count of them, `stride` apart from `first`.
struct Line {
    const float* first;
    size_t stride;
    int64_t count;

    double at(int64_t i) const { return first[size_t(i) * stride]; }
};

// The interior samples of `line` (indices 1..count−2, ascending) that the 1-D greedy insertion
// chooses, starting from its two ends, so that every sample lies within max_error of the
// polyline through the chosen ones. The global greedy (insert the worst sample of the whole
// line, ties to the lowest index) chooses exactly the samples this recursion does: inserting
// a sample changes only its own segment, so each segment is split at its own worst sample
// (ties: lowest index) as long as that is beyond the bound, in whatever order.
std::vector<int64_t> simplifyLine(const Line& line, double max_error)
{
    std::vector<int64_t> chosen;
    std::vector<std::pair<int64_t, int64_t>> segments{{0, line.count - 1}};
    while (!segments.empty()) {
        const auto [i0, i1] = segments.back();
        segments.pop_back();
        const double h0 = line.at(i0), h1 = line.at(i1);
        double worst = max_error;
        int64_t split = -1;
        for (int64_t i = i0 + 1; i < i1; ++i) {
            const double error = std::abs(line.at(i) - lerp(h0, h1, i - i0, i1 - i0));
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

// The samples a scan looks at: rows [row0, row1] × columns [column0, column1].
struct Window {
    int64_t row0, row1, column0, column1;
};

class TinBuilder {
  public:
    TinBuilder(std::span<const float> heights, int width, int height, double max_error)
        : heights_(heights), width_(width), height_(height), max_error_(max_error)
    {
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
    size_t sampleOf(Point p) const { return size_t(p.row) * size_t(width_) + size_t(p.column); }

    uint32_t addVertex(Point p)
    {
        points_.push_back(p);
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
    // corners are cocircular, so either diagonal is Delaunay; this one is fixed).
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
        const Line west{h, w, height_}, southern{h + size_t(south) * w, 1, width_};
        const Line eastern{h + east, w, height_}, north{h, 1, width_};

        uint32_t from = 0; // the north-west corner
        for (const int64_t row : simplifyLine(west, max_error_))
            from = insertOnHull(from, {0, row});
        from = 1; // south-west
        for (const int64_t column : simplifyLine(southern, max_error_))
            from = insertOnHull(from, {column, south});
        from = 2; // south-east
        const std::vector<int64_t> east_rows = simplifyLine(eastern, max_error_);
        for (auto row = east_rows.rbegin(); row != east_rows.rend(); ++row)
            from = insertOnHull(from, {east, *row});
        from = 3; // north-east
        const std::vector<int64_t> north_columns = simplifyLine(north, max_error_);
        for (auto column = north_columns.rbegin(); column != north_columns.rend(); ++column)
            from = insertOnHull(from, {*column, 0});
    }

    // Inserts p on the hull edge leaving vertex `from`, makes the mesh Delaunay again, and
    // returns p's vertex (the start of the hull edge beyond it).
    uint32_t insertOnHull(uint32_t from, Point p)
    {
        const uint32_t v = addVertex(p);
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
    // sub-triangle's area), is an exact integer that changes by a fixed step per column and
    // per row; the sample is inside when no weight is negative, and the weights sum to det
    // (twice t's area). Strictly inside, the mesh is S / det with S = Σ weight·height, and the
    // error is measured as |height·det − S| (no division per sample), divided by det once at
    // the end. A sample with a zero weight lies on an edge and takes the edge's own lerp, so
    // the two triangles beside an edge agree on it exactly; a vertex (two zero weights) has
    // error 0 by construction and is skipped.
    //
    // Each row walks the bounding box from the west until the first point inside, then to
    // the last: triangles are convex. Most triangles are small, where this beats computing
    // each row's span exactly (divisions per triangle, branches per row); in wide ones the
    // walk first jumps to just short of the span.
    Candidate scan(size_t t, const Window& window) const
    {
        const Point v[3] = {points_[corners_[3 * t]], points_[corners_[3 * t + 1]],
                            points_[corners_[3 * t + 2]]};
        const double h[3] = {sampleHeight(sampleOf(v[0])), sampleHeight(sampleOf(v[1])),
                             sampleHeight(sampleOf(v[2]))};
        const double det = double(orientation(v[0], v[1], v[2]));
        // Edge k runs from v[k+1] to v[k+2], opposite vertex k.
        const Point from[3] = {v[1], v[2], v[0]}, to[3] = {v[2], v[0], v[1]};
        Candidate on_edges;          // the worst sample on an edge
        double inside_scaled = -1.0; // the worst |height·det − S| strictly inside
        size_t inside_sample = 0;    // and its sample
        auto visitEdge = [&](Point s, const int64_t(&w)[3]) {
            if ((w[0] == 0) + (w[1] == 0) + (w[2] == 0) > 1)
                return; // a vertex
            const int k = w[0] == 0 ? 0 : w[1] == 0 ? 1 : 2;
            const double mesh =
                edgeHeight(s, from[k], h[k == 2 ? 0 : k + 1], to[k], h[k == 0 ? 2 : k - 1]);
            const size_t sample = sampleOf(s);
            const double error = std::abs(sampleHeight(sample) - mesh);
            if (error > on_edges.error) // strict: the lowest index wins a tie
                on_edges = {error, sample};
        };

        const int64_t row0 = std::max(window.row0, std::min({v[0].row, v[1].row, v[2].row}));
        const int64_t row1 = std::min(window.row1, std::max({v[0].row, v[1].row, v[2].row}));
        const int64_t column0 =
            std::max(window.column0, std::min({v[0].column, v[1].column, v[2].column}));
        const int64_t column1 =
            std::min(window.column1, std::max({v[0].column, v[1].column, v[2].column}));
        if (row0 > row1 || column0 > column1)
            return on_edges;
        int64_t per_column[3], per_row[3], row_start[3]; // weight steps; weights at column0
        for (int k = 0; k < 3; ++k) {
            per_column[k] = to[k].row - from[k].row;
            per_row[k] = from[k].column - to[k].column;
            row_start[k] = orientation(from[k], to[k], {column0, row0});
        }
        const double column_step[3] = {double(per_column[0]), double(per_column[1]),
                                       double(per_column[2])};
        // In a wide triangle the walk to each row's span would be long.
        const bool wide = column1 - column0 > 16;
        for (int64_t row = row0; row <= row1; ++row) {
            int64_t w[3] = {row_start[0], row_start[1], row_start[2]};
            for (int k = 0; k < 3; ++k)
                row_start[k] += per_row[k];
            auto advance = [&](int64_t columns) {
                for (int k = 0; k < 3; ++k)
                    w[k] += per_column[k] * columns;
            };
            int64_t column = column0;
            if (wide) {
                // Jump close to the span: each edge whose weight grows eastwards admits the
                // columns from −weight/step on. The double estimate is far within one column
                // (operands below 2^34), and one column of margin keeps the jump short of it.
                double west = 0.0;
                for (int k = 0; k < 3; ++k)
                    if (per_column[k] > 0)
                        west = std::max(west, double(-w[k]) / column_step[k]);
                const int64_t skip = std::min(int64_t(west) - 1, column1 - column0);
                if (skip > 0) {
                    column += skip;
                    advance(skip);
                }
            }
            while (column <= column1 && (w[0] | w[1] | w[2]) < 0) // some weight negative
                ++column, advance(1);
            // Inside. The weights in doubles stay exact integers, so S never depends on the
            // walk that reached a sample.
            const float* samples = heights_.data() + size_t(row) * size_t(width_);
            double wa = double(w[0]), wb = double(w[1]), wc = double(w[2]);
            for (; column <= column1 && (w[0] | w[1] | w[2]) >= 0; ++column) {
                if (w[0] == 0 || w[1] == 0 || w[2] == 0) {
                    visitEdge({column, row}, w);
                } else {
                    const double scaled = std::abs(double(samples[column]) * det -
                                                   (wa * h[0] + wb * h[1] + wc * h[2]));
                    if (scaled > inside_scaled) { // strict: the lowest index wins a tie
                        inside_scaled = scaled;
                        inside_sample = size_t(row) * size_t(width_) + size_t(column);
                    }
                }
                advance(1);
                wa += column_step[0], wb += column_step[1], wc += column_step[2];
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
        const Point s{int64_t(sample % size_t(width_)), int64_t(sample / size_t(width_))};
        const uint32_t p = addVertex(s);
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
        tin.columns.reserve(points_.size());
        tin.rows.reserve(points_.size());
        tin.heights.reserve(points_.size());
        for (const Point& p : points_) {
            tin.columns.push_back(uint32_t(p.column));
            tin.rows.push_back(uint32_t(p.row));
            tin.heights.push_back(heights_[sampleOf(p)]);
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
    int64_t width_, height_;
    double max_error_;

    std::vector<Point> points_;       // per vertex
    std::vector<int64_t> hull_start_; // per vertex: the hull half-edge leaving it, if any
    std::vector<uint32_t> corners_;   // per half-edge: its start vertex
    std::vector<int64_t> twins_;      // per half-edge: its twin, or kHull
    std::vector<bool> dirty_flags_;   // per triangle: listed in dirty_
    std::vector<size_t> dirty_;       // triangles changed since their last scan
    std::vector<size_t> pending_;     // half-edges left to legalise
    TriangleQueue queue_;
};

void checkInput(std::span<const float> heights, int width, int height, double max_error)
{
    checkParameter("width", int64_t(width), 2, 65536);
    checkParameter("height", int64_t(height), 2, 65536);
    const size_t expected = size_t(width) * size_t(height);
    if (heights.size() != expected)
        throw Error("heights has " + std::to_string(heights.size()) +
                    " samples: must be width * height = " + std::to_string(expected));
    checkParameter("max_error", max_error, ValueRange::nonNegative());
    for (size_t i = 0; i < heights.size(); ++i)
        if (!std::isfinite(heights[i]))
            throw Error("heights at row " + std::to_string(i / size_t(width)) + ", column " +
                        std::to_string(i % size_t(width)) + " is " + formatNumber(heights[i]) +
                        ": must be a finite number");
}

} // namespace

Tin buildTin(std::span<const float> heights, int width, int height, double max_error)
{
    checkInput(heights, width, height, max_error);
    return TinBuilder(heights, width, height, max_error).build();
}

} // namespace ridge::web
