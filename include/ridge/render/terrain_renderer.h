#pragma once
// The hardware-tessellation terrain renderer (Yusov & Shevtsov 2011, §5 and "Implementation
// Details"): coarse LOD on the CPU (PatchQuadtree), fine LOD in the tessellation control
// shader (per-edge factors from Λ^(d)), vertical skirts, and the whole terrain in one
// instanced draw over texture arrays of height maps, normal maps (computed on the GPU when a
// patch becomes resident) and tessellation block errors.
//
// Needs a current OpenGL 4.5 core context (ridge::gpu::HeadlessContext or WindowContext) for
// its whole lifetime; draws into the framebuffer bound by the caller. Depth is reverse-Z
// (glClipControl zero-to-one, cleared to 0, GL_GREATER), set and restored by draw().
#include "ridge/archive/archive_reader.h"
#include "ridge/core/parameter_check.h"
#include "ridge/lod/archive_frame.h"
#include "ridge/lod/arrival_blend.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/edge_tessellation.h"
#include "ridge/lod/patch_quadtree.h"
#include "ridge/lod/patch_residency.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ridge::render {

enum class DebugMode : int { Shaded = 0, LodLevels = 1, TessellationFactors = 2 };

// LOD schemes — how selected patches become triangles — are named by the registry
// (src/render/scheme_registry.cpp), each with its own options (ridge/render/scheme_options.h):
// the paper's hardware tessellation first, then the baselines it is compared with and the
// schemes added since. Every scheme shares everything else — archive, selection, texture
// arrays, skirts, shading — so that frame rates compare the schemes alone. The CLI (render
// --lod, bench --lod, view --lod and the viewer's L key), the benchmarks and the tests take
// these names rather than spelling any.
std::vector<std::string> lodSchemeNames();
// The first registered scheme: the default of RenderSettings::scheme and of the CLI's --lod.
std::string defaultLodScheme();
// "NAME, NAME, ..." (the registered names) for messages and --help.
std::string lodSchemeList();
// One line about scheme `name`; throws ridge::Error for a name that is not registered.
std::string lodSchemeDescription(const std::string& name);

// What a scheme guarantees, declared in its registration; the conformance suite
// (tests/render/scheme_conformance_test.cpp) checks each scheme against its promises and
// measures and reports the rest for all.
struct SchemePromises {
    // Every finest sample in view within ε pixels of the drawn surface (false: measured only).
    bool screen_space_error = true;
    // How neighbouring pieces close their seams: skirts hung below every border, or
    // stitching (shared bit-identical vertices: every edge of the surface used by exactly two
    // triangles).
    enum class Seams { Skirts, Stitching } seams = Seams::Skirts;
    // A change of LOD (all of it resident) moves no drawn point visibly: geomorphing.
    // Arrivals while streaming are not LOD changes.
    bool pop_free = false;
    // Draws a globe whose columns go round the Earth (lod::GeodeticGrid::wrap_columns): its
    // selection wraps too. A scheme without it refuses such a frame by name.
    bool wrapping_globe = true;
    // What a streamed arrival does to the surface drawn before it (lod/arrival_blend.h):
    //   Fade          fades in from exactly what was drawn: no frame of a still camera moves
    //                 the surface by more than the fade's steps;
    //   FadeFromGrid  fades in from the ancestors' grids, which the scheme draws otherwise
    //                 (the tessellator triangulates a stand-in its own way): the arrival frame
    //                 still jumps by that difference;
    //   Replace       replaces its ancestor at once (the renderer fades nothing for it).
    enum class Arrivals { Fade, FadeFromGrid, Replace } arrivals = Arrivals::Fade;
};
// Scheme `name`'s promises; throws ridge::Error for a name that is not registered.
SchemePromises lodSchemePromises(const std::string& name);

struct RenderSettings {
    // ε in pixels. Below 1/20 px the tessellator saturates everywhere (the finest level at
    // 64 segments per edge costs what brute force does); above 1000 px the root patch is all
    // any view gets.
    static constexpr ValueRange kEpsilonPxRange = ValueRange::closed(0.05, 1000.0);
    // Components of sun_direction: any finite direction of sane magnitude (its length is
    // squared when it is normalised).
    static constexpr ValueRange kSunComponentRange = ValueRange::closed(-1e6, 1e6);

