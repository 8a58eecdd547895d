#include "ridge/web/tile_sampler.h"

#include "ridge/core/error.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::web {

namespace {

constexpr double kWgs84A = 6378137.0;
constexpr int kBorderPoints = 256; // per side, tracing the archive's outline to lon/lat

// Metres per degree of latitude (and of longitude at the equator) on a sphere of radius a:
// close enough to choose a level by.
constexpr double kMetresPerDegree = kWgs84A * std::numbers::pi / 180.0;

// Each missing sample (valid[i] 0) takes the height of its nearest valid one (breadth
// first over the grid's 4-neighbours, ties to the first reached): the surface goes on flat
// past the archive's edge and its nodata instead of dropping to 0 m, which would put a cliff
// inside the tile's cells at the edge of the data (5,332 m on the Everest fixture's border).
void fillFromNearest(std::vector<float>& heights, int columns, std::vector<uint8_t>& valid)
{
    std::vector<uint32_t> queue;
    queue.reserve(heights.size());
    for (uint32_t i = 0; i < heights.size(); ++i)
        if (valid[i])
            queue.push_back(i);
    for (size_t head = 0; head < queue.size(); ++head) {
        const uint32_t i = queue[head];
        const int rows = int(heights.size()) / columns;
        const int r = int(i) / columns, c = int(i) % columns;
        const int neighbours[4][2] = {{r - 1, c}, {r + 1, c}, {r, c - 1}, {r, c + 1}};
        for (const auto& [nr, nc] : neighbours) {
            if (nr < 0 || nr >= rows || nc < 0 || nc >= columns)
                continue;
            const uint32_t n = uint32_t(nr * columns + nc);
            if (valid[n])
                continue;
            valid[n] = 1;
            heights[n] = heights[i];
            queue.push_back(n);
        }
    }
}

void checkKey(TileKey k)
{
    if (!GeographicTms::valid(k))
        throw Error("web tile " + std::to_string(k.z) + "/" + std::to_string(k.x) + "/" +
                    std::to_string(k.y) + " is not a geographic tile");
}

// Pixel/line coordinate of level sample `i` (a column or row) `step` finest samples apart:
// finest sample min(i·step, finest − 1), the centre of its pixel.
double samplePixel(int64_t i, double step, int64_t finest)
{
    return std::min(double(i) * step, double(finest - 1)) + 0.5;
}

} // namespace

TileSampler::TileSampler(const std::string& archive_path, size_t cache_patches)
    : query_(archive_path, cache_patches)
{
    const TerrainGeoreference& g = query_.georeference();
    const std::optional<std::array<double, 6>>& gt =
        query_.reader().metadata().georeference.geotransform;
    north_up_geographic_ = g.geographicCrs() && gt && (*gt)[2] == 0.0 && (*gt)[4] == 0.0 &&
                           (*gt)[1] > 0.0 && (*gt)[5] < 0.0;
    if (!g.hasCrs() || !g.hasGeotransform())
        throw Error(archive_path + ": web tiles need longitude/latitude, and the archive has no " +
                    (g.hasCrs() ? "geotransform" : "CRS"));
    const archive::ArchiveReader& reader = query_.reader();
    level_bounds_.assign(size_t(reader.geometry().finestLevel() + 1), 0.0);
    for (const archive::PatchRecord& r : reader.index())
        level_bounds_[r.level] = std::max(level_bounds_[r.level], double(r.err));
    // The outline of the raster's pixels, in lon/lat: a projected raster's border is curved
    // there, so it is traced, not just its corners.
    const double w = double(query_.reader().geometry().width());
    const double h = double(query_.reader().geometry().height());
    extent_ = {180.0, 90.0, -180.0, -90.0};
    for (int k = 0; k <= kBorderPoints; ++k) {
        const double t = double(k) / kBorderPoints;
        for (const glm::dvec2 pixel : {glm::dvec2(t * w, 0.0), glm::dvec2(t * w, h),
                                       glm::dvec2(0.0, t * h), glm::dvec2(w, t * h)}) {
            const glm::dvec2 ll = g.fromLocal(g.localOfPixel(pixel), PointSpace::LonLat);
            extent_.west = std::min(extent_.west, ll.x);
            extent_.east = std::max(extent_.east, ll.x);
            extent_.south = std::min(extent_.south, ll.y);
            extent_.north = std::max(extent_.north, ll.y);
        }
    }
}

