// The public API's rendering (<ridge/ridge.h>): headless PNGs, and a Renderer that draws into
// the caller's GL context with ridge's camera or the host's matrices, and picks what it drew,
// over render::TerrainRenderer. Every call that touches GL runs inside a render::HostGlState,
// which gives the host its state back.
#include "ridge/ridge.h"

#include "host_view.h"
#include "picking.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/core/parameter_check.h"
#include "ridge/pipeline/height_query.h"
#include "ridge/pipeline/terrain_georeference.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/host_gl_state.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ridge {
namespace {

glm::dvec3 toGlm(const std::array<double, 3>& v)
{
    return {v[0], v[1], v[2]};
}
std::array<double, 3> fromGlm(const glm::dvec3& v)
{
    return {v.x, v.y, v.z};
}

// `scheme`: the scheme drawn, by name (DrawParameters::scheme resolved by the caller).
render::RenderSettings settingsFrom(const DrawParameters& p, const std::string& scheme)
{
    render::RenderSettings s;
    s.scheme = scheme;
    s.epsilon_px = p.max_screen_error_px;
    s.texel_px = p.texel_size_px;
    s.skirts = p.skirts;
    s.clear = p.clear;
    s.sky = p.sky;
    s.fog = p.fog;
    s.exaggeration = p.vertical_exaggeration;
    return s;
}

FrameSummary summaryOf(const render::FrameStats& stats)
{
    FrameSummary f;
    f.patches = stats.patches;
    f.triangles = stats.triangles;
    f.screen_error_px = stats.epsilon_px;
    f.missing = stats.missing;
    return f;
}

render::HeadlessRenderOptions headlessOptions(const CameraPose& pose, int width, int height)
{
    render::HeadlessRenderOptions options;
    options.camera = toGlm(pose.position);
    options.look_at = toGlm(pose.look_at);
    options.fov_y_degrees = pose.fov_y_degrees;
    options.viewport = {width, height};
    return options;
}

// How far the drawn triangle `t` (local frame) lies from the source: the largest vertical
// distance at the finest samples under it (its xy footprint, edges included) between the
// triangle and the archive's decoded sample, plus the finest level's bound to the source.
// A sliver with no sample under it (clipped at the valid extent) is measured at the sample
// nearest its centroid. Kept nodata is skipped.
double drawnError(HeightQuery& query, const glm::dvec3 (&t)[3])
{
    const lod::TerrainFrame& frame = query.georeference().frame();
    const PyramidGeometry& g = query.reader().geometry();
    const double sx = frame.spacingX(), sy = frame.spacingY();
    const int last_row = g.height() - 1;
    // Barycentric coordinates of (x, y) in the triangle's footprint.
    const double det =
        (t[1].y - t[2].y) * (t[0].x - t[2].x) + (t[2].x - t[1].x) * (t[0].y - t[2].y);
    auto weights = [&](double x, double y) {
        const double a =
            ((t[1].y - t[2].y) * (x - t[2].x) + (t[2].x - t[1].x) * (y - t[2].y)) / det;
        const double b =
            ((t[2].y - t[0].y) * (x - t[2].x) + (t[0].x - t[2].x) * (y - t[2].y)) / det;
        return glm::dvec3(a, b, 1.0 - a - b);
    };
    double worst = -1.0;
    auto measure = [&](int column, int row, glm::dvec3 w) {
        const HeightSample s = query.sample({column + 0.5, row + 0.5}, PointSpace::Pixel, -1,
                                            QueryResampling::Nearest);
        if (s.on_raster && !s.nodata)
            worst =
                std::max(worst, std::abs(w.x * t[0].z + w.y * t[1].z + w.z * t[2].z - s.height));
    };
    if (std::abs(det) > 0.0) {
        const double x0 = std::min({t[0].x, t[1].x, t[2].x}),
                     x1 = std::max({t[0].x, t[1].x, t[2].x});
        const double y0 = std::min({t[0].y, t[1].y, t[2].y}),
                     y1 = std::max({t[0].y, t[1].y, t[2].y});
        const int c0 = std::max(0, int(std::floor(x0 / sx))),
                  c1 = std::min(g.width() - 1, int(std::ceil(x1 / sx)));
        const int r0 = std::max(0, last_row - int(std::ceil(y1 / sy)));
        const int r1 = std::min(last_row, last_row - int(std::floor(y0 / sy)));
        constexpr double kSlack = 1e-6; // float corners: a sample on an edge is under it
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c) {
                const glm::dvec3 w = weights(c * sx, (last_row - r) * sy);
                if (w.x >= -kSlack && w.y >= -kSlack && w.z >= -kSlack)
                    measure(c, r, w);
            }
    }
    if (worst < 0.0 && std::abs(det) > 0.0) {
        const glm::dvec3 centre = (t[0] + t[1] + t[2]) / 3.0;
        const int c = std::clamp(int(std::lround(centre.x / sx)), 0, g.width() - 1);
        const int r = std::clamp(last_row - int(std::lround(centre.y / sy)), 0, last_row);
        measure(c, r, weights(c * sx, (last_row - r) * sy));
    }
    if (worst < 0.0)
        return std::numeric_limits<double>::quiet_NaN(); // nothing but kept nodata under it
    return worst + query.reader().levelErrorBound(g.finestLevel());
}

} // namespace

