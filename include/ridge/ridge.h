#pragma once
// ridge's public API for embedding applications: build an archive from any raster GDAL
// reads, open it, ask the terrain's height without a GL context, verify it, and render it
// headless or into the caller's OpenGL 4.5 core context.
//
// This header and <ridge/error.h> are all that is installed; they use only the standard
// library, so an application needs no other ridge header and none of ridge's dependencies.
// Everything else in ridge is internal and may change between releases. docs/EMBEDDING.md
// has a complete example.
//
// Conventions:
// * Errors are exceptions: ridge::Error (bad input, corrupt archive, I/O, a parameter out
//   of range — the message names the file or the parameter) and ridge::Cancelled.
// * Local coordinates are the archive's terrain frame, metres: x east of the first (western)
//   column, y north of the last (southern) row, z the elevation in the source's vertical
//   datum. Geographic and CRS coordinates go through PROJ (Terrain::localFromLonLat, ...).
// * Objects are thread-compatible: one thread at a time per object; different objects may be
//   used from different threads. A Renderer belongs to the thread whose context it uses.
#include "ridge/error.h"

#include <array>
#include <cstdint>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#define RIDGE_VERSION_MAJOR 0
#define RIDGE_VERSION_MINOR 1
#define RIDGE_VERSION_PATCH 0

