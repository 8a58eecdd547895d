// libFuzzer target: the parameters of rendering, from hostile callers — cameras, fields of
// view, viewports, clip planes, ε, error scales, patch budgets, sun angles, memory and upload
// budgets, camera paths and the fly camera — through the renderer's CPU entry points on real
// archives: RenderSettings / RendererOptions / HeadlessRenderOptions validation, lod::Camera,
// the ground height, clip planes and default camera of lod::CoarseTerrain, LOD selection,
// residency, the streaming cover and the instance records (fuzz/render_cpu_frame.h).
//
// Numbers come as raw bit patterns (NaN, infinities, denormals, ±1e308) or as values scaled to
// the terrain, so both the validators and the arithmetic behind them are reached.
// Properties: every refusal is a ridge::Error; what a validator accepts keeps the arithmetic
// finite (checked); no crash, no out-of-bounds access, no UB.
//
// The archives: every *.ridge in $RIDGE_FUZZ_ARCHIVES (scripts/fuzz.sh builds them from
// tests/data, the globe fixture among them: its cameras then run in ECEF, from inside the
// Earth and its centre to far past the Moon), opened once.
#include "render_cpu_frame.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/lod/camera_path.h"
#include "ridge/render/fly_camera.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/scheme_options.h"
#include "ridge/render/terrain_renderer.h"

#include <fuzzer/FuzzedDataProvider.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace {

using ridge::fuzz::require;

struct Loaded {
    std::unique_ptr<ridge::archive::ArchiveReader> reader;
    std::unique_ptr<ridge::fuzz::CpuRenderer> renderer;
};

std::vector<Loaded>& archives()
{
    static std::vector<Loaded> loaded;
    return loaded;
}

// A double as a caller might pass it: raw bits (anything, NaN included), a special value, or
// a plausible value `scale` times a fraction.
double consumeNumber(FuzzedDataProvider& in, double scale)
{
    switch (in.ConsumeIntegralInRange<int>(0, 3)) {
    case 0:
        return std::bit_cast<double>(in.ConsumeIntegral<uint64_t>());
    case 1: {
        static constexpr double kSpecial[] = {NAN,    INFINITY, -INFINITY, 0.0,  -0.0,
                                              1e-310, 1e308,    -1e308,    1e15, -1e15,
                                              1e16,   1.0,      -1.0,      90.0, 180.0};
        return in.PickValueInArray(kSpecial);
    }
    default:
        return scale * in.ConsumeFloatingPointInRange<double>(-2.0, 2.0);
    }
}

glm::dvec3 consumePoint(FuzzedDataProvider& in, const ridge::lod::Box& box)
{
    const glm::dvec3 size = box.max - box.min + glm::dvec3(1.0);
    return box.centre() + glm::dvec3(consumeNumber(in, size.x), consumeNumber(in, size.y),
                                     consumeNumber(in, size.z));
}