FrameSummary renderPng(const std::string& archive_path, const std::string& png_path,
                       const RenderParameters& parameters)
{
    render::HeadlessRenderOptions options;
    options.viewport = {parameters.width, parameters.height};
    options.samples = parameters.samples;
    const std::string spec =
        parameters.draw.scheme.empty() ? render::defaultLodScheme() : parameters.draw.scheme;
    options.settings = settingsFrom(parameters.draw, render::parseSchemeSpec(spec).scheme());
    options.scheme_spec = spec;
    if (parameters.camera) {
        options.camera = toGlm(parameters.camera->position);
        options.look_at = toGlm(parameters.camera->look_at);
        options.fov_y_degrees = parameters.camera->fov_y_degrees;
    }
    return summaryOf(render::renderToPng(archive_path, options, png_path).stats);
}

struct Renderer::Impl {
    archive::ArchiveReader reader;
    render::TerrainRenderer renderer;
    TerrainGeoreference georeference;
    // The last frame: the rays through its pixels, and its triangles once a pick asked.
    std::optional<api::PixelRays> rays;
    std::optional<api::PickSurface> surface;
    // The finest samples picks are measured against, opened by the first pick.
    std::unique_ptr<HeightQuery> finest;
    double exaggeration = 1.0; // of the last frame drawn: picks divide its heights by it

    Impl(const std::string& path, const render::RendererOptions& options)
        : reader(path), renderer(reader, options), georeference(reader)
    {
    }

    FrameSummary draw(const api::HostCamera& host, const DrawParameters& parameters,
                      bool host_projection)
    {
        const std::string& scheme =
            parameters.scheme.empty() ? renderer.schemes().front() : parameters.scheme;
        if (scheme.find(',') != std::string::npos)
            throw Error("DrawParameters::scheme '" + scheme +
                        "': Renderer::draw takes a scheme's name (its options are "
                        "RendererParameters::schemes')");
        const render::RenderSettings settings = settingsFrom(parameters, scheme);
        settings.validate(); // before any GL state changes
        render::HostGlState state("Renderer::draw");
        surface.reset();
        rays.reset();
        const render::FrameStats stats = renderer.draw(
            host.lod_camera, settings, nullptr, host_projection ? &host.projection : nullptr);
        rays = host.rays;
        exaggeration = settings.exaggeration;
        return summaryOf(stats);
    }

    const api::PixelRays& lastRays() const
    {
        if (!rays)
            throw Error("Renderer::pick: no frame drawn yet (picks meet what the last draw() "
                        "drew)");
        return *rays;
    }

    std::optional<TerrainHit> pick(glm::dvec3 origin, glm::dvec3 direction)
    {
        lastRays();
        if (!surface) {
            render::HostGlState state("Renderer::pick");
            surface.emplace(renderer.lastFrameSurface());
        }
        const glm::dvec3 unit = glm::normalize(direction);
        const std::optional<api::SurfaceHit> hit =
            surface->intersect(origin - surface->cameraPosition(), unit);
        if (!hit)
            return std::nullopt;
        TerrainHit out;
        const glm::dvec3 p = surface->cameraPosition() + hit->relative;
        out.position = fromGlm(p);
        out.height = p.z / exaggeration; // the drawn height is k times the terrain's
        out.distance = hit->t;
        out.level = hit->patch.level;
        if (!finest)
            finest = std::make_unique<HeightQuery>(reader.path(), 64);
        // The triangle in true heights, to compare with the archive's samples.
        glm::dvec3 triangle[3] = {surface->cameraPosition() + hit->triangle[0],
                                  surface->cameraPosition() + hit->triangle[1],
                                  surface->cameraPosition() + hit->triangle[2]};
        for (glm::dvec3& v : triangle)
            v.z /= exaggeration;
        out.error_bound = drawnError(*finest, triangle);
        if (georeference.hasCrs()) {
            try {
                const glm::dvec2 ll = georeference.fromLocal({p.x, p.y}, PointSpace::LonLat);
                out.lon_lat = std::array<double, 2>{ll.x, ll.y};
            } catch (const Error&) {
                // Outside the projection's domain: the hit stands without longitude/latitude.
            }
        }
        return out;
    }
};