namespace ridge {

// "0.1.0": the library's version (equal to the RIDGE_VERSION_* macros of the header it was
// built with; an application may compare them).
RIDGE_API const char* versionString();

// Progress of a long operation in [0, 1]; return false to cancel (the operation then throws
// ridge::Cancelled and leaves no output behind).
using ProgressCallback = std::function<bool(double fraction)>;

// ---- Building and verifying archives ------------------------------------------------------

struct BuildParameters {
    // A codec spec as `ridge build --codec` takes it, NAME[,KEY=VALUE...] (its --help lists
    // the registered codecs and their options).
    std::string codec = "lossless";
    // Lossy codecs: the L∞ bound at the finest level, metres (ingest quantization included).
    std::optional<double> max_error;
    int patch_size = 129;            // samples per patch side, 2^n + 1 (33 .. 4097)
    std::string filter = "decimate"; // level filter: "decimate" or "neville"
    // Nodata in the source: "interior" fills voids enclosed by data and keeps nodata that
    // reaches the raster's border (a warped DEM's collar, sea) as nodata, which no renderer
    // draws and queries report as off the terrain; "all" fills every void, "none" none.
    std::string fill_voids = "interior";
    ProgressCallback progress; // optional
};

struct BuildSummary {
    int64_t width = 0; // finest samples
    int64_t height = 0;
    int levels = 0;
    int64_t patches = 0;
    uint64_t archive_bytes = 0;
    int64_t voids_filled = 0;
    int64_t voids_kept = 0; // nodata kept as nodata (BuildParameters::fill_voids)
    double seconds = 0.0;
};

// Builds `archive_path` from `source_path` (any raster GDAL opens). Refuses to overwrite the
// source; writes atomically (nothing is left at `archive_path` on failure or cancel).
RIDGE_API BuildSummary build(const std::string& source_path, const std::string& archive_path,
                             const BuildParameters& parameters = {});

struct VerifySummary {
    bool ok = false;                   // no problem found
    std::vector<std::string> problems; // each names the file and, where it applies, the patch
    bool source_checked = false;
    int64_t samples_checked = 0;  // sample comparisons: every finest sample once per level
    double max_error = 0.0;       // largest |drawn surface − source|, metres
    int64_t bound_violations = 0; // samples farther from the source than their bound
};

// Checks every checksum and field of `archive_path`, decodes every patch and, with a
// `source_path`, checks every sample of every level against its stored error bound. Never
// throws for problems in the files (they are reported); throws ridge::Cancelled.
RIDGE_API VerifySummary verify(const std::string& archive_path, const std::string& source_path = {},
                               const ProgressCallback& progress = {});

// ---- An open archive and GL-free queries --------------------------------------------------

struct TerrainInfo {
    std::string path;
    int64_t width = 0;      // finest samples, west to east
    int64_t height = 0;     // finest samples, north to south
    double spacing_x = 0.0; // metres between samples
    double spacing_y = 0.0;
    int levels = 0;     // level 0 is one patch; levels − 1 is the finest
    int patch_size = 0; // samples per patch side
    int64_t patches = 0;
    std::string codec;       // as `BuildParameters::codec`
    double min_height = 0.0; // metres, over every level (bounds, not exact extremes)
    double max_height = 0.0;
    // The finest level's L∞ distance from the source, metres (codec + quantization): every
    // finest sample of Terrain::height is within this of the source sample.
    double max_error = 0.0;
    std::string crs_wkt;     // empty when the source had none
    bool geographic = false; // the CRS is longitude/latitude
    // GDAL's geotransform of the finest grid (pixel-is-area), when the source had one.
    std::optional<std::array<double, 6>> geotransform;
};

// The position of a point in the local terrain frame, metres (see the conventions above).
struct LocalPoint {
    double x = 0.0;
    double y = 0.0;
};

// ---- Batch height queries -------------------------------------------------------------------

// The coordinates points are given in (see Terrain's conversions).
enum class Coordinates : uint8_t {
    Local, // the terrain frame, metres
    Pixel, // GDAL pixel/line, pixel-is-area (the first sample's centre is 0.5, 0.5)
    Crs,   // the archive's CRS (needs a geotransform)
    LonLat // WGS 84 longitude, latitude in degrees, through PROJ (needs a CRS)
};

// How a point between samples is answered.
enum class Resampling : uint8_t {
    // The level's surface: bilinear between the four samples around the point, as
    // Terrain::height answers (what the renderers draw, up to their triangulation).
    Bilinear,
    // The level's sample nearest to the point: at the finest level the sample whose GDAL pixel
    // holds it (pixel ⌊P⌋, line ⌊L⌋): what gdallocationinfo reports. Equal to the source
    // sample in a lossless archive of an integer source.
    Nearest,
};

struct QueryParameters {
    Coordinates coordinates = Coordinates::Local;
    Resampling resampling = Resampling::Bilinear;
    int level = -1; // the level read: 0 (coarsest) .. levels − 1; −1 the finest
};

enum class HeightStatus : uint8_t {
    Ok,           // `height` is set
    OffTerrain,   // outside the raster's area (pixel/line [0, width] x [0, height])
    NoData,       // on the raster where the archive keeps nodata (bilinear: a cell no renderer
                  // draws; nearest: a sample that is not data)
    InvalidPoint, // NaN or infinite coordinates, a longitude/latitude out of range, or a point
                  // PROJ cannot transform into the archive's CRS
};

// One point's answer (24 bytes; `status` leaves room for per-sample flags without growing it).
struct PointHeight {
    double height = std::numeric_limits<double>::quiet_NaN(); // metres; NaN unless Ok
    // Err(P) of the patch read, metres: every sample of it is within this of the source
    // (codec and quantization; at a coarser level also the level's simplification). 0 unless Ok.
    double error_bound = 0.0;
    int level = -1; // the level read
    HeightStatus status = HeightStatus::InvalidPoint;
    // With a height (Ok): water there (the archive's water flags, as the renderers draw it:
    // sea, lakes, whatever the build's --sea-level and --water said), and whether the height
    // was invented by filling a void of the source (SRTM holes) rather than measured.
    bool water = false;
    bool filled = false;
};

// ---- Cameras --------------------------------------------------------------------------------

// A camera in the local frame, looking at a point (z up). Pitch and heading follow from the
// two points; the up direction is the terrain's.
struct CameraPose {
    std::array<double, 3> position{0.0, 0.0, 0.0};
    std::array<double, 3> look_at{0.0, 1.0, 0.0};
    double fov_y_degrees = 60.0;
};

// A camera given the ways a GIS user gives one (what `ridge render --camera-lonlat
// --above-ground --look-at-lonlat --heading --pitch` take); Terrain::cameraPose resolves it.
// Exactly one position form; at most one of a look-at point (either form) or heading + pitch;
// nothing: the look-at point is the terrain's centre on its surface.
struct CameraParameters {
    std::optional<std::array<double, 3>> position;        // local x, y, z, metres
    std::optional<std::array<double, 3>> position_lonlat; // longitude°, latitude°, height m
    bool above_ground = false; // the position's height is above the finest surface under it
    std::optional<std::array<double, 3>> look_at; // local x, y, z, metres
    // Longitude°, latitude°, height m; a NaN height looks at the finest surface there.
    std::optional<std::array<double, 3>> look_at_lonlat;
    // Degrees clockwise from grid north (local +y; Terrain::convergenceDegrees turns it into
    // true north) and above the horizon (negative looks down, within ±89).
    std::optional<double> heading_degrees;
    std::optional<double> pitch_degrees;
    double fov_y_degrees = 60.0; // (0, 180)
    // The vertical exaggeration the camera is for (DrawParameters::vertical_exaggeration):
    // heights given are in the drawn space, the ground is the drawn ground.
    double vertical_exaggeration = 1.0;
};

class RIDGE_API Terrain {
  public:
    // Opens and validates `archive_path` (header, index, every field; blobs are checked as
    // they are read). `cache_patches` decoded patches are kept for queries (LRU; at least
    // the pyramid's depth whatever is asked).
    explicit Terrain(const std::string& archive_path, size_t cache_patches = 256);
    ~Terrain();
    Terrain(Terrain&&) noexcept;
    Terrain& operator=(Terrain&&) noexcept;
    Terrain(const Terrain&) = delete;
    Terrain& operator=(const Terrain&) = delete;