// The validators' promise: what they accept is finite where the renderer computes with it.
void settingsAndOptions(FuzzedDataProvider& in)
{
    ridge::render::RenderSettings s;
    s.epsilon_px = consumeNumber(in, 10.0);
    try {
        s.sun_direction =
            ridge::render::sunDirection(consumeNumber(in, 360.0), consumeNumber(in, 90.0));
        require(std::isfinite(s.sun_direction.x + s.sun_direction.y + s.sun_direction.z));
    } catch (const ridge::Error&) {
        s.sun_direction = {consumeNumber(in, 1.0), consumeNumber(in, 1.0), consumeNumber(in, 1.0)};
    }
    try {
        s.validate();
        require(std::isfinite(s.epsilon_px) && s.epsilon_px > 0);
        require(std::isfinite(glm::length(s.sun_direction)) && glm::length(s.sun_direction) > 0);
    } catch (const ridge::Error&) {
    }

    ridge::render::RendererOptions o;
    o.vram_budget_mb = consumeNumber(in, 512.0);
    o.ram_budget_mb = consumeNumber(in, 512.0);
    o.upload_budget_mb = consumeNumber(in, 16.0);
    o.upload_budget_ms = consumeNumber(in, 8.0);
    // A registered scheme, maybe with options from the input: the spec parser's hostile text.
    const std::vector<std::string> names = ridge::render::lodSchemeNames();
    std::string spec = names[in.ConsumeIntegralInRange<size_t>(0, names.size() - 1)];
    if (in.ConsumeBool())
        spec += "," + in.ConsumeRandomLengthString(64);
    o.schemes = {spec};
    o.max_resident_patches = in.ConsumeIntegral<int>();
    o.uploads_per_frame = in.ConsumeIntegral<int>();
    o.io_threads = in.ConsumeIntegral<int>();
    o.prefetch_frames = in.ConsumeIntegral<int>();
    try {
        o.validate();
        // The byte counts the renderer derives (slots, the streamer's caches) fit a size_t.
        require(o.vram_budget_mb * 1048576.0 < 1.8e19 && o.ram_budget_mb * 1048576.0 < 1.8e19);
        require(o.upload_budget_mb * 1048576.0 < 1.8e19 && o.max_resident_patches >= 1);
        // An accepted spec spells every option back, and that spelling parses to itself.
        const std::string whole = ridge::render::parseSchemeSpec(spec).spec();
        require(ridge::render::parseSchemeSpec(whole).spec() == whole);
    } catch (const ridge::Error&) {
    }

    ridge::render::HeadlessRenderOptions h;
    if (in.ConsumeBool())
        h.camera =
            glm::dvec3(consumeNumber(in, 1e4), consumeNumber(in, 1e4), consumeNumber(in, 1e4));
    if (in.ConsumeBool())
        h.look_at =
            glm::dvec3(consumeNumber(in, 1e4), consumeNumber(in, 1e4), consumeNumber(in, 1e4));
    h.fov_y_degrees = consumeNumber(in, 90.0);
    h.viewport = {in.ConsumeIntegral<int>(), in.ConsumeIntegral<int>()};
    h.samples = in.ConsumeIntegral<int>();
    h.vram_budget_mb = consumeNumber(in, 256.0);
    h.settings = s;
    try {
        h.validate();
        require(h.viewport.width >= 1 && h.viewport.height >= 1);
    } catch (const ridge::Error&) {
    }
}

// Cameras, selection and the instance records, as a frame of the renderer builds them.
void frame(FuzzedDataProvider& in, ridge::fuzz::CpuRenderer& r)
{
    const ridge::lod::Box box = r.coarse.box();
    const ridge::lod::Viewport viewport{in.ConsumeIntegralInRange<int>(-2, 5000),
                                        in.ConsumeIntegralInRange<int>(-2, 5000)};
    const double fov = consumeNumber(in, 90.0);
    try {
        const double h =
            r.coarse.groundHeight(consumeNumber(in, box.max.x), consumeNumber(in, box.max.y));
        require(std::isfinite(h));
    } catch (const ridge::Error&) {
    }
    try {
        (void)r.coarse.defaultCamera(viewport, fov);
    } catch (const ridge::Error&) {
    }
    try {
        const glm::dvec3 position = consumePoint(in, box), look_at = consumePoint(in, box);
        double near_m = consumeNumber(in, 10.0), far_m = consumeNumber(in, 1e5);
        if (in.ConsumeBool()) {
            r.coarse.clipPlanesFor(position, near_m, far_m);
            require(std::isfinite(near_m) && std::isfinite(far_m) && 0 < near_m && near_m < far_m);
        }
        const ridge::lod::Camera camera(position, look_at, fov, viewport, near_m, far_m);
        ridge::lod::SelectionSettings settings;
        settings.epsilon_px = consumeNumber(in, 8.0);
        settings.error_scale = consumeNumber(in, 2.0);
        settings.max_patches =
            in.ConsumeIntegralInRange<size_t>(0, ridge::fuzz::CpuRenderer::kSlots - 1);
        settings.cull = in.ConsumeBool();
        settings.conservative_distance = in.ConsumeBool();
        const int policy = in.ConsumeIntegralInRange<int>(0, 2);
        if (policy == 1) {
            // Scheme rings' own selection: any ring count and vertex step, valid or not.
            ridge::lod::RingsSettings rings;
            rings.rings = in.ConsumeIntegralInRange<int>(-2, 20);
            rings.vertex_step = in.ConsumeIntegralInRange<int>(0, 3);
            r.drawRingsFrame(camera, settings, rings);
        } else if (policy == 2) {
            // Scheme clipmaps' level windows: any n and level count, valid or not.
            ridge::lod::ClipmapSettings clipmap;
            clipmap.n = in.ConsumeIntegralInRange<int>(-2, 2100);
            clipmap.levels = in.ConsumeIntegralInRange<int>(-2, 30);
            r.drawClipmapsFrame(camera, settings, clipmap);
        } else {
            r.drawFrame(camera, settings);
        }
    } catch (const ridge::Error&) {
    }
}

