#include "ridge/pipeline/hillshade.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/sample_flag_bits.h"
#include "ridge/core/terrain_palette.h"
#include "ridge/io/raster_writer.h"
#include "ridge/pipeline/level_decoder.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace ridge {

namespace {

uint8_t toByte(double v)
{
    return static_cast<uint8_t>(std::clamp(std::lround(v * 255.0), 0L, 255L));
}

} // namespace

void HillshadeOptions::validate() const
{
    checkParameter("level", int64_t{level}, -1, kMaxLevel);
    checkParameter("azimuth (degrees)", azimuth, kAzimuthDegreesRange);
    checkParameter("altitude (degrees)", altitude, kAltitudeDegreesRange);
    checkParameter("z_factor", z_factor, kZFactorRange);
}

std::vector<uint8_t> shadeRelief(const std::vector<float>& metres, int width, int height,
                                 double spacing_x, double spacing_y,
                                 const HillshadeOptions& options, const std::vector<uint8_t>& valid,
                                 const std::vector<uint8_t>* water)
{
    options.validate();
    const double spacing[2] = {spacing_x, spacing_y};
    checkParameters("hillshade spacing (m)", spacing, 2, ValueRange::positive());
    const double deg = std::numbers::pi / 180.0;
    const double zenith = (90.0 - options.altitude) * deg;
    // Azimuth in the math convention (counter-clockwise from east), as gdaldem does.
    const double azimuth = (360.0 - options.azimuth + 90.0) * deg;
    const size_t count = static_cast<size_t>(width) * height;
    const bool masked = !valid.empty();
    if (masked && valid.size() != count)
        throw Error("hillshade validity mask has " + std::to_string(valid.size()) +
                    " entries: must be width * height = " + std::to_string(count));
    if (water && !water->empty() && water->size() != count)
        throw Error("hillshade water flags have " + std::to_string(water->size()) +
                    " entries: must be width * height = " + std::to_string(count));
    auto isWater = [&](size_t i) {
        if (!water)
            return palette::isWater(metres[i]);
        return !water->empty() && ((*water)[i] & kSampleWater) != 0;
    };
    float lo_value = std::numeric_limits<float>::infinity(), hi_value = -lo_value;
    for (size_t i = 0; i < count; ++i)
        if (!masked || valid[i]) {
            lo_value = std::min(lo_value, metres[i]);
            hi_value = std::max(hi_value, metres[i]);
        }
    const float* lo = &lo_value; // the palette's range: the valid heights'
    const float* hi = &hi_value;
    const int channels = masked ? 4 : options.colour ? 3 : 1;
    std::vector<uint8_t> pixels(count * channels, 0);
    int cx = 0, cy = 0; // the pixel being shaded
    auto h = [&](int x, int y) {
        size_t i =
            static_cast<size_t>(std::clamp(y, 0, height - 1)) * width + std::clamp(x, 0, width - 1);
        if (masked && !valid[i])
            i = static_cast<size_t>(cy) * width + cx;
        return double(metres[i]);
    };
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            if (masked && !valid[static_cast<size_t>(y) * width + x])
                continue; // transparent background
            cx = x;
            cy = y;
            // Horn: 3x3 weighted differences; y grows southwards in the raster.
            const double dzdx = ((h(x + 1, y - 1) + 2 * h(x + 1, y) + h(x + 1, y + 1)) -
                                 (h(x - 1, y - 1) + 2 * h(x - 1, y) + h(x - 1, y + 1))) /
                                (8 * spacing_x) * options.z_factor;
            const double dzdy = ((h(x - 1, y + 1) + 2 * h(x, y + 1) + h(x + 1, y + 1)) -
                                 (h(x - 1, y - 1) + 2 * h(x, y - 1) + h(x + 1, y - 1))) /
                                (8 * spacing_y) * options.z_factor;
            const double slope = std::atan(std::hypot(dzdx, dzdy));
            const double aspect = std::atan2(dzdy, -dzdx);
            const double shade =
                std::max(0.0, std::cos(zenith) * std::cos(slope) +
                                  std::sin(zenith) * std::sin(slope) * std::cos(azimuth - aspect));
            uint8_t* out = pixels.data() + (static_cast<size_t>(y) * width + x) * channels;
            if (masked)
                out[3] = 255;
            if (!options.colour) {
                out[0] = toByte(shade);
                if (masked)
                    out[1] = out[2] = out[0];
                continue;
            }
            // The renderer's palette (water where flagged, the land ramp elsewhere), modulated
            // by the shade with an ambient floor so shadows keep their colour.
            const size_t i = static_cast<size_t>(y) * width + x;
            const palette::Rgb c = palette::terrainColour(metres[i], isWater(i), *lo, *hi);
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
    if (level < 0 || level >= g.levelCount())
        decodeLevel(reader, level); // throws the message naming the levels
    std::vector<uint8_t> valid, flags;
    const CodeGrid grid =
        decodeLevelWindow(reader, level, 0, 0, g.validLevelWidth(level), g.validLevelHeight(level),
                          subProgress(options.progress, 0.0, 0.7), &valid, &flags);
    const std::vector<float> metres = toMetres(grid, reader.quantization());
    const double s = double(g.step(level));
    // Archives of format 4 say where water is; older ones are painted by the height rule.
    const std::vector<uint8_t> pixels =
        shadeRelief(metres, grid.width, grid.height, reader.header().spacing_x * s,
                    reader.header().spacing_y * s, options, valid,
                    reader.storesSampleFlags() ? &flags : nullptr);
    io::writePng(output, pixels.data(), grid.width, grid.height,
                 !valid.empty()   ? 4
                 : options.colour ? 3
                                  : 1);
    reportDone(options.progress); // published: too late to cancel
}

} // namespace ridge