    // The scheme drawn: a bare name (no options), one of the renderer's schemes
    // (TerrainRenderer::schemes(), as RendererOptions::schemes built them).
    std::string scheme = defaultLodScheme();
    double epsilon_px = 2.0; // ε, pixels (schemes that draw the finest level ignore it)
    // Texture detail beside ε (lod::SelectionSettings::texel_px), decoupled from geometry:
    // the levels below each drawn patch down to samples at most this many pixels apart on
    // screen are made resident (Selection::detail), and colour, water and normals come from
    // the finest resident one under each fragment (the shading map, lod/shading_tiles.h), so
    // they are at about one texel per pixel while the triangles are ε's alone. 0 disables it:
    // each patch shades from its own maps.
    static constexpr ValueRange kTexelPxRange = ValueRange::closed(0.0, 1000.0);
    double texel_px = 1.0;
    bool cull = true; // view-frustum culling of patches
    // ... and of tessellation blocks in the control shader (with `cull`). capture() keeps
    // whatever is set: tests that check a whole patch's mesh turn it off.
    bool cull_blocks = true;
    lod::TessellationRule tessellation_rule = lod::TessellationRule::Conservative;
    // Coarse selection with lod::visibleDepthBound's side-on factor (ε anywhere on screen).
    // false: the bound of earlier releases (cheaper, up to 1.09 ε off-axis), which with
    // tessellation_rule = Paper reproduces their LOD for like-for-like comparisons.
    bool side_on_bound = true;
    bool skirts = true;
    // Vertical exaggeration at render time: every height drawn k times the archive's. The
    // camera is in that space (its z, the ground clamps: groundHeight · k), and selection,
    // tessellation, culling and skirts measure the exaggerated surface, so ε holds on what is
    // drawn; colours stay those of the true heights, normals are the exaggerated surface's.
    static constexpr ValueRange kExaggerationRange = lod::SelectionSettings::kExaggerationRange;
    double exaggeration = 1.0;
    DebugMode mode = DebugMode::Shaded;
    bool wireframe = false; // triangle edges over the shading
    bool sky = true;        // gradient sky; otherwise clear to clear_colour
    // Clear colour and depth before drawing. Off: draw over what the framebuffer holds (a
    // host application's scene, HostProjection), with no sky (it would paint over the scene).
    bool clear = true;
    bool fog = true;
    glm::vec4 clear_colour{0.62f, 0.74f, 0.88f, 1.f};
    // Towards the sun (normalised on use): azimuth 315° (north-west, as hillshades), altitude 45°.
    glm::dvec3 sun_direction{-0.5, 0.5, 0.70710678};

    // Throws ridge::Error naming the first field outside its range (an unregistered scheme,
    // NaN, infinities, ε outside kEpsilonPxRange, a zero or huge sun_direction, a clear colour
    // outside [0, 1]).
    // draw() and capture() call it.
    void validate() const;
};

// Sun azimuth, degrees clockwise from north (either way round, up to a full turn), and
// altitude above the horizon: a sun at or below it lights nothing.
inline constexpr ValueRange kSunAzimuthDegreesRange = ValueRange::closed(-360.0, 360.0);
inline constexpr ValueRange kSunAltitudeDegreesRange = ValueRange::openClosed(0.0, 90.0);
// The unit vector towards a sun at `azimuth_degrees`, `altitude_degrees` in the terrain frame
// (x east, y north, z up). Throws ridge::Error outside the ranges above.
glm::dvec3 sunDirection(double azimuth_degrees, double altitude_degrees);

