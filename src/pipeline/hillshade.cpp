#include "ridge/pipeline/hillshade.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/terrain_palette.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/level_decoder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace ridge {

namespace {

uint8_t toByte(double v) { return static_cast<uint8_t>(std::clamp(std::lround(v * 255.0), 0L, 255L)); }

} // namespace

void HillshadeOptions::validate() const
{
    checkParameter("level", int64_t{level}, -1, kMaxLevel);
    checkParameter("azimuth (degrees)", azimuth, kAzimuthDegreesRange);
    checkParameter("altitude (degrees)", altitude, kAltitudeDegreesRange);
    checkParameter("z_factor", z_factor, kZFactorRange);
}

std::vector<uint8_t> shadeRelief(const std::vector<float>& metres, int width, int height,
                                 double spacing_x, double spacing_y, const HillshadeOptions& options)
{
    options.validate();
    const double spacing[2] = {spacing_x, spacing_y};
    checkParameters("hillshade spacing (m)", spacing, 2, ValueRange::positive());
    const double deg = std::numbers::pi / 180.0;
    const double zenith = (90.0 - options.altitude) * deg;
    // Azimuth in the math convention (counter-clockwise from east), as gdaldem does.
    const double azimuth = (360.0 - options.azimuth + 90.0) * deg;
    const auto [lo, hi] = std::minmax_element(metres.begin(), metres.end());
    const int channels = options.colour ? 3 : 1;
    std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * channels);
    auto h = [&](int x, int y) {
        return double(metres[static_cast<size_t>(std::clamp(y, 0, height - 1)) * width +
                             std::clamp(x, 0, width - 1)]);
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            // Horn: 3x3 weighted differences; y grows southwards in the raster.
            const double dzdx = ((h(x + 1, y - 1) + 2 * h(x + 1, y) + h(x + 1, y + 1)) -
                                 (h(x - 1, y - 1) + 2 * h(x - 1, y) + h(x - 1, y + 1))) /
                                (8 * spacing_x) * options.z_factor;
            const double dzdy = ((h(x - 1, y + 1) + 2 * h(x, y + 1) + h(x + 1, y + 1)) -
                                 (h(x - 1, y - 1) + 2 * h(x, y - 1) + h(x + 1, y - 1))) /
                                (8 * spacing_y) * options.z_factor;
            const double slope = std::atan(std::hypot(dzdx, dzdy));
            const double aspect = std::atan2(dzdy, -dzdx);
            const double shade = std::max(0.0, std::cos(zenith) * std::cos(slope) +
                                                   std::sin(zenith) * std::sin(slope) *
                                                       std::cos(azimuth - aspect));
            uint8_t* out = pixels.data() + (static_cast<size_t>(y) * width + x) * channels;
            if (!options.colour) {
                out[0] = toByte(shade);
                continue;
            }
            // The renderer's palette (water at or below 0 m, the land ramp above), modulated
            // by the shade with an ambient floor so shadows keep their colour.
            const palette::Rgb c = palette::terrainColour(float(h(x, y)), *lo, *hi);
            const double light = 0.35 + 0.65 * shade;
            out[0] = toByte(c.r * light);
            out[1] = toByte(c.g * light);
            out[2] = toByte(c.b * light);
        }
    }
    return pixels;
}

void writeHillshade(const std::string& archive_path, const std::string& output,
                    const HillshadeOptions& options)
{
    options.validate();
    refuseOutputOverInput(output, {archive_path});
    checkOutputWritable(output); // before the work, not after it
    const archive::ArchiveReader reader(archive_path);
    const PyramidGeometry& g = reader.geometry();
    const int level = resolveLevel(reader, options.level);
    const CodeGrid grid = decodeLevel(reader, level, subProgress(options.progress, 0.0, 0.7));
    const std::vector<float> metres = toMetres(grid, reader.quantization());
    const double s = double(g.step(level));
    const std::vector<uint8_t> pixels = shadeRelief(metres, grid.width, grid.height,
                                                    reader.header().spacing_x * s,
                                                    reader.header().spacing_y * s, options);
    io::writePng(output, pixels.data(), grid.width, grid.height, options.colour ? 3 : 1);
    reportDone(options.progress); // published: too late to cancel
}

} // namespace ridge
