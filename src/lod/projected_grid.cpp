#include "ridge/lod/projected_grid.h"

#include "ridge/core/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <string>

namespace ridge::lod {

namespace {

// The Gauss–Newton inverse starts from the nearest of at most this many nodes a side.
constexpr int kSeedNodes = 24;

int powerOfTwoAtLeast(double x)
{
    int p = 1;
    while (p < x && p < (1 << 29))
        p <<= 1;
    return p;
}

} // namespace

std::array<double, 4> hermiteWeights(double u, bool derivative)
{
    const double u2 = u * u, u3 = u2 * u;
    if (derivative)
        return {6.0 * u2 - 6.0 * u, -6.0 * u2 + 6.0 * u, 3.0 * u2 - 4.0 * u + 1.0,
                3.0 * u2 - 2.0 * u};
    return {2.0 * u3 - 3.0 * u2 + 1.0, -2.0 * u3 + 3.0 * u2, u3 - 2.0 * u2 + u, u3 - u2};
}

ProjectedGrid ProjectedGrid::build(const Ellipsoid& ellipsoid, const LatticeRequest& request,
                                   const ToGeodetic& to_geodetic)
{
    auto pointAt = [&](double c, double r) -> std::optional<glm::dvec3> {
        const std::optional<std::array<double, 2>> g = to_geodetic(c, r);
        if (!g || !std::isfinite((*g)[0]) || !std::isfinite((*g)[1]))
            return std::nullopt;
        return geodeticToEcef(ellipsoid, (*g)[0], (*g)[1], 0.0);
    };

    ProjectedGrid grid;
    grid.ellipsoid_ = ellipsoid;
    int step = powerOfTwoAtLeast(std::max(request.last_column, request.last_row) / 16.0);
    for (;;) {
        grid.step_ = step;
        const double h = step;
        // Nodes from one before sample 0 to at least one beyond the raster and the padding.
        const double end_c = std::max(request.columns_end, request.last_column + h);
        const double end_r = std::max(request.rows_end, request.last_row + h);
        grid.nodes_x_ = int(std::ceil((end_c + h) / h)) + 1;
        grid.nodes_y_ = int(std::ceil((end_r + h) / h)) + 1;
        grid.nodes_.assign(size_t(grid.nodes_x_) * size_t(grid.nodes_y_), LatticeNode{});
        std::vector<char> present(grid.nodes_.size(), 0);

        // Derivatives by central differences h/64 wide. Their truncation, d^2 S'''/6, enters
        // the surface times h: ~0.03 (hL)^3/(R^2 64^2) for L metres a sample (80 km cells:
        // 0.08 mm, where h/4 gave 20 mm); their rounding, ~1e-9 m of an Earth-scale point over
        // d^2, enters times h^2 (the cross term): 1e-9 * 64^2, a few micrometres, whatever h.
        const double d = h / 64.0;
        double column_metres = 0.0, row_metres = 0.0;
        for (int j = 0; j < grid.nodes_y_; ++j)
            for (int i = 0; i < grid.nodes_x_; ++i) {
                const double c = grid.firstColumn() + i * h, r = grid.firstRow() + j * h;
                const bool required = c <= request.last_column + h && r <= request.last_row + h;
                std::optional<glm::dvec3> p[3][3];
                bool ok = true;
                for (int b = 0; b < 3 && ok; ++b)
                    for (int a = 0; a < 3 && ok; ++a) {
                        p[b][a] = pointAt(c + (a - 1) * d, r + (b - 1) * d);
                        ok = p[b][a].has_value();
                    }
                if (!ok) {
                    if (required)
                        throw Error("the projection has no point at grid column " +
                                    std::to_string(c) + ", row " + std::to_string(r) +
                                    " (within a node of the raster)");
                    continue;
                }
                LatticeNode& n = grid.nodes_[size_t(j) * grid.nodes_x_ + i];
                n.s = *p[1][1];
                n.s_c = (*p[1][2] - *p[1][0]) / (2.0 * d);
                n.s_r = (*p[2][1] - *p[0][1]) / (2.0 * d);
                n.s_cr = (*p[2][2] - *p[2][0] - *p[0][2] + *p[0][0]) / (4.0 * d * d);
                present[size_t(j) * grid.nodes_x_ + i] = 1;
                if (required) {
                    column_metres = std::max(column_metres, glm::length(n.s_c));
                    row_metres = std::max(row_metres, glm::length(n.s_r));
                }
            }
        grid.column_metres_ = 1.01 * column_metres;
        grid.row_metres_ = 1.01 * row_metres;

        // Nodes the projection does not reach (only beyond the raster) continue the tangent
        // plane of their nearest reached node: a breadth-first fill from the reached ones.
        std::deque<size_t> queue;
        std::vector<size_t> source(grid.nodes_.size(), std::numeric_limits<size_t>::max());
        for (size_t k = 0; k < present.size(); ++k)
            if (present[k]) {
                source[k] = k;
                queue.push_back(k);
            }
        while (!queue.empty()) {
            const size_t k = queue.front();
            queue.pop_front();
            const int i = int(k % size_t(grid.nodes_x_)), j = int(k / size_t(grid.nodes_x_));
            const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
            for (int q = 0; q < 4; ++q) {
                const int ni = i + di[q], nj = j + dj[q];
                if (ni < 0 || nj < 0 || ni >= grid.nodes_x_ || nj >= grid.nodes_y_)
                    continue;
                const size_t nk = size_t(nj) * grid.nodes_x_ + ni;
                if (source[nk] != std::numeric_limits<size_t>::max())
                    continue;
                source[nk] = source[k];
                const LatticeNode& from = grid.nodes_[source[k]];
                const int si = int(source[k] % size_t(grid.nodes_x_));
                const int sj = int(source[k] / size_t(grid.nodes_x_));
                LatticeNode& to = grid.nodes_[nk];
                to = from;
                to.s = from.s + from.s_c * ((ni - si) * h) + from.s_r * ((nj - sj) * h);
                to.s_cr = glm::dvec3(0.0);
                queue.push_back(nk);
            }
        }

        // How far the surface is from PROJ between the nodes over the raster: at cell
        // centres and edge midpoints (where a cubic's error peaks).
        double worst = 0.0;
        for (int j = 0; j + 1 < grid.nodes_y_; ++j)
            for (int i = 0; i + 1 < grid.nodes_x_; ++i) {
                const double c = grid.firstColumn() + i * h, r = grid.firstRow() + j * h;
                if (c + h < 0.0 || r + h < 0.0 || c > request.last_column || r > request.last_row)
                    continue;
                const double probes[3][2] = {
                    {c + h / 2, r + h / 2}, {c + h / 2, r}, {c, r + h / 2}};
                for (const auto& q : probes)
                    if (const std::optional<glm::dvec3> exact = pointAt(q[0], q[1]))
                        worst = std::max(worst, glm::length(grid.surfaceAt(q[0], q[1]) - *exact));
            }
        grid.measured_error_ = worst;
        const bool too_many = std::max(grid.nodes_x_, grid.nodes_y_) * 2 - 1 > request.max_nodes;
        if (worst <= request.tolerance || step == 1 || too_many)
            return grid;
        step /= 2;
    }
}

void ProjectedGrid::locate(double c, double r, int& i, int& j, double& u, double& v) const
{
    const double x = (c - firstColumn()) / step_, y = (r - firstRow()) / step_;
    i = int(std::clamp(std::floor(x), 0.0, double(nodes_x_ - 2)));
    j = int(std::clamp(std::floor(y), 0.0, double(nodes_y_ - 2)));
    u = x - i;
    v = y - j;
}

glm::dvec3 ProjectedGrid::surfaceAt(double c, double r) const
{
    int i, j;
    double u, v;
    locate(c, r, i, j, u, v);
    const std::array<double, 4> wu = hermiteWeights(u), wv = hermiteWeights(v);
    const double h = step_;
    glm::dvec3 s(0.0);
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            const LatticeNode& n = node(i + a, j + b);
            s += wu[a] * wv[b] * n.s + wu[2 + a] * wv[b] * h * n.s_c +
                 wu[a] * wv[2 + b] * h * n.s_r + wu[2 + a] * wv[2 + b] * h * h * n.s_cr;
        }
    return s;
}