struct FrameStats {
    int patches = 0; // drawn (instances)
    int culled = 0;  // subtrees dropped by the frustum test
    int loaded = 0;  // patches made resident this frame
    int missing = 0; // streaming: selected patches drawn by a resident ancestor
    int fading = 0;  // streaming: drawn patches fading in over their ancestor (arrivals)
    // Texture detail (RenderSettings::texel_px): the patches the selection wants for shading
    // (lod::Selection::detail), and how many of them are resident after this frame's uploads.
    int detail = 0, detail_resident = 0;
    int resident = 0;
    double epsilon_px = 0.0; // ε met (raised when the selection exceeds the slots)
    double texel_px = 0.0;   // texel target met (raised to fit the slots; 0: off)
    bool coarser = false;    // ε was raised: the view needed more patches than slots
    uint64_t triangles = 0; // generated by the tessellator (GL_PRIMITIVES_GENERATED), when measured
    double gpu_ms = 0.0;    // terrain pass, from a timer query (latest available)
    double gpu_upload_ms = 0.0;    // texture uploads + normal-map pass of new patches, likewise
    double upload_budget_ms = 0.0; // streaming: this frame's upload time budget (adaptive)
    double cpu_select_ms = 0.0;
    double cpu_load_ms = 0.0;
    // This frame's traffic. Streaming: the streamer's reads and decodes since the last frame
    // (worker threads), and the render thread's uploads; synchronous: the loader's.
    uint64_t bytes_read = 0;    // compressed blobs read from the archive
    uint64_t bytes_decoded = 0; // decode results (codes or residuals, λ)
    // Sent to the GPU: codes or residuals, and λ unless the GPU derives it.
    uint64_t bytes_uploaded = 0;
    int cache_hits = 0;    // requests served by the decoded-patch cache
    int cache_misses = 0;  // patches that had to be decoded
    int reconstructed = 0; // of `loaded`, patches decoded on the GPU
    // Base incremental (refinable codecs, the fractal codec): resident patches refined in
    // place this frame, and the steps (iterations) that took.
    int refined = 0;
    int refine_steps = 0;
    // Desired patches drawn this frame with fewer steps than the view wants (the per-frame
    // budget ran out): each exceeds ε by at most its stored partial bound until refined.
    int under_refined = 0;
    // Level windows (clipmaps): all of them (L), levels that shifted this frame, levels drawn
    // and levels the view wants (level deactivation keeps them; fewer are drawn while a strip
    // waits for its patches), and window samples written on the GPU. 0 for schemes without.
    int levels = 0;
    int level_shifts = 0;
    int levels_drawn = 0;
    int levels_wanted = 0;
    uint64_t samples_written = 0;
};

// Triangles as the tessellator produced them, captured with transform feedback.
struct CapturedVertex {
    float x, y, z;    // camera-relative terrain frame, metres
    int32_t instance; // index into CapturedSurface::patches
    int32_t skirt;    // 0 surface, 1 skirt, 2 a skirt's foot vertex
};
struct PoppingReport; // ridge/render/frame_measures.h

struct CapturedSurface {
    glm::dvec3 camera_position{0.0};      // add to positions for the terrain frame
    std::vector<CapturedVertex> vertices; // 3 per triangle
    std::vector<PatchId> patches;         // per instance
    std::vector<float> skirt_depth;       // per instance, metres below the border
};

struct RendererOptions {
    // The ranges validate() enforces. Budgets are positive; the upper ends are far beyond
    // any machine (1 TB of VRAM, 1 PB of RAM) and keep byte counts within size_t.
    static constexpr int kMinResidentPatches = 4; // raising ε must always find a fit
    static constexpr int kMaxResidentPatches = 1 << 20;
    static constexpr ValueRange kVramBudgetMbRange = ValueRange::openClosed(0.0, 1e6);
    static constexpr ValueRange kRamBudgetMbRange = ValueRange::openClosed(0.0, 1e9);
    static constexpr int kMaxIoThreads = 256;
    static constexpr int kMaxUploadsPerFrame = 1 << 20;
    static constexpr ValueRange kUploadBudgetMbRange = ValueRange::openClosed(0.0, 1e6);
    static constexpr ValueRange kUploadBudgetMsRange = ValueRange::openClosed(0.0, 1e9);
    static constexpr int kMaxPrefetchFrames = 1000000;