Renderer::Renderer(const std::string& archive_path, const RendererParameters& parameters)
{
    render::RendererOptions options;
    options.vram_budget_mb = parameters.vram_budget_mb;
    options.ram_budget_mb = parameters.ram_budget_mb;
    options.streaming = parameters.streaming;
    options.schemes = parameters.schemes;
    // The public API's poses, ground heights and picks are in the plane's local metres.
    options.frame = lod::FrameChoice::Plane;
    options.validate();
    render::HostGlState state("Renderer::Renderer");
    impl_ = std::make_unique<Impl>(archive_path, options);
}

Renderer::~Renderer() = default;

std::vector<std::string> Renderer::schemes() const
{
    return impl_->renderer.schemes();
}

std::vector<std::string> lodSchemes()
{
    return render::lodSchemeNames();
}

FrameSummary Renderer::draw(const CameraPose& pose, int width, int height,
                            const DrawParameters& parameters)
{
    // Validates the pose and viewport like renderPng; ridge's own reverse-Z projection.
    render::HeadlessRenderOptions options = headlessOptions(pose, width, height);
    options.settings.exaggeration = parameters.vertical_exaggeration;
    const lod::Camera camera = render::cameraFor(impl_->renderer, options);
    const HostView view = api::hostViewOf(camera);
    api::HostCamera host = api::hostCamera(view, impl_->renderer, parameters.vertical_exaggeration);
    host.lod_camera = camera; // exactly the pose's camera, not one rebuilt from matrices
    return impl_->draw(host, parameters, false);
}

FrameSummary Renderer::draw(const HostView& view, const DrawParameters& parameters)
{
    return impl_->draw(api::hostCamera(view, impl_->renderer, parameters.vertical_exaggeration),
                       parameters, true);
}

HostView Renderer::hostView(const CameraPose& pose, int width, int height) const
{
    return api::hostViewOf(
        render::cameraFor(impl_->renderer, headlessOptions(pose, width, height)));
}

std::optional<TerrainHit> Renderer::pick(double x, double y)
{
    const double xy[2] = {x, y};
    checkParameters("pick window point", xy, 2, ValueRange::any());
    const api::PixelRays& rays = impl_->lastRays();
    return impl_->pick(rays.eye, rays.direction(x, y));
}

std::optional<TerrainHit> Renderer::pick(const std::array<double, 3>& origin,
                                         const std::array<double, 3>& direction)
{
    checkParameters("pick ray origin", origin.data(), 3, lod::kCameraCoordinateRange);
    checkParameters("pick ray direction", direction.data(), 3, ValueRange::any());
    const glm::dvec3 d = toGlm(direction);
    if (!(glm::length(d) > 0.0) || !std::isfinite(glm::length(d)))
        throw Error("pick ray direction is (0, 0, 0): give a direction");
    return impl_->pick(toGlm(origin), d);
}

void Renderer::waitForStreaming()
{
    impl_->renderer.waitForStreaming();
}

bool Renderer::waitForStreaming(double timeout_seconds)
{
    return impl_->renderer.waitForStreaming(timeout_seconds);
}

CameraPose Renderer::defaultCamera(int width, int height, double fov_y_degrees,
                                   double vertical_exaggeration) const
{
    const lod::Camera c =
        impl_->renderer.defaultCamera({width, height}, fov_y_degrees, vertical_exaggeration);
    CameraPose pose;
    pose.position = fromGlm(c.position());
    // Any point along the view direction: the camera looks the same.
    pose.look_at = fromGlm(c.position() + c.forward() * 1000.0);
    pose.fov_y_degrees = fov_y_degrees;
    return pose;
}

double Renderer::groundHeight(double x, double y, double vertical_exaggeration) const
{
    return impl_->renderer.groundHeight(x, y, vertical_exaggeration);
}

} // namespace ridge
