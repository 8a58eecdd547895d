#include "camera_readout.h"

#include "ridge/core/error.h"
#include "ridge/io/crs_summary.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

namespace ridge::cli {

namespace {

// "27.988123° N, 86.925012° E": latitude first, hemispheres spelled out, as people read them.
std::string latitudeLongitude(glm::dvec2 lon_lat)
{
    return fmt::format("{:.6f}° {}, {:.6f}° {}", std::abs(lon_lat.y), lon_lat.y < 0 ? 'S' : 'N',
                       std::abs(lon_lat.x), lon_lat.x < 0 ? 'W' : 'E');
}

} // namespace

CameraReadout::CameraReadout(const archive::ArchiveReader& reader) : georeference_(reader)
{
    const std::string& wkt = reader.metadata().georeference.crs_wkt;
    if (wkt.empty())
        return;
    try {
        const io::CrsSummary crs = io::summarizeCrs(wkt, reader.path());
        crs_label_ = crs.name + (crs.epsg ? fmt::format(" (EPSG:{})", *crs.epsg) : "");
        wgs84_lon_lat_crs_ = crs.horizontal_epsg == 4326;
    } catch (const Error&) {
        crs_label_ = "archive CRS"; // PROJ cannot name it; the geotransform still applies
    }
}

std::vector<std::string> CameraReadout::positionLines(glm::dvec3 p) const
{
    std::vector<std::string> lines;
    lines.push_back(fmt::format("terrain frame: x {:.1f}, y {:.1f}, z {:.1f} m", p.x, p.y, p.z));
    // PROJ refuses points outside a projection's domain: that frame's line is left out.
    if (georeference_.hasGeotransform() && !crs_label_.empty() && !wgs84_lon_lat_crs_) {
        try {
            const glm::dvec2 c = georeference_.fromLocal({p.x, p.y}, PointSpace::Crs);
            lines.push_back(crs_label_ + ": " +
                            (georeference_.geographicCrs()
                                 ? latitudeLongitude(c)
                                 : fmt::format("E {:.2f} m, N {:.2f} m", c.x, c.y)));
        } catch (const Error&) {
        }
    }
    if (georeference_.hasGeotransform() && georeference_.hasCrs()) {
        try {
            const glm::dvec2 ll = georeference_.fromLocal({p.x, p.y}, PointSpace::LonLat);
            lines.push_back((wgs84_lon_lat_crs_ ? crs_label_ : std::string("WGS 84")) + ": " +
                            latitudeLongitude(ll));
        } catch (const Error&) {
        }
    }
    return lines;
}

double CameraReadout::flySpeed(double height_above_ground_m, double rate)
{
    const double height = std::max(std::abs(height_above_ground_m), kMinSpeedHeightMetres);
    return std::clamp(rate, kMinSpeedRate, kMaxSpeedRate) * height;
}

} // namespace ridge::cli