void ProjectedGrid::tangentsAt(double c, double r, glm::dvec3& s_c, glm::dvec3& s_r) const
{
    int i, j;
    double u, v;
    locate(c, r, i, j, u, v);
    const std::array<double, 4> wu = hermiteWeights(u), wv = hermiteWeights(v);
    const std::array<double, 4> du = hermiteWeights(u, true), dv = hermiteWeights(v, true);
    const double h = step_;
    s_c = s_r = glm::dvec3(0.0);
    for (int b = 0; b < 2; ++b)
        for (int a = 0; a < 2; ++a) {
            const LatticeNode& n = node(i + a, j + b);
            s_c += (du[a] * wv[b] * n.s + du[2 + a] * wv[b] * h * n.s_c +
                    du[a] * wv[2 + b] * h * n.s_r + du[2 + a] * wv[2 + b] * h * h * n.s_cr) /
                   h;
            s_r += (wu[a] * dv[b] * n.s + wu[2 + a] * dv[b] * h * n.s_c +
                    wu[a] * dv[2 + b] * h * n.s_r + wu[2 + a] * dv[2 + b] * h * h * n.s_cr) /
                   h;
        }
}

glm::dvec3 ProjectedGrid::normalThrough(glm::dvec3 p) const
{
    return glm::normalize(glm::dvec3(p.x, p.y, p.z / (1.0 - ellipsoid_.e2())));
}