std::string TileSampler::verticalReference() const
{
    const archive::ArchiveMetadata& m = query_.reader().metadata();
    if (m.build.vertical_shift)
        return "ellipsoid";
    if (m.georeference.vertical_datum)
        return m.georeference.vertical_datum->name;
    return "unknown";
}

std::optional<int> TileSampler::verticalDatumEpsg() const
{
    const archive::ArchiveMetadata& m = query_.reader().metadata();
    if (m.build.vertical_shift || !m.georeference.vertical_datum)
        return std::nullopt;
    return m.georeference.vertical_datum->epsg;
}

std::string TileSampler::toEllipsoid(int epsg, const std::string& name)
{
    geoid_ = std::make_unique<io::GeoidModel>(query_.reader().path(), epsg, name);
    return geoid_->operation();
}

void TileSampler::addUndulations(std::span<float> heights, PointSpace space)
{
    if (!geoid_)
        return;
    const TerrainGeoreference& g = query_.georeference();
    lonlat_.resize(heights.size());
    for (size_t i = 0; i < heights.size(); ++i) {
        const glm::dvec2 ll = space == PointSpace::LonLat
                                  ? points_[i]
                                  : g.fromLocal(g.localOfPixel(points_[i]), PointSpace::LonLat);
        lonlat_[i] = {ll.x, ll.y};
    }
    undulations_.resize(heights.size());
    geoid_->undulations(lonlat_, undulations_);
    for (size_t i = 0; i < heights.size(); ++i)
        heights[i] = float(double(heights[i]) + undulations_[i]);
}

bool TileSampler::overlaps(TileKey k) const
{
    return overlapsRect(GeographicTms::rect(k));
}

bool TileSampler::overlapsRect(const GeoRect& r) const
{
    if (r.south > extent_.north || r.north < extent_.south)
        return false;
    // The extent's longitudes may run past ±180° (a 0..360° E grid): a tile 360° on counts.
    for (const double s : {0.0, 360.0, -360.0})
        if (r.west + s <= extent_.east && r.east + s >= extent_.west)
            return true;
    return false;
}

double TileSampler::finestSpacingMetres() const
{
    const lod::TerrainFrame& f = query_.georeference().frame();
    return std::min(f.spacingX(), f.spacingY());
}

int TileSampler::levelFor(TileKey k, int cells) const
{
    // The tile's sample spacing, metres, along its meridians (the shorter way on a
    // geographic tile away from the equator is along parallels, but a level chosen by the
    // meridians keeps at least the tile's density there too within cos(latitude)).
    return levelForSpacing(180.0 / double(GeographicTms::tilesY(k.z)) / cells * kMetresPerDegree);
}

int TileSampler::levelForSpacing(double metres) const
{
    const int finest = query_.finestLevel();
    const double ratio = metres / finestSpacingMetres();
    if (!(ratio > 1.0))
        return finest;
    const int coarser = int(std::floor(std::log2(ratio)));
    return std::max(0, finest - coarser);
}

int TileSampler::maxZoom(int cells) const
{
    const double finest = finestSpacingMetres();
    int z = 0;
    while (z < kMaxTileZoom &&
           180.0 / double(GeographicTms::tilesY(z + 1)) / cells * kMetresPerDegree >= finest)
        ++z;
    return z;
}