    const TerrainInfo& info() const;

    // The finest level's surface at local (x, y): bilinear between the decoded finest samples.
    // std::nullopt off the terrain and where it keeps nodata (the cells no renderer draws).
    // Throws ridge::Error for NaN or infinite coordinates.
    std::optional<double> height(double x, double y) const;
    // The surface of level `level` (0 = coarsest, levels − 1 = finest) at (x, y): what a LOD
    // scheme draws where it selects that level (bilinear over the covering patch's samples).
    std::optional<double> heightAtLevel(double x, double y, int level) const;

    // Coordinate conversions into the local frame. Pixel/line follows GDAL (pixel-is-area:
    // the centre of the first sample is (0.5, 0.5)). CRS and longitude/latitude need a
    // georeferenced archive (else ridge::Error); longitude/latitude are WGS 84 degrees.
    LocalPoint localFromPixel(double pixel, double line) const;
    LocalPoint localFromCrs(double x, double y) const;
    LocalPoint localFromLonLat(double longitude, double latitude) const;
    std::array<double, 2> lonLatFromLocal(double x, double y) const;
    // The meridian convergence at local (x, y): degrees clockwise from grid north (local +y)
    // to true north; 0 for a north-up longitude/latitude archive, up to a few degrees in a
    // transverse Mercator zone. Needs a CRS (else ridge::Error).
    double convergenceDegrees(double x, double y) const;

    // Batch queries: out[k] answers points[k] ({x, y} in parameters.coordinates). Points are
    // read in input order when the patches they touch fit in the cache, else patch by patch:
    // either way each patch the points fall in is decoded at most once a call, whatever the
    // order of the points and the cache size. Over 10^6 points a second once decoded
    // (bench/query_bench.cpp; longitude/latitude add PROJ's cost). A bad point gets its
    // status and the batch goes on. Throws ridge::Error when out.size() != points.size(), for
    // a level out of range, coordinates the archive cannot take (CRS without a geotransform,
    // longitude/latitude without a CRS), or a corrupt patch. Same thread rules as height().
    void heights(std::span<const std::array<double, 2>> points, std::span<PointHeight> out,
                 const QueryParameters& parameters = {}) const;
    std::vector<PointHeight> heights(std::span<const std::array<double, 2>> points,
                                     const QueryParameters& parameters = {}) const;
    // heights() on a thread of its own, over its own reader of the archive (its own file
    // handle and decoded-patch cache of the size this Terrain was given): it shares nothing
    // with this Terrain, which may be used, moved or destroyed meanwhile. Opening costs
    // what the constructor does (header and index). Parameters are checked before it starts
    // (ridge::Error); the future rethrows what the query throws.
    std::future<std::vector<PointHeight>>
    heightsAsync(std::vector<std::array<double, 2>> points,
                 const QueryParameters& parameters = {}) const;

    // The pose `camera` describes (longitude/latitude through PROJ, heights above the
    // finest surface where asked). Throws ridge::Error naming the fields for conflicting or
    // incomplete cameras (no position, both forms of one thing, a look-at point and a
    // heading, a heading without a pitch), for values out of range, for a longitude/latitude
    // position off the raster with above_ground, or without the CRS longitude/latitude need.
    CameraPose cameraPose(const CameraParameters& camera) const;