    // The LOD schemes this renderer can draw (RenderSettings::scheme picks one per frame by
    // name), each a spec of a registered scheme and its own options, "NAME[,KEY=VALUE...]"
    // (ridge/render/scheme_options.h; options not given take the module's defaults); at most
    // one spec per scheme. Each prepares what it needs from construction on — CPU codes,
    // per-patch products on the stream workers, memory per slot — so a scheme that needs codes
    // on the CPU turns GPU reconstruction off for all. Empty: every registered scheme, with
    // its default options, whose needs cost nothing: those that do not need codes on the CPU.
    std::vector<std::string> schemes;

    // The terrain frame (lod/archive_frame.h): the plane, or the WGS 84 ellipsoid; auto puts
    // a raster that goes round the Earth on the ellipsoid and keeps the rest on the plane.
    lod::FrameChoice frame = lod::FrameChoice::Auto;

    // Texture-array slots: at most this many, at most what `vram_budget_mb` holds (heights,
    // normals and block errors of one patch per slot) and at most the GL implementation's
    // array layers. When a view needs more patches than slots, ε is raised until it fits
    // (FrameStats::epsilon_px says so).
    int max_resident_patches = 512;
    double vram_budget_mb = 256.0;
    size_t decoded_cache_patches = 1024;
    // Normal maps continuous across seams between resident patches of one level: the normal
    // pass borrows a ring of samples from the neighbours' height layers, and a resident
    // neighbour's map is recomputed when a patch arrives next to it. Off: one-sided
    // differences at every patch border.
    bool seamless_normals = true;
    // Streaming: draw() never waits for disk or decoding. Missing patches are requested from
    // worker threads and drawn by their finest resident ancestor until they arrive; at most
    // `uploads_per_frame` arrive per frame. Off: every selected patch is loaded before the
    // frame is drawn (headless renders, tests of exact output).
    bool streaming = false;
    // The streamer's RAM caches together: a quarter for compressed blobs, the rest for
    // decoded patches (stream::StreamerOptions::forRamBudget).
    double ram_budget_mb = 256.0;
    int io_threads = 2; // decode threads (one more thread reads)
    // The per-frame upload budget: a frame stops uploading once it has sent this many bytes
    // or spent its time budget (CPU time submitting uploads), or made this many patches
    // resident; at least one patch is uploaded when one is waiting, so streaming always
    // progresses. The time budget follows the frame time (stream::UploadTimeBudget):
    // upload_frame_fraction of the median recent frame time without uploads, at least
    // upload_budget_ms, at most upload_budget_max_ms; fraction 0: upload_budget_ms alone.
    int uploads_per_frame = 16;
    double upload_budget_mb = 8.0;
    double upload_budget_ms = 4.0;
    double upload_frame_fraction = 0.25;
    double upload_budget_max_ms = 250.0;
    // Streaming with a codec that has a GPU half (HeightCodec::capabilities().gpu: progressive,
    // jpeg2000, fractal): workers run the CPU half only (entropy decoding, parsing); the
    // codec's GPU decoder finishes the patch (from the resident parent when the codec reads
    // it) and λ (unless stored) and the normal map are derived in compute passes. Parents of
    // patches waiting for them are kept resident. Off (--cpu-decode): workers decode to codes.
    bool gpu_reconstruction = true;
    // Base incremental (the fractal-rings paper, §8), for refinable codecs decoded on the GPU:
    // a patch is first decoded with the fewest steps that keep it within ε for the view
    // (stream::stepsForView), and refined in place as the viewer approaches, at most this many
    // steps (iterations over one patch) a frame. 0: every patch decoded fully on arrival (the
    // paper's "Base").
    static constexpr int kMaxRefineStepsPerFrame = 1 << 16;
    int refine_steps_per_frame = 64;
    // Streaming: also request what the camera will see this many frames ahead at its current
    // velocity (after everything the current frame needs). 0 disables prefetching.
    int prefetch_frames = 20;
    // Streaming: an arriving patch fades in over the ancestor that stood in for it, moving at
    // most px_per_frame pixels a frame for at most max_frames frames (lod/arrival_blend.h);
    // max_frames 0: it replaces the ancestor at once. Fixed per renderer (the shaders compile
    // the fade in only for a streaming renderer that fades).
    lod::ArrivalBlendSettings arrival_blend;
    // Waits for this frame's GPU timer and GL_PRIMITIVES_GENERATED query (stalls the
    // pipeline: headless renders and tests). Otherwise gpu_ms and triangles are those of the
    // latest finished frame (a few frames old).
    bool synchronous_stats = false;
    // Throws ridge::Error naming the first field outside its range above (NaN and infinities
    // included), and for a spec in `schemes` that does not parse (an unregistered scheme, an
    // option it does not take or a value outside its range: parseSchemeSpec's message) or a
    // scheme given twice. The TerrainRenderer constructor calls it.
    void validate() const;

