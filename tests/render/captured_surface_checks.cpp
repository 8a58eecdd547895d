#include "captured_surface_checks.h"

#include "ridge/lod/horizon.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <set>

namespace ridge::test {
namespace {

using VertexKey = std::array<uint32_t, 3>;

VertexKey keyOf(const render::CapturedVertex& v)
{
    VertexKey k;
    std::memcpy(&k[0], &v.x, 4);
    std::memcpy(&k[1], &v.y, 4);
    std::memcpy(&k[2], &v.z, 4);
    return k;
}

// Finest-grid column, row and height of a captured vertex: through the frame's inverse on a
// globe; on a plane the local x, y as before (z is left camera-relative there: the callers
// only compare heights of one capture).
glm::dvec3 gridOfVertex(float x, float y, float z, const render::CapturedSurface& s,
                        const lod::TerrainFrame& frame)
{
    if (frame.onEllipsoid())
        return frame.gridOf(s.camera_position + glm::dvec3(x, y, z));
    return {frame.columnOf(x + s.camera_position.x), frame.rowOf(y + s.camera_position.y),
            double(z)};
}

glm::dvec3 gridOfKey(const VertexKey& k, const render::CapturedSurface& s,
                     const lod::TerrainFrame& frame)
{
    float x, y, z;
    std::memcpy(&x, &k[0], 4);
    std::memcpy(&y, &k[1], 4);
    std::memcpy(&z, &k[2], 4);
    return gridOfVertex(x, y, z, s, frame);
}

struct Footprint {
    int64_t c0, c1, r0, r1; // finest samples
};

Footprint footprintOf(PatchId p, const PyramidGeometry& g)
{
    const int64_t span = int64_t(g.cells()) * g.step(p.level);
    return {p.x * span, (p.x + 1) * span, p.y * span, (p.y + 1) * span};
}

// Border vertices of one patch along one seam line, as (position along the seam, height).
using SeamProfile = std::vector<std::pair<double, double>>;

double heightAt(const SeamProfile& profile, double t)
{
    auto it = std::lower_bound(profile.begin(), profile.end(), std::make_pair(t, -1e300));
    if (it == profile.end())
        return profile.back().second;
    if (it == profile.begin() || it->first == t)
        return it->second;
    auto lo = std::prev(it);
    const double f = (t - lo->first) / (it->first - lo->first);
    return lo->second + f * (it->second - lo->second);
}

// Globe: whether a captured vertex lies on the polar axis (a pole row's vertex, or a skirt
// foot or wall foot under one), from its ECEF position rather than through gridOf, which
// loses its way for skirt feet thousands of kilometres deep. The tolerance is the float
// precision of camera-relative coordinates (about 1e-6 of the distances involved); the
// nearest other sample is a whole grid step from the axis.
bool onPoleAxis(const VertexKey& k, const render::CapturedSurface& s,
                const lod::TerrainFrame& frame)
{
    // A pole inside a projected grid is an ordinary sample.
    if (!frame.onEllipsoid() || frame.projectedGrid())
        return false;
    float x, y, z;
    std::memcpy(&x, &k[0], 4);
    std::memcpy(&y, &k[1], 4);
    std::memcpy(&z, &k[2], 4);
    const glm::dvec3 relative(x, y, z);
    const glm::dvec3 world = s.camera_position + relative;
    const double tolerance = 1e-6 * (glm::length(s.camera_position) + glm::length(relative)) + 0.01;
    return std::hypot(world.x, world.y) < tolerance;
}

// Globe: the finest-grid column of a captured vertex's meridian. On a grid that goes round
// the Earth its edge meridian is column 0 and column W − 1 alike, and is given as 0.
double columnOfLongitude(const VertexKey& k, const render::CapturedSurface& s,
                         const lod::TerrainFrame& frame)
{
    float x, y, z;
    std::memcpy(&x, &k[0], 4);
    std::memcpy(&y, &k[1], 4);
    std::memcpy(&z, &k[2], 4);
    const glm::dvec3 world = s.camera_position + glm::dvec3(x, y, z);
    const lod::GeodeticGrid& g = frame.geodetic();
    const double turn = 2.0 * std::numbers::pi;
    double lon = std::remainder(std::atan2(world.y, world.x) - g.lon0, turn); // (−π, π]
    if (lon < -1e-9)
        lon += turn;
    double column = lon / g.dlon;
    if (g.wrap_columns > 0 && std::abs(column - double(g.wrap_columns)) < 1e-3)
        column = 0.0;
    return column;
}

// The terrain's outer border x = 0, x = W − 1, y = 0, y = H − 1 (finest samples): open by
// nature. Only edges lying on it are exempt.
bool onOuterBorder(const VertexKey& a, const VertexKey& b, const render::CapturedSurface& s,
                   const lod::TerrainFrame& frame)
{
    const double last_column = frame.geometry().width() - 1,
                 last_row = frame.geometry().height() - 1;
    const glm::dvec3 ga = gridOfKey(a, s, frame), gb = gridOfKey(b, s, frame);
    const double ca = ga.x, cb = gb.x, ra = ga.y, rb = gb.y;
    auto both = [](double u, double v, double line) {
        return std::abs(u - line) < 1e-3 && std::abs(v - line) < 1e-3;
    };
    return both(ca, cb, 0.0) || both(ca, cb, last_column) || both(ra, rb, 0.0) ||
           both(ra, rb, last_row);
}

// The samples a fan triangle into a pole covers, marked. In grid terms the pole is a whole
// row, so the triangle (pole, A, B) is the region between that row and the segment A-B:
// at each column from A's to B's (across the wrap seam B is taken one period on, and the
// samples wrap back), the rows from the pole to the segment, inclusive.
void markPoleBand(const glm::dvec3 q[3], const lod::TerrainFrame& frame,
                  std::vector<uint8_t>& covered)
{
    const int W = frame.geometry().width(), H = frame.geometry().height();
    double pole_row = 0.0;
    glm::dvec2 a{}, b{};
    int n = 0;
    for (int k = 0; k < 3; ++k) {
        if (frame.poleRow(q[k].y))
            pole_row = q[k].y;
        else
            (n++ == 0 ? a : b) = glm::dvec2(q[k]);
    }
    if (a.x > b.x)
        std::swap(a, b);
    const int64_t period = frame.geodetic().wrap_columns;
    if (period > 0 && b.x - a.x > 0.5 * double(period)) {
        std::swap(a, b);
        b.x += double(period);
    }
    for (int c = int(std::ceil(a.x - 1e-6)); c <= int(std::floor(b.x + 1e-6)); ++c) {
        const double t = b.x > a.x ? (c - a.x) / (b.x - a.x) : 0.0;
        const double edge_row = a.y + t * (b.y - a.y);
        const int r0 = int(std::ceil(std::min(pole_row, edge_row) - 1e-6));
        const int r1 = int(std::floor(std::max(pole_row, edge_row) + 1e-6));
        const int col = period > 0 ? int(((int64_t(c) % period) + period) % period) : c;
        for (int r = std::max(0, r0); r <= std::min(H - 1, r1); ++r) {
            if (col >= 0 && col < W)
                covered[size_t(r) * W + col] = 1;
            if (period > 0 && col == 0)
                covered[size_t(r) * W + size_t(period)] = 1; // the repeated column
        }
    }
}

// A single-valued surface puts each point of the grid under one triangle at most. Probed at
// (column + ¼, row + ½) of every cell — strictly inside one of a cell's two triangles
// whichever its diagonal, and off the samples, which the finest level's triangles have only
// as corners: counted into `inside` per cell, and into `overlapped` when a second triangle
// holds the probe (a level drawn over another, a turn drawn twice).
void markInside(const glm::dvec3 q[3], double det, const lod::TerrainFrame& frame,
                std::vector<uint8_t>& inside, size_t& overlapped)
{
    const int W = frame.geometry().width(), H = frame.geometry().height();
    const int64_t period = frame.onEllipsoid() ? frame.geodetic().wrap_columns : 0;
    const double x0 = std::min({q[0].x, q[1].x, q[2].x}), x1 = std::max({q[0].x, q[1].x, q[2].x});
    const double y0 = std::min({q[0].y, q[1].y, q[2].y}), y1 = std::max({q[0].y, q[1].y, q[2].y});
    constexpr double kStrict = 1e-3;
    for (int r = std::max(0, int(std::floor(y0 - 0.5))); r <= std::min(H - 2, int(y1)); ++r)
        for (int c = int(std::floor(x0 - 0.25)); c <= int(x1); ++c) {
            const double px = c + 0.25, py = r + 0.5;
            const double l0 =
                ((q[1].y - q[2].y) * (px - q[2].x) + (q[2].x - q[1].x) * (py - q[2].y)) / det;
            const double l1 =
                ((q[2].y - q[0].y) * (px - q[2].x) + (q[0].x - q[2].x) * (py - q[2].y)) / det;
            if (l0 <= kStrict || l1 <= kStrict || 1.0 - l0 - l1 <= kStrict)
                continue;
            const int64_t cell = period > 0 ? ((c % period) + period) % period : c;
            if (cell < 0 || cell > W - 2)
                continue;
            if (++inside[size_t(r) * W + size_t(cell)] == 2)
                ++overlapped;
        }
}

} // namespace

StitchedReport checkStitchedWatertight(const render::CapturedSurface& s,
                                       const lod::TerrainFrame& frame)
{
    StitchedReport report;
    std::map<std::pair<VertexKey, VertexKey>, int> edges;
    std::set<VertexKey> feet;
    const size_t triangles = s.vertices.size() / 3;
    report.triangles = triangles;
    for (size_t t = 0; t < triangles; ++t) {
        const render::CapturedVertex* v = &s.vertices[3 * t];
        const VertexKey k[3] = {keyOf(v[0]), keyOf(v[1]), keyOf(v[2])};
        if (k[0] == k[1] || k[1] == k[2] || k[0] == k[2]) {
            ++report.degenerate;
            continue;
        }
        report.walls += v[0].skirt != 0;
        for (int e = 0; e < 3; ++e) {
            if (v[e].skirt == 2)
                feet.insert(k[e]);
            VertexKey a = k[e], b = k[(e + 1) % 3];
            if (b < a)
                std::swap(a, b);
            ++edges[{a, b}];
        }
    }
    for (const auto& [edge, count] : edges) {
        const bool foot = feet.count(edge.first) && feet.count(edge.second);
        // Globe: as for patches (checkWatertight), every vertex of a pole row is one point of
        // the polar axis (heights apart): edges into a pole are not followed (the cap's closure
        // is checked by the pixels), and the polar cells all meet on the axis.
        const bool into_pole =
            onPoleAxis(edge.first, s, frame) || onPoleAxis(edge.second, s, frame);
        const bool polar_axis =
            onPoleAxis(edge.first, s, frame) && onPoleAxis(edge.second, s, frame);
        if (count == 1 && !foot && !into_pole &&
            !onOuterBorder(edge.first, edge.second, s, frame)) {
            ++report.open_edges;
            if (report.first_problem.empty()) {
                const glm::dvec3 g = gridOfKey(edge.first, s, frame);
                report.first_problem =
                    "open edge at column " + std::to_string(g.x) + ", row " + std::to_string(g.y);
            }
        }
        if (count > 2 && !polar_axis)
            ++report.overused_edges;
    }
    return report;
}

WatertightReport checkWatertight(const render::CapturedSurface& s, const lod::TerrainFrame& frame)
{
    WatertightReport report;
    const size_t instances = s.patches.size();
    std::vector<std::map<std::pair<VertexKey, VertexKey>, int>> edges(instances);
    std::vector<std::set<VertexKey>> surface_vertices(instances), foot_vertices(instances);
    // Skirt vertices on the patch border (the skirt's top, shared with the surface).
    std::vector<std::vector<glm::dvec3>> border(instances);
    const size_t triangles = s.vertices.size() / 3;
    report.triangles = triangles;
    // On a globe every vertex of a pole row is one point: the triangles of the polar cells
    // have two identical corners, cover nothing (the rasteriser drops them) and are left out.
    auto degenerate = [&](const render::CapturedVertex* v) {
        const VertexKey k0 = keyOf(v[0]), k1 = keyOf(v[1]), k2 = keyOf(v[2]);
        return frame.onEllipsoid() && (k0 == k1 || k1 == k2 || k0 == k2);
    };
    for (size_t t = 0; t < triangles; ++t) {
        const render::CapturedVertex* v = &s.vertices[3 * t];
        const size_t inst = size_t(v[0].instance);
        if (degenerate(v))
            continue;
        if (v[0].skirt)
            ++report.skirt_triangles;
        for (int e = 0; e < 3; ++e) {
            VertexKey a = keyOf(v[e]), b = keyOf(v[(e + 1) % 3]);
            if (b < a)
                std::swap(a, b);
            ++edges[inst][{a, b}];
            if (!v[0].skirt)
                surface_vertices[inst].insert(keyOf(v[e]));
            if (v[e].skirt == 2)
                foot_vertices[inst].insert(keyOf(v[e]));
        }
    }
    // The terrain's own outer border x = 0, x = W − 1, y = 0, y = H − 1 (finest samples) is
    // open by nature: skirts and the walls under clipped patches end there, vertically. Only
    // edges lying on it are exempt, so a surface that stops short of the border (a level whose
    // samples miss the last column) shows its open side.
    const double last_column = frame.geometry().width() - 1,
                 last_row = frame.geometry().height() - 1;
    auto onOuterBorder = [&](const VertexKey& a, const VertexKey& b, size_t instance) {
        const glm::dvec3 ga = gridOfKey(a, s, frame), gb = gridOfKey(b, s, frame);
        double ca = ga.x, cb = gb.x;
        const double ra = ga.y, rb = gb.y;
        // Globe: edges into a pole are not followed (a pole vertex has no column; the cap's
        // closure is checked by the pixels, GlobeConformance's no-background test).
        if (onPoleAxis(a, s, frame) || onPoleAxis(b, s, frame))
            return true;
        if (frame.onEllipsoid() && !frame.projectedGrid()) {
            // Columns from the longitude alone: a skirt or wall foot lies on its top's normal,
            // which stays in the top's meridian plane however deep (gridOf's latitude and
            // height do not survive thousands of kilometres down, the longitude does).
            ca = columnOfLongitude(a, s, frame);
            cb = columnOfLongitude(b, s, frame);
        }
        // On the globe a skirt or wall edge may be cut off the border's line: the clip shader
        // cuts a skirt's diagonal linearly in cell terms, and its top and foot hang along
        // normals that are not parallel, so the cut point strays from the column's line by
        // about depth × (the cell's angle)/2 (a skirt 1.3 km deep under 180 m cells: 1e-3
        // columns). Surface edges keep the tight test.
        const bool surface =
            surface_vertices[instance].count(a) && surface_vertices[instance].count(b);
        const double tolerance = frame.onEllipsoid() && !surface ? 1e-2 : 1e-3;
        auto both = [&](double u, double v, double line) {
            return std::abs(u - line) < tolerance && std::abs(v - line) < tolerance;
        };
        // A skirt's side cut at a globe's edge meridian: the clip shader cuts in cell terms,
        // linearly between vertices on both sides, and thousands of kilometres down such a
        // point strays from the meridian plane by up to a column (a surface edge keeps the
        // tight test).
        if (const double period = double(frame.geodetic().wrap_columns);
            frame.onEllipsoid() && period > 0 && !surface) {
            auto fromEdgeMeridian = [&](double c) { return std::min(c, period - c); };
            if (fromEdgeMeridian(ca) < 1.0 && fromEdgeMeridian(cb) < 1.0)
                return true;
        }
        return both(ca, cb, 0.0) || both(ca, cb, last_column) || both(ra, rb, 0.0) ||
               both(ra, rb, last_row);
    };
    for (size_t i = 0; i < instances; ++i) {
        for (const auto& [edge, count] : edges[i]) {
            const bool foot =
                foot_vertices[i].count(edge.first) && foot_vertices[i].count(edge.second);
            if (count == 1 && !foot && !onOuterBorder(edge.first, edge.second, i)) {
                ++report.open_edges;
                if (report.first_problem.empty()) {
                    const glm::dvec3 a = gridOfKey(edge.first, s, frame),
                                     b = gridOfKey(edge.second, s, frame);
                    report.first_problem =
                        "open edge in " + archive::ArchiveReader::patchName(s.patches[i]) +
                        " from column " + std::to_string(a.x) + ", row " + std::to_string(a.y) +
                        ", h " + std::to_string(a.z) + " to column " + std::to_string(b.x) +
                        ", row " + std::to_string(b.y) + ", h " + std::to_string(b.z);
                }
            }
            // Every vertex of a pole row is one point, and every skirt foot under it one
            // point of the polar axis: the cap's cells and the skirts of both sides of a
            // polar patch all meet on that segment (a line, not a fold that could hide a gap).
            const bool polar_axis =
                onPoleAxis(edge.first, s, frame) && onPoleAxis(edge.second, s, frame);
            // A patch spanning a whole turn of a wrapping globe meets itself at the edge
            // meridian: its west and east borders are one line, whose edges both sides'
            // surface and skirt use, as two patches meeting there would (four).
            const int64_t period = frame.onEllipsoid() ? frame.geodetic().wrap_columns : 0;
            const PatchId patch = s.patches[i];
            const bool whole_turn =
                period > 0 &&
                int64_t(frame.geometry().cells()) * frame.geometry().step(patch.level) >= period;
            auto onEdgeMeridian = [&](const VertexKey& k) {
                const double c = columnOfLongitude(k, s, frame);
                return onPoleAxis(k, s, frame) || c < 1e-3 || c > double(period) - 1e-3;
            };
            const bool self_seam = whole_turn && count <= 4 && onEdgeMeridian(edge.first) &&
                                   onEdgeMeridian(edge.second);
            if (count > 2 && !polar_axis && !self_seam) {
                ++report.overused_edges;
                if (report.first_problem.empty()) {
                    const glm::dvec3 a = gridOfKey(edge.first, s, frame),
                                     b = gridOfKey(edge.second, s, frame);
                    report.first_problem = "edge used " + std::to_string(count) + " times in " +
                                           archive::ArchiveReader::patchName(s.patches[i]) +
                                           " from column " + std::to_string(a.x) + ", row " +
                                           std::to_string(a.y) + ", h " + std::to_string(a.z) +
                                           " to column " + std::to_string(b.x) + ", row " +
                                           std::to_string(b.y) + ", h " + std::to_string(b.z);
                }
            }
        }
    }
    // Border profiles from skirt triangles whose vertex is also a surface vertex.
    for (size_t t = 0; t < triangles; ++t) {
        const render::CapturedVertex* v = &s.vertices[3 * t];
        if (!v[0].skirt || degenerate(v))
            continue;
        const size_t inst = size_t(v[0].instance);
        for (int e = 0; e < 3; ++e)
            if (surface_vertices[inst].count(keyOf(v[e])))
                border[inst].push_back(gridOfVertex(v[e].x, v[e].y, v[e].z, s, frame));
    }

    const PyramidGeometry& g = frame.geometry();
    auto profileAlong = [&](size_t inst, bool vertical_seam, double line) {
        SeamProfile profile;
        for (const glm::dvec3& p : border[inst]) {
            const double across = vertical_seam ? p.x : p.y, along = vertical_seam ? p.y : p.x;
            if (std::abs(across - line) < 1e-3)
                profile.push_back({along, p.z});
        }
        std::sort(profile.begin(), profile.end());
        return profile;
    };
    for (size_t a = 0; a < instances; ++a) {
        const Footprint fa = footprintOf(s.patches[a], g);
        for (size_t b = 0; b < instances; ++b) {
            if (a == b)
                continue;
            const Footprint fb = footprintOf(s.patches[b], g);
            // Seams where b lies east of a, or south of a (each pair once per seam).
            const bool east = fa.c1 == fb.c0 && std::max(fa.r0, fb.r0) < std::min(fa.r1, fb.r1);
            const bool south = fa.r1 == fb.r0 && std::max(fa.c0, fb.c0) < std::min(fa.c1, fb.c1);
            if (!east && !south)
                continue;
            const double line = east ? double(fa.c1) : double(fa.r1);
            const SeamProfile pa = profileAlong(a, east, line), pb = profileAlong(b, east, line);
            if (pa.empty() || pb.empty()) {
                ++report.uncovered_seams;
                if (report.first_problem.empty())
                    report.first_problem = "seam without skirt vertices";
                continue;
            }
            const double lo =
                east ? double(std::max(fa.r0, fb.r0)) : double(std::max(fa.c0, fb.c0));
            const double hi =
                east ? double(std::min(fa.r1, fb.r1)) : double(std::min(fa.c1, fb.c1));
            std::vector<double> positions;
            for (const auto& q : pa)
                positions.push_back(q.first);
            for (const auto& q : pb)
                positions.push_back(q.first);
            for (double t : positions) {
                if (t < lo - 1e-6 || t > hi + 1e-6)
                    continue;
                ++report.seams_checked;
                const double ha = heightAt(pa, t), hb = heightAt(pb, t);
                const double bottom_of_higher =
                    ha >= hb ? ha - s.skirt_depth[a] : hb - s.skirt_depth[b];
                if (bottom_of_higher > std::min(ha, hb) + 1e-3) {
                    ++report.uncovered_seams;
                    if (report.first_problem.empty())
                        report.first_problem = "gap not covered by a skirt between " +
                                               archive::ArchiveReader::patchName(s.patches[a]) +
                                               " and " +
                                               archive::ArchiveReader::patchName(s.patches[b]);
                }
            }
        }
    }
    return report;
}

ScreenErrorReport measureScreenSpaceError(const render::CapturedSurface& s,
                                          const lod::TerrainFrame& frame,
                                          const std::vector<float>& finest,
                                          const lod::Camera& camera)
{
    ScreenErrorReport report;
    std::vector<double> deviations;
    const int W = frame.geometry().width(), H = frame.geometry().height();
    std::vector<uint8_t> covered(size_t(W) * H, 0), inside(size_t(W) * H, 0);
    const glm::dvec3 c = s.camera_position;
    const lod::Viewport vp = camera.viewport();
    auto inView = [&](glm::dvec3 p, glm::dvec2& px) {
        if (!camera.project(p, px))
            return false;
        const double depth = glm::dot(p - camera.position(), camera.forward());
        // GL clips at the near plane; the frustum test culls boxes in front of it.
        return px.x >= 0 && px.y >= 0 && px.x <= vp.width && px.y <= vp.height &&
               depth >= camera.nearPlane() && depth < camera.farPlane();
    };
    for (size_t t = 0; t + 2 < s.vertices.size(); t += 3) {
        const render::CapturedVertex* v = &s.vertices[t];
        if (v[0].skirt)
            continue;
        glm::dvec3 q[3];
        // Vertices lie on samples, except where the clipping shader cut an edge at the
        // border (there they may fall between samples along it): snapping to the nearest
        // sample undoes the float error of camera-relative positions (~1e-5 samples here)
        // and leaves cut points alone.
        auto snap = [](double u) {
            const double r = std::round(u);
            return std::abs(u - r) < 1e-3 ? r : u;
        };
        glm::dvec3 world[3]; // globe: the drawn triangle's corners
        for (int k = 0; k < 3; ++k) {
            if (frame.onEllipsoid()) {
                world[k] = c + glm::dvec3(v[k].x, v[k].y, v[k].z);
                const glm::dvec3 g = frame.gridOf(world[k]);
                q[k] = {snap(g.x), snap(g.y), g.z};
                continue;
            }
            q[k] = {snap(frame.columnOf(v[k].x + c.x)), snap(frame.rowOf(v[k].y + c.y)),
                    double(v[k].z) + c.z};
        }
        if (frame.onEllipsoid()) {
            // A pole vertex has no column of its own (every one is the same point): such
            // triangles are not measured, nor the pole rows' samples below. What they cover
            // is: in grid terms a fan triangle (pole, A, B) is the band from A's and B's
            // columns up to the pole row.
            const int at_pole = int(frame.poleRow(q[0].y)) + int(frame.poleRow(q[1].y)) +
                                int(frame.poleRow(q[2].y));
            if (at_pole == 1)
                markPoleBand(q, frame, covered);
            if (at_pole > 0)
                continue;
            // A triangle on the wrap seam: its columns in one period.
            const double period = double(frame.geodetic().wrap_columns);
            if (period > 0 &&
                std::max({q[0].x, q[1].x, q[2].x}) - std::min({q[0].x, q[1].x, q[2].x}) >
                    0.5 * period)
                for (glm::dvec3& p : q)
                    if (p.x < 0.5 * period)
                        p.x += period;
        }
        // A sample on a shared edge must fall inside one of its two triangles: barycentric
        // slack for the corners' grid positions, which near a pole carry the float error of
        // camera-relative positions magnified by 1 / cos φ.
        const double kInside = frame.onEllipsoid() ? 1e-4 : 1e-6;
        const double det =
            (q[1].y - q[2].y) * (q[0].x - q[2].x) + (q[2].x - q[1].x) * (q[0].y - q[2].y);
        if (std::abs(det) < 1e-12)
            continue;
        markInside(q, det, frame, inside, report.overlapped);
        const int c0 = std::max(0, int(std::ceil(std::min({q[0].x, q[1].x, q[2].x}) - 1e-6)));
        const int c1 = std::min(W - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}) + 1e-6)));
        const int r0 = std::max(0, int(std::ceil(std::min({q[0].y, q[1].y, q[2].y}) - 1e-6)));
        const int r1 = std::min(H - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}) + 1e-6)));
        for (int r = r0; r <= r1; ++r)
            for (int col = c0; col <= c1; ++col) {
                const double l0 =
                    ((q[1].y - q[2].y) * (col - q[2].x) + (q[2].x - q[1].x) * (r - q[2].y)) / det;
                const double l1 =
                    ((q[2].y - q[0].y) * (col - q[2].x) + (q[0].x - q[2].x) * (r - q[2].y)) / det;
                const double l2 = 1.0 - l0 - l1;
                if (l0 < -kInside || l1 < -kInside || l2 < -kInside)
                    continue;
                covered[size_t(r) * W + col] = 1;
                const double z_lod = l0 * q[0].z + l1 * q[1].z + l2 * q[2].z;
                const double z_true = finest[size_t(r) * W + col];
                glm::dvec3 p_true(frame.xOf(col), frame.yOf(r), z_true),
                    p_lod(p_true.x, p_true.y, z_lod);
                if (frame.onEllipsoid()) {
                    // The flat triangle's point over the sample, against the sample itself:
                    // the chord's sag below the curved surface is error too.
                    p_true = frame.worldOf(col, r, z_true);
                    p_lod = l0 * world[0] + l1 * world[1] + l2 * world[2];
                }
                glm::dvec2 a, b;
                if (!inView(p_true, a) || !camera.project(p_lod, b))
                    continue;
                ++report.samples;
                deviations.push_back(glm::length(a - b));
                report.max_px = std::max(report.max_px, glm::length(a - b));
                report.max_metres =
                    std::max(report.max_metres, frame.onEllipsoid() ? glm::length(p_lod - p_true)
                                                                    : std::abs(z_lod - z_true));
            }
    }
    const lod::HorizonOccluder horizon(frame, camera.position(),
                                       double(*std::min_element(finest.begin(), finest.end())));
    for (int r = 0; r < H; ++r)
        for (int col = 0; col < W; ++col) {
            glm::dvec2 px;
            const double z = finest[size_t(r) * W + col];
            if (frame.onEllipsoid() && frame.poleRow(r))
                continue;
            // Behind the Earth: culled with reason (lod::HorizonOccluder), not uncovered.
            if (horizon.hides(frame.worldOf(col, r, z)))
                continue;
            if (!covered[size_t(r) * W + col] &&
                inView(frame.onEllipsoid() ? frame.worldOf(col, r, z)
                                           : glm::dvec3(frame.xOf(col), frame.yOf(r), z),
                       px))
                ++report.uncovered;
        }
    if (!deviations.empty()) {
        const auto p99 = deviations.begin() + std::ptrdiff_t(deviations.size() * 99 / 100);
        std::nth_element(deviations.begin(), p99, deviations.end());
        report.p99_px = *p99;
    }
    return report;
}

SeamReport checkSeamsAsPromised(render::TerrainRenderer& renderer, const lod::Camera& camera,
                                render::RenderSettings settings, const lod::TerrainFrame& frame)
{
    SeamReport out;
    out.stitched = render::lodSchemePromises(settings.scheme).seams ==
                   render::SchemePromises::Seams::Stitching;
    settings.cull_blocks = false;
    if (out.stitched) {
        settings.cull = false;
        const StitchedReport w = checkStitchedWatertight(renderer.capture(camera, settings), frame);
        out.triangles = w.triangles;
        out.degenerate = w.degenerate;
        out.problems = w.open_edges + w.overused_edges + (w.triangles <= w.degenerate ? 1 : 0);
        out.first_problem =
            w.triangles <= w.degenerate ? "nothing but degenerate triangles" : w.first_problem;
    } else {
        const WatertightReport w = checkWatertight(renderer.capture(camera, settings), frame);
        out.triangles = w.triangles;
        out.problems = w.open_edges + w.overused_edges + w.uncovered_seams;
        out.first_problem = w.first_problem;
    }
    return out;
}

} // namespace ridge::test