  private:
    friend class Renderer;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// ---- Rendering ----------------------------------------------------------------------------

// The LOD schemes ridge draws with, by name, in its registry's order (the first is the
// default). A scheme may take options of its own, spelt after its name in a spec
// "NAME[,KEY=VALUE...]" (`ridge render --help` lists them); options not given take the
// scheme's defaults.
RIDGE_API std::vector<std::string> lodSchemes();

struct DrawParameters {
    // The LOD scheme. renderPng: a spec, "NAME[,KEY=VALUE...]"; Renderer::draw: the name of
    // one of the renderer's schemes (RendererParameters::schemes set their options). Empty:
    // the first of lodSchemes() for renderPng, the renderer's first scheme for draw().
    std::string scheme;
    double max_screen_error_px = 2.0; // ε, pixels
    // Texture detail beside ε: colour and normals come from the finest resident level under
    // each fragment, and levels down to samples this many pixels apart on screen are fetched
    // for it; the drawn triangles are ε's alone. 0 disables.
    double texel_size_px = 1.0;
    bool skirts = true;
    // Clear colour and depth first (to the depth convention's far value). Off: the terrain is
    // drawn over what the framebuffer holds, depth-tested against it (a host's scene).
    bool clear = true;
    bool sky = true; // the background gradient, drawn only when clearing
    bool fog = true;
    // Vertical exaggeration, (0.01, 100]: heights drawn this many times as tall. Cameras live
    // in the drawn space (defaultCamera, groundHeight and CameraParameters take the same
    // factor); ε, culling and skirts hold on the exaggerated surface; picks report true
    // heights.
    double vertical_exaggeration = 1.0;
};

struct FrameSummary {
    int patches = 0;              // drawn
    uint64_t triangles = 0;       // GPU query results arrive a frame or two late: 0 until then
    double screen_error_px = 0.0; // ε met (raised when the view needed more patches than fit)
    int missing = 0;              // streaming: selected patches drawn by a resident ancestor
};

struct RenderParameters {
    int width = 1920; // pixels
    int height = 1080;
    int samples = 4;                  // MSAA
    std::optional<CameraPose> camera; // default: an oblique view that frames the terrain
    DrawParameters draw;
};

// Renders one frame of `archive_path` without a window (EGL; Mesa's llvmpipe where there is
// no GPU) and writes `png_path` atomically.
RIDGE_API FrameSummary renderPng(const std::string& archive_path, const std::string& png_path,
                                 const RenderParameters& parameters = {});

struct RendererParameters {
    double vram_budget_mb = 256.0; // texture arrays of resident patches
    double ram_budget_mb = 256.0;  // caches of compressed and decoded patches
    bool streaming = true;         // never wait for disk: draw resident ancestors meanwhile
    // The LOD schemes draw() may be asked for, as specs "NAME[,KEY=VALUE...]" (lodSchemes()),
    // at most one per scheme. Empty: every scheme that, with its default options, needs no
    // heights on the CPU; naming one that does decodes patches on the CPU for all.
    std::vector<std::string> schemes;
};

// How window depth follows from the host's projection and which way its depth test looks.
enum class DepthConvention : uint8_t {
    // GL's defaults: glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE), GL_LESS, depth
    // cleared to 1; a projection such as glm::perspective (near → −1, far → +1).
    Standard,
    // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), GL_LESS, cleared to 1; a projection such as
    // glm::perspectiveRH_ZO (near → 0, far → 1).
    ZeroToOne,
    // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE), GL_GREATER, cleared to 0; a projection that
    // maps near to 1 and far (or infinity) to 0: what ridge draws with on its own, and what
    // keeps float depth precise over a whole terrain.
    ReverseZ,
};

// A host application's camera: the matrices it draws its own scene with, in the OpenGL/glm
// layout (column-major: element [column · 4 + row]).
struct HostView {
    // Local frame (metres, z up) → eye space (looking down −z, y up): a rigid motion, rotation
    // and translation only (a scale or shear would change what ε's pixels measure). A host whose
    // world is not ridge's local frame (another origin, y up) multiplies its world-from-local
    // transform in. Doubles: a camera far from the origin keeps its precision.
    std::array<double, 16> view{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    // Eye → clip: a perspective projection, last row (0, 0, −1, 0): glm::perspective,
    // glm::frustum (off-centre, jittered), their _ZO, infinite and reverse-Z forms.
    std::array<double, 16> projection{};
    int width = 0; // the viewport the host draws into, pixels
    int height = 0;
    DepthConvention depth = DepthConvention::Standard; // must agree with `projection`
};

// The terrain point a pick hit, on the triangles the last frame drew.
struct TerrainHit {
    std::array<double, 3> position{}; // where it was drawn: local x, y, z, metres
    double height = 0.0; // the terrain's height there, metres in the source's vertical datum
    // WGS 84 longitude, latitude in degrees; nullopt without a CRS.
    std::optional<std::array<double, 2>> lon_lat;
    double distance = 0.0; // from the ray's origin (the eye for a screen point), metres
    int level = 0;         // level of the drawn patch hit
    // How far the drawn surface is from the source around the hit, metres: the largest
    // vertical distance between the triangle hit and the archive's decoded finest samples
    // under it (measured on that triangle, whatever the scheme dropped), plus the finest
    // level's bound to the source (TerrainInfo::max_error; 0 for a lossless integer source).
    // A lossless archive drawn at its finest level gives the float rounding of the vertices
    // (below a centimetre). NaN when only kept nodata lies under the triangle.
    double error_bound = 0.0;
};

// Draws a terrain into the caller's OpenGL 4.5 core context, which must be current on the
// calling thread from construction to destruction (ridge loads GL through libepoxy, which
// follows whatever context is current). draw() renders into the framebuffer the caller has
// bound, with the viewport the caller has set. Every call that touches GL (construction,
// draw, pick) puts back the GL state it changes (docs/EMBEDDING.md lists it) and throws
// ridge::Error when a GL error is pending from the host's own calls.
class RIDGE_API Renderer {
  public:
    Renderer(const std::string& archive_path, const RendererParameters& parameters = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // One frame of the viewport `width` × `height` (the bound framebuffer's size), drawn with
    // ridge's own matrices (hostView says which), reverse-Z.
    FrameSummary draw(const CameraPose& camera, int width, int height,
                      const DrawParameters& parameters = {});
    // One frame drawn with the host's view, projection and depth convention, so that what
    // the host draws with the same matrices depth-tests against the terrain, before or after
    // (DrawParameters::clear off to keep the host's scene). LOD is chosen so that ε holds
    // in the host's pixels over the host's whole frustum (a rolled or off-centre frustum is
    // contained in a wider one). The terrain beyond a finite far plane is clipped, as the
    // host's own geometry is. Throws ridge::Error for non-finite matrices, a view that is not
    // rigid, a projection that is not perspective, or a depth convention it contradicts.
    FrameSummary draw(const HostView& view, const DrawParameters& parameters = {});
    // The view and projection draw(camera, width, height) uses (ReverseZ, infinite far
    // plane): a host can draw its own objects with them, or pass them to draw(HostView).
    HostView hostView(const CameraPose& camera, int width, int height) const;
    // The names of the schemes draw() takes (RendererParameters::schemes, resolved), the
    // first drawn when DrawParameters::scheme is empty.
    std::vector<std::string> schemes() const;

    // The terrain point under window pixel (x, y) of the last frame drawn: x right and y down
    // from the viewport's top-left corner, in pixels (pixel (i, j) covers [i, i+1) × [j, j+1);
    // mouse coordinates). The ray from the eye through it meets the triangles the last draw()
    // rasterised (the same patches, levels and tessellation, replayed): the first surface
    // triangle hit; skirts are not hit. nullopt when it meets none (sky, or terrain that frame
    // did not draw). Exact to the drawn triangles up to their float vertices (about 1e-7 of
    // the distance); TerrainHit::error_bound says how far they are from the source. The first
    // pick after a draw() captures that frame's triangles (a draw's worth of GPU work); later
    // picks of the same frame only intersect. Throws ridge::Error before any draw() and for
    // non-finite coordinates.
    std::optional<TerrainHit> pick(double x, double y);
    // The same for a ray in the local frame: origin and a non-zero direction.
    std::optional<TerrainHit> pick(const std::array<double, 3>& origin,
                                   const std::array<double, 3>& direction);

    // Blocks until every streamed patch requested so far is decoded (tests, screenshots).
    void waitForStreaming();
    // The same for at most `timeout_seconds` (finite, in [0, 10^9]): true when every request
    // so far is decoded, false when the time ran out first; true at once without streaming.
    // Decoded patches become resident in the following draw() calls (a few a frame), which
    // report FrameSummary::missing == 0 once the view is complete.
    bool waitForStreaming(double timeout_seconds);
    // An oblique view from the south-south-west that frames the whole terrain.
    // `vertical_exaggeration`: as DrawParameters', for a camera of an exaggerated frame.
    CameraPose defaultCamera(int width, int height, double fov_y_degrees = 60.0,
                             double vertical_exaggeration = 1.0) const;
    // The ground height under local (x, y) from the coarsest level (cheap: camera clamps),
    // times `vertical_exaggeration` (the drawn ground).
    double groundHeight(double x, double y, double vertical_exaggeration = 1.0) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace ridge