bool TileSampler::placeOnSamples(TileKey k, int level, int cells, TileHeights& grid)
{
    if (!north_up_geographic_)
        return false;
    // Pixel/line of the tile's edges straight from the geotransform (not through PROJ), the
    // same arithmetic for every tile, so neighbours compute their shared edge bit for bit.
    const std::array<double, 6>& gt = *query_.reader().metadata().georeference.geotransform;
    const PyramidGeometry& geometry = query_.reader().geometry();
    GeoRect r = GeographicTms::rect(k);
    // A grid in another period (0..360° E) holds the tile 360° on: the period that overlaps
    // the grid most. Heights on a meridian the grid repeats (ETOPO's 0° and 360°) are the
    // same samples, so tiles on either side of the seam still meet.
    const double grid_west = gt[0], grid_east = gt[0] + double(geometry.width()) * gt[1];
    double best_overlap = -1.0, shift = 0.0;
    for (const double s : {0.0, 360.0, -360.0}) {
        const double overlap = std::min(r.east + s, grid_east) - std::max(r.west + s, grid_west);
        if (overlap > best_overlap + 1e-9) {
            best_overlap = overlap;
            shift = s;
        }
    }
    r.west += shift;
    r.east += shift;
    const double px_w = (r.west - gt[0]) / gt[1], px_e = (r.east - gt[0]) / gt[1];
    const double py_n = (r.north - gt[3]) / gt[5], py_s = (r.south - gt[3]) / gt[5];
    if (!(px_e > px_w && py_s > py_n))
        return false;
    const double step = double(geometry.step(level));
    constexpr int32_t kMax = QuantizedMesh::kMaxCoordinate;
    // The level's sample centres strictly inside (lo, hi), as format coordinates 1..32766
    // (ones that round onto an edge or onto the previous line are left out).
    const auto inner = [&](double lo, double hi, int count, int64_t finest, std::vector<double>& at,
                           std::vector<int32_t>& lines) {
        at.assign(1, lo);
        lines.assign(1, 0);
        const int first = std::max(0, int(std::floor((lo - 0.5) / step)));
        for (int i = first; i < count; ++i) {
            const double p = samplePixel(i, step, finest);
            if (p <= lo)
                continue;
            if (p >= hi)
                break;
            const int32_t q = int32_t(std::lround((p - lo) / (hi - lo) * kMax));
            if (q <= lines.back() || q >= kMax)
                continue;
            at.push_back(p);
            lines.push_back(q);
        }
        at.push_back(hi);
        lines.push_back(kMax);
        // Gaps the level leaves (the part of a tile off the archive, where it has no
        // samples) get evenly spaced lines no wider than a `cells` grid's cell or the level's
        // own spacing, so the mesh can follow the globe's curvature there (terrain_tile.h).
        // The same rule on both sides of an edge.
        const double spacing = step / (hi - lo) * kMax; // the level's, in format units
        const int32_t widest = int32_t(std::ceil(std::max(double(kMax) / cells, spacing)));
        const double gap_limit = std::max(double(widest), 1.5 * spacing);
        std::vector<double> filled_at;
        std::vector<int32_t> filled;
        for (size_t i = 0; i < lines.size(); ++i) {
            if (i > 0 && double(lines[i] - lines[i - 1]) > gap_limit) {
                // On the lattice of multiples of `widest`, which both tiles of an edge share
                // (their lines along it span the same range), at least half a cell from the
                // gap's ends.
                const int32_t a = lines[i - 1], b = lines[i];
                for (int32_t q = (a / widest + 1) * widest; q < b; q += widest)
                    if (q - a >= widest / 2 && b - q >= widest / 2) {
                        filled.push_back(q);
                        filled_at.push_back(lo + (hi - lo) * double(q) / kMax);
                    }
            }
            filled.push_back(lines[i]);
            filled_at.push_back(at[i]);
        }
        lines.swap(filled);
        at.swap(filled_at);
    };
    std::vector<double> xs, ys;
    std::vector<int32_t> rows;
    inner(px_w, px_e, geometry.levelWidth(level), geometry.width(), xs, grid.u);
    inner(py_n, py_s, geometry.levelHeight(level), geometry.height(), ys, rows);
    grid.v.resize(rows.size()); // rows run south: v = 32767 − their offset from the north
    for (size_t i = 0; i < rows.size(); ++i)
        grid.v[i] = kMax - rows[i];
    points_.resize(xs.size() * ys.size());
    for (size_t r = 0; r < ys.size(); ++r)
        for (size_t c = 0; c < xs.size(); ++c)
            points_[r * xs.size() + c] = {xs[c], ys[r]};
    return true;
}

