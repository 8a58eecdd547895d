// The ranges of RenderSettings and RendererOptions (GL-free: checked before any GL call).
#include "ridge/render/terrain_renderer.h"

#include "ridge/core/error.h"
#include "ridge/render/scheme_options.h"
#include "ridge/stream/upload_planner.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ridge::render {

void RenderSettings::validate() const
{
    lodSchemeDescription(scheme); // throws for a name that is not registered
    checkParameter("epsilon_px", epsilon_px, kEpsilonPxRange);
    checkParameter("texel_px", texel_px, kTexelPxRange);
    checkParameter("exaggeration", exaggeration, kExaggerationRange);
    checkParameters("sun_direction", &sun_direction.x, 3, kSunComponentRange);
    // Normalising a zero vector gives NaN, which would shade every pixel black.
    if (!(glm::length(sun_direction) > 1e-9))
        throw Error("sun_direction is (0, 0, 0): it must point somewhere");
    const double colour[4] = {clear_colour.r, clear_colour.g, clear_colour.b, clear_colour.a};
    checkParameters("clear_colour", colour, 4, ValueRange::closed(0.0, 1.0));
}

glm::dvec3 sunDirection(double azimuth_degrees, double altitude_degrees)
{
    checkParameter("sun azimuth (degrees)", azimuth_degrees, kSunAzimuthDegreesRange);
    checkParameter("sun altitude (degrees)", altitude_degrees, kSunAltitudeDegreesRange);
    const double az = azimuth_degrees * std::numbers::pi / 180.0;
    const double alt = altitude_degrees * std::numbers::pi / 180.0;
    return {std::sin(az) * std::cos(alt), std::cos(az) * std::cos(alt), std::sin(alt)};
}

void RendererOptions::validate() const
{
    checkParameter("max_resident_patches", int64_t{max_resident_patches}, kMinResidentPatches,
                   kMaxResidentPatches);
    checkParameter("vram_budget_mb", vram_budget_mb, kVramBudgetMbRange);
    checkParameter("decoded_cache_patches",
                   int64_t(std::min<size_t>(decoded_cache_patches, 1u << 31)), 1, int64_t{1} << 30);
    checkParameter("ram_budget_mb", ram_budget_mb, kRamBudgetMbRange);
    checkParameter("io_threads", int64_t{io_threads}, 1, kMaxIoThreads);
    checkParameter("uploads_per_frame", int64_t{uploads_per_frame}, 1, kMaxUploadsPerFrame);
    checkParameter("upload_budget_mb", upload_budget_mb, kUploadBudgetMbRange);
    checkParameter("upload_budget_ms", upload_budget_ms, kUploadBudgetMsRange);
    using stream::UploadTimeSettings;
    checkParameter("upload_frame_fraction", upload_frame_fraction,
                   UploadTimeSettings::kFrameFractionRange);
    checkParameter("upload_budget_max_ms", upload_budget_max_ms,
                   UploadTimeSettings::kCeilingMsRange);
    checkParameter("prefetch_frames", int64_t{prefetch_frames}, 0, kMaxPrefetchFrames);
    checkParameter("refine_steps_per_frame", int64_t{refine_steps_per_frame}, 0,
                   kMaxRefineStepsPerFrame);
    arrival_blend.validate();
    std::vector<std::string> named;
    for (const std::string& spec : schemes) {
        const std::string name = parseSchemeSpec(spec).scheme();
        if (std::find(named.begin(), named.end(), name) != named.end())
            throw Error("LOD scheme " + name + " is given twice (one spec per scheme)");
        named.push_back(name);
    }
}

} // namespace ridge::render