glm::dvec2 ProjectedGrid::gridOf(glm::dvec3 point) const
{
    const Geodetic g = ecefToGeodetic(ellipsoid_, point);
    const glm::dvec3 foot = geodeticToEcef(ellipsoid_, g.longitude, g.latitude, 0.0);
    const int stride = std::max(1, std::max(nodes_x_, nodes_y_) / kSeedNodes);
    double best = INFINITY;
    glm::dvec2 q(0.0);
    for (int j = 0; j < nodes_y_; j += stride)
        for (int i = 0; i < nodes_x_; i += stride)
            if (const double d2 = glm::dot(node(i, j).s - foot, node(i, j).s - foot); d2 < best) {
                best = d2;
                q = {firstColumn() + double(i) * step_, firstRow() + double(j) * step_};
            }
    const double c_max = firstColumn() + double(nodes_x_ - 1) * step_;
    const double r_max = firstRow() + double(nodes_y_ - 1) * step_;
    for (int iteration = 0; iteration < 30; ++iteration) {
        glm::dvec3 s_c, s_r;
        tangentsAt(q.x, q.y, s_c, s_r);
        const glm::dvec3 d = foot - surfaceAt(q.x, q.y);
        const double a = glm::dot(s_c, s_c), b = glm::dot(s_c, s_r), c = glm::dot(s_r, s_r);
        const double det = a * c - b * b;
        if (!(det > 0.0))
            break;
        const double e = glm::dot(s_c, d), f = glm::dot(s_r, d);
        const glm::dvec2 delta((c * e - b * f) / det, (a * f - b * e) / det);
        const glm::dvec2 next(std::clamp(q.x + delta.x, double(firstColumn()), c_max),
                              std::clamp(q.y + delta.y, double(firstRow()), r_max));
        const double moved = std::abs(next.x - q.x) + std::abs(next.y - q.y);
        q = next;
        if (moved < 1e-10)
            break;
    }
    return q;
}

} // namespace ridge::lod