std::pair<glm::dvec2, glm::dvec2> TileSampler::pixelWindow(TileKey k) const
{
    const GeoRect r = GeographicTms::rect(k);
    const TerrainGeoreference& g = query_.georeference();
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (int i = 0; i <= 16; ++i) {
        const double t = i / 16.0;
        for (const glm::dvec2 ll : {glm::dvec2(r.west + t * (r.east - r.west), r.south),
                                    glm::dvec2(r.west + t * (r.east - r.west), r.north),
                                    glm::dvec2(r.west, r.south + t * (r.north - r.south)),
                                    glm::dvec2(r.east, r.south + t * (r.north - r.south))}) {
            const glm::dvec2 p = g.toPixel(ll, PointSpace::LonLat);
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    }
    return {lo, hi};
}

double TileSampler::levelBound(int level) const
{
    if (level < 0 || level >= int(level_bounds_.size()))
        throw Error("web tile level " + std::to_string(level) + " outside [0, " +
                    std::to_string(int(level_bounds_.size()) - 1) + "]");
    return level_bounds_[size_t(level)];
}

int TileSampler::levelWithin(int zoom, int cells, double error) const
{
    const int finest = query_.finestLevel();
    // A tile's side in finest samples, along the meridians (as levelFor measures it).
    const double across =
        180.0 / double(GeographicTms::tilesY(zoom)) * kMetresPerDegree / finestSpacingMetres();
    int level = levelFor({zoom, 0, 0}, cells);
    while (level < finest && levelBound(level) > error &&
           across / double(query_.reader().geometry().step(level + 1)) <= kMaxTileSamples)
        ++level;
    return level;
}

std::optional<SampledTile> TileSampler::sample(TileKey k, int cells, int level)
{
    checkKey(k);
    if (cells < 1 || cells > 4096)
        throw Error("web tile cells " + std::to_string(cells) + " outside [1, 4096]");
    if (level > query_.finestLevel())
        throw Error("web tile level " + std::to_string(level) + " outside [0, " +
                    std::to_string(query_.finestLevel()) + "]");

    SampledTile out;
    out.level = level < 0 ? levelFor(k, cells) : level;
    // On the level's own samples where the archive is a north-up geographic grid; else a
    // uniform grid of `cells` cells read through PROJ. Row 0 is the northern edge.
    PointSpace space = PointSpace::Pixel;
    if (!placeOnSamples(k, out.level, cells, out.grid)) {
        out.grid = uniformTileHeights(k, cells);
        const int side = cells + 1;
        points_.resize(size_t(side) * size_t(side));
        for (int r = 0; r < side; ++r)
            for (int c = 0; c < side; ++c)
                points_[size_t(r) * side + size_t(c)] = {
                    GeographicTms::longitude(k, c, cells),
                    GeographicTms::latitude(k, cells - r, cells)};
        space = PointSpace::LonLat;
    }
    out.grid.key = k;
    const size_t valid = readPoints(space, out.level, out.grid.heights, out.flags,
                                    out.archive_error, out.off_raster, out.nodata);
    if (valid == 0)
        return std::nullopt; // PROJ placed none of the tile's points
    if (valid < points_.size())
        fillFromNearest(out.grid.heights, int(out.grid.u.size()), valid_);
    addUndulations(out.grid.heights, PointSpace::Pixel);
    return out;
}

size_t TileSampler::readPoints(PointSpace space, int level, std::vector<float>& heights,
                               std::vector<uint8_t>& flags, double& archive_error,
                               size_t& off_raster, size_t& nodata)
{
    const TerrainGeoreference& g = query_.georeference();
    const double w = double(query_.reader().geometry().width());
    const double h = double(query_.reader().geometry().height());
    // Every point as pixel/line, then clamped into the raster: off it, the raster's edge
    // goes on outwards (the clamped point's height).
    unreadable_.assign(points_.size(), 0);
    outside_.assign(points_.size(), 0);
    fade_.assign(points_.size(), 1.0);
    for (size_t i = 0; i < points_.size(); ++i) {
        glm::dvec2& p = points_[i];
        if (space == PointSpace::LonLat) {
            try {
                p = g.toPixel(p, PointSpace::LonLat);
            } catch (const Error&) {
                unreadable_[i] = 1; // PROJ cannot place it
                p = {0.5, 0.5};
                continue;
            }
        }
        if (!(p.x >= 0.0 && p.x <= w && p.y >= 0.0 && p.y <= h)) {
            outside_[i] = 1;
            const glm::dvec2 clamped(std::clamp(p.x, 0.0, w), std::clamp(p.y, 0.0, h));
            // The edge's height fades to 0 m over the raster's own size beyond it.
            fade_[i] = std::max(0.0, 1.0 - glm::length(p - clamped) / std::max(w, h));
            p = clamped;
        }
    }
    samples_.resize(points_.size());
    query_.sampleBatch(points_, PointSpace::Pixel, level, QueryResampling::Bilinear, samples_);
    heights.assign(points_.size(), 0.f);
    valid_.assign(points_.size(), 0);
    flags.assign(points_.size(), SampledTile::kAbsent);
    for (size_t i = 0; i < samples_.size(); ++i) {
        const HeightSample& s = samples_[i];
        if (unreadable_[i] || !s.on_raster || s.invalid_point) {
            ++off_raster;
            continue; // filled from the nearest valid sample (the caller's grid)
        }
        valid_[i] = 1;
        archive_error = std::max(archive_error, s.error_bound);
        if (s.nodata) {
            ++nodata;
            heights[i] = float(s.nodata_fill);
        } else if (outside_[i]) {
            ++off_raster;
            heights[i] = float(s.height * fade_[i]);
        } else {
            heights[i] = float(s.height);
            flags[i] = s.water ? SampledTile::kWater : 0;
        }
    }
    // What was read is kept (valid_ marks it); only unreadable points are filled by the
    // caller, and a tile none of whose points could be read is not made.
    return size_t(std::count(valid_.begin(), valid_.end(), uint8_t(1)));
}

bool TileSampler::overlapsMercator(TileKey k) const
{
    if (!WebMercatorXyz::valid(k))
        throw Error("web tile " + std::to_string(k.z) + "/" + std::to_string(k.x) + "/" +
                    std::to_string(k.y) + " is not a Web Mercator tile");
    return overlapsRect(WebMercatorXyz::rect(k));
}

int TileSampler::levelForMercator(TileKey k, int size) const
{
    const GeoRect r = WebMercatorXyz::rect(k);
    return levelForSpacing(WebMercatorXyz::metresPerPixel(k.z, 0.5 * (r.south + r.north), size));
}

int TileSampler::maxMercatorZoom(int size) const
{
    const double lat = std::clamp(0.5 * (extent_.south + extent_.north), -85.0, 85.0);
    const double finest = finestSpacingMetres();
    int z = 0;
    while (z < kMaxTileZoom && WebMercatorXyz::metresPerPixel(z + 1, lat, size) >= finest)
        ++z;
    return z;
}

std::optional<MercatorSamples> TileSampler::sampleMercator(TileKey k, int size)
{
    if (size < 1 || size > 4096)
        throw Error("web tile size " + std::to_string(size) + " outside [1, 4096]");
    if (!overlapsMercator(k))
        return std::nullopt;
    MercatorSamples out;
    out.size = size;
    out.level = levelForMercator(k, size);
    points_.resize(size_t(size) * size_t(size));
    for (int j = 0; j < size; ++j) {
        const double lat = WebMercatorXyz::latitude(k, j, size);
        for (int i = 0; i < size; ++i)
            points_[size_t(j) * size_t(size) + size_t(i)] = {WebMercatorXyz::longitude(k, i, size),
                                                             lat};
    }
    // A grid in 0..360° E holds western longitudes one period on.
    if (extent_.east > 180.0)
        for (glm::dvec2& p : points_)
            if (p.x < extent_.west)
                p.x += 360.0;
    std::vector<uint8_t> flags;
    size_t off_raster = 0, nodata = 0;
    const size_t read = readPoints(PointSpace::LonLat, out.level, out.heights, flags,
                                   out.archive_error, off_raster, nodata);
    if (read == 0)
        return std::nullopt;
    out.missing = off_raster + nodata;
    if (read < out.heights.size())
        fillFromNearest(out.heights, size, valid_);
    return out;
}

std::vector<TileSampler::LevelSample> TileSampler::levelSamples(TileKey k, int level, size_t limit)
{
    checkKey(k);
    if (level < 0 || level > query_.finestLevel())
        throw Error("web tile level " + std::to_string(level) + " outside [0, " +
                    std::to_string(query_.finestLevel()) + "]");
    std::vector<LevelSample> out;
    if (!overlaps(k))
        return out;
    const auto [lo, hi] = pixelWindow(k);
    const GeoRect r = GeographicTms::rect(k);
    const TerrainGeoreference& g = query_.georeference();
    const PyramidGeometry& geometry = query_.reader().geometry();
    // Level sample (i, j) is finest sample (i·s, j·s), the centre of pixel (i·s + ½, j·s + ½).
    const double s = double(geometry.step(level));
    const int w = geometry.levelWidth(level), h = geometry.levelHeight(level);
    const int i0 = std::clamp(int(std::floor((lo.x - 0.5) / s)) - 1, 0, w - 1);
    const int i1 = std::clamp(int(std::ceil((hi.x - 0.5) / s)) + 1, 0, w - 1);
    const int j0 = std::clamp(int(std::floor((lo.y - 0.5) / s)) - 1, 0, h - 1);
    const int j1 = std::clamp(int(std::ceil((hi.y - 0.5) / s)) + 1, 0, h - 1);
    points_.clear();
    std::vector<glm::dvec2> lonlat;
    for (int j = j0; j <= j1 && points_.size() < limit; ++j)
        for (int i = i0; i <= i1 && points_.size() < limit; ++i) {
            const glm::dvec2 pixel(samplePixel(i, s, geometry.width()),
                                   samplePixel(j, s, geometry.height()));
            const glm::dvec2 ll = g.fromLocal(g.localOfPixel(pixel), PointSpace::LonLat);
            if (ll.x < r.west || ll.x > r.east || ll.y < r.south || ll.y > r.north)
                continue;
            points_.push_back(pixel);
            lonlat.push_back(ll);
        }
    samples_.resize(points_.size());
    query_.sampleBatch(points_, PointSpace::Pixel, level, QueryResampling::Nearest, samples_);
    for (size_t i = 0; i < samples_.size(); ++i)
        if (samples_[i].on_raster && !samples_[i].nodata && !samples_[i].invalid_point)
            out.push_back({lonlat[i].x, lonlat[i].y, samples_[i].height});
    if (geoid_) {
        lonlat_.resize(out.size());
        for (size_t i = 0; i < out.size(); ++i)
            lonlat_[i] = {out[i].lon, out[i].lat};
        undulations_.resize(out.size());
        geoid_->undulations(lonlat_, undulations_);
        for (size_t i = 0; i < out.size(); ++i)
            out[i].height += undulations_[i];
    }
    return out;
}

} // namespace ridge::web