    // The defaults with streaming on (the viewer's and the benchmark's).
    static RendererOptions streamingDefaults()
    {
        RendererOptions o;
        o.streaming = true;
        return o;
    }
};

// Reverse-Z infinite perspective (depth 1 at the near plane, 0 at infinity) for
// glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE): the projection draw() uses for `camera`
// without a HostProjection. Its x, y and w rows equal those of Camera::projection(), so
// screen-space measurements in the shaders match the C++ ones.
glm::dmat4 reverseZProjection(const lod::Camera& camera);

// A host application's camera for draw() (ridge::Renderer::draw with a HostView): the image is
// drawn with the host's matrices and depth convention, so that the host's geometry and the
// terrain depth-test against each other in either drawing order. LOD is still decided for
// draw()'s lod::Camera, which must sit at the host's eye with a frustum containing the host's
// and γ no smaller than the host's (src/api/host_view.cpp derives one).
struct HostProjection {
    // Camera-relative terrain frame (world − camera.position(), metres) → clip: the host's
    // projection times the rotation of its view.
    glm::dmat4 view_projection{1.0};
    bool zero_to_one = true; // glClipControl depth mode GL_ZERO_TO_ONE, else NEGATIVE_ONE_TO_ONE
    bool greater = true;     // nearer is greater depth (reverse-Z): GL_GREATER, cleared to 0;
                             // else GL_LESS, cleared to 1
};

class TerrainRenderer {
  public:
    TerrainRenderer(const archive::ArchiveReader& reader, const RendererOptions& options = {});
    ~TerrainRenderer();
    TerrainRenderer(const TerrainRenderer&) = delete;
    TerrainRenderer& operator=(const TerrainRenderer&) = delete;

    // Selects, loads (synchronously) and draws one frame into the bound framebuffer, whose
    // size must be camera.viewport(). Clears colour and depth. `lod_camera` (default:
    // `camera`) is the camera every LOD decision is made for — the selection, tessellation
    // factors, morph factors — while the image is drawn from `camera`: a frozen LOD for
    // inspecting a scheme, and the popping metric (this frame's view with the previous
    // frame's LOD state).
    // `host`: the image is drawn with the host's projection and depth convention instead of
    // ridge's reverse-Z one for `camera` (whose position must be the host's eye).
    FrameStats draw(const lod::Camera& camera, const RenderSettings& settings,
                    const lod::Camera* lod_camera = nullptr, const HostProjection* host = nullptr);
    // The triangles the last draw() rasterised, for picking: its instance records replayed
    // through the transform-feedback programs with its cameras, settings and resident slots,
    // so the same selection, tessellation factors and morphs. Empty before the first draw()
    // and after capture() (which replaces the instance records).
    CapturedSurface lastFrameSurface();
    // The triangles draw() would rasterise for this camera (rasterizer discarded).
    // `keep_residency`: draw what is resident now (finest resident ancestors standing in),
    // requesting and uploading nothing — the state the last draw() left, for measurements.
    CapturedSurface capture(const lod::Camera& camera, const RenderSettings& settings,
                            const lod::Camera* lod_camera = nullptr, bool keep_residency = false);
    // The popping metric (ridge/render/frame_measures.h) along a run of frames, at the cost
    // of one capture a frame. Call after each draw(): the surface this frame's LOD state draws
    // over what is resident (capture(camera, settings, nullptr, true), tessellation blocks
    // unculled) is kept as heights over the finest samples and compared with the one the
    // previous call kept, both seen from `camera`. That previous surface is what the previous
    // frame's LOD state draws for this camera — a surface depends on its LOD camera and on
    // what is resident, not on the camera looking at it, and nothing becomes resident between
    // one frame's call and the next draw() — so this is "this frame's camera drawn with the
    // previous frame's LOD state and with its own" at half the captures (the conformance
    // suite checks it against measurePopping of exactly those two captures). On a plane frame
    // the surfaces stay on the GPU (height textures over the grid, a compute reduction;
    // PoppingReport::sample_stride > 1 for grids past 64 Mi samples); on the ellipsoid they
    // come back and measurePopping compares them. Returns an empty report on the first call
    // and the first after resetPopping().
    PoppingReport measureFramePopping(const lod::Camera& camera, const RenderSettings& settings);
    void resetPopping();