// The benchmark's camera paths and the viewer's fly camera, over the same ground.
void paths(FuzzedDataProvider& in, ridge::fuzz::CpuRenderer& r)
{
    ridge::lod::CameraPathSettings s;
    s.kind = in.PickValueInArray({"flyover", "orbit", "teleport"});
    s.speed_mps = consumeNumber(in, 500.0);
    s.frame_seconds = consumeNumber(in, 0.05);
    s.height_above_ground = consumeNumber(in, 1000.0);
    s.teleport_every = in.ConsumeIntegralInRange<int>(-2, 100);
    const ridge::lod::Box box = r.coarse.box();
    try {
        const auto poses = ridge::lod::makeCameraPath(
            r.tree.frame(), box.min.z, box.max.z,
            [&](double x, double y) { return r.coarse.groundHeight(x, y); }, s,
            in.ConsumeIntegralInRange<int>(-1, 64));
        for (const ridge::lod::CameraPose& p : poses)
            require(std::isfinite(p.position.x + p.position.y + p.position.z));
    } catch (const ridge::Error&) {
    }
    try {
        ridge::render::FlyCamera fly(consumePoint(in, box), consumeNumber(in, 3.0),
                                     consumeNumber(in, 1.0), consumeNumber(in, 100.0));
        ridge::render::FlyInput input;
        input.forward = in.ConsumeBool();
        input.up = in.ConsumeBool();
        input.fast = in.ConsumeBool();
        input.mouse_dx = consumeNumber(in, 100.0);
        input.mouse_dy = consumeNumber(in, 100.0);
        input.speed_steps = consumeNumber(in, 10.0);
        fly.update(input, consumeNumber(in, 0.1));
        const glm::dvec3 p = fly.position();
        require(std::isfinite(p.x + p.y + p.z));
        (void)fly.camera({64, 64}, 60.0, 0.5, 1e6);
    } catch (const ridge::Error&) {
    }
}

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***)
{
    const char* dir = std::getenv("RIDGE_FUZZ_ARCHIVES");
    if (!dir) {
        std::fprintf(
            stderr, "fuzz_render_params: set RIDGE_FUZZ_ARCHIVES to a directory of .ridge files\n");
        std::exit(2);
    }
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".ridge")
            continue;
        Loaded l;
        l.reader = std::make_unique<ridge::archive::ArchiveReader>(entry.path().string());
        l.renderer = std::make_unique<ridge::fuzz::CpuRenderer>(*l.reader);
        archives().push_back(std::move(l));
    }
    if (archives().empty()) {
        std::fprintf(stderr, "fuzz_render_params: no .ridge file in %s\n", dir);
        std::exit(2);
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    FuzzedDataProvider in(data, size);
    Loaded& a = archives()[in.ConsumeIntegralInRange<size_t>(0, archives().size() - 1)];
    settingsAndOptions(in);
    frame(in, *a.renderer);
    paths(in, *a.renderer);
    return 0;
}