    const lod::PatchQuadtree& quadtree() const;
    // b: cells per tessellation block edge (the largest tessellation factor).
    int blockCells() const;
    // The LOD schemes this renderer draws (RendererOptions::schemes, resolved), by name.
    const std::vector<std::string>& schemes() const;
    // Texture-array slots actually allocated (see RendererOptions::max_resident_patches).
    int residentSlots() const;
    // The patches the last draw() or capture() drew (after streaming fallbacks).
    const std::vector<PatchId>& lastDrawnPatches() const;
    // Streaming: blocks until every request so far is decoded (tests, benchmarks).
    void waitForStreaming();
    // The same for at most `timeout_seconds` (finite, >= 0): true when every request so far
    // is decoded, false when the time ran out first. True at once without streaming.
    bool waitForStreaming(double timeout_seconds);
    // Streaming: the first patch that failed to decode ("PATH: patch (...): ..."), or empty.
    // Such a patch stays drawn by its ancestor.
    std::string streamingError() const;
    size_t streamingCacheBytes() const;
    // The codes resident for `p` (read back from the GPU: tests), empty when not resident.
    std::vector<uint16_t> residentCodes(PatchId p) const;
    // λ(d) resident for `p` in metres (TessellationBlockLayout order, D <= 4 levels), read
    // back from the GPU (tests); empty when not resident.
    std::vector<float> residentBlockErrors(PatchId p) const;
    // The normal map resident for `p`: RGBA8_SNORM texels, row-major (tests); empty when not
    // resident.
    std::vector<int8_t> residentNormals(PatchId p) const;
    // The largest λ the renderer uses for `p`'s skirt (tests); −1 when not resident.
    double residentLambdaMax(PatchId p) const;
    // Patches decoded because the decoded-patch cache did not have them (misses), and loads
    // it served (hits), since construction; either mode.
    uint64_t cacheMisses() const;
    uint64_t cacheHits() const;
    // Camera placement over this terrain, from its level-0 patch (lod::CoarseTerrain, which
    // says how; each throws ridge::Error for NaN, infinite or out-of-range arguments), in the
    // space drawn with `exaggeration` (RenderSettings::exaggeration: heights times it).
    // An oblique view from the south-south-west that frames the whole terrain.
    lod::Camera defaultCamera(lod::Viewport viewport, double fov_y_degrees = 60.0,
                              double exaggeration = 1.0) const;
    // near/far planes that suit a camera at `position` over this terrain.
    void clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m,
                       double exaggeration = 1.0) const;
    // Terrain-frame height (metres, times `exaggeration`) of the level-0 patch's surface under
    // (x, y), bilinearly (cheap, for cameras); points off the terrain take its nearest border
    // point.
    double groundHeight(double x, double y, double exaggeration = 1.0) const;
    // The same under a world point of the frame (on a globe: along the ellipsoid's normal
    // through it), metres above the plane's zero or the ellipsoid.
    double groundUnder(glm::dvec3 world, double exaggeration = 1.0) const;
    // A camera at `position` looking at `look_at`, with this terrain's clip planes and the
    // frame's up through `position` (the plane's +z, the ellipsoid's normal on a globe).
    lod::Camera cameraLookingAt(glm::dvec3 position, glm::dvec3 look_at, double fov_y_degrees,
                                lod::Viewport viewport, double exaggeration = 1.0) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace ridge::render
