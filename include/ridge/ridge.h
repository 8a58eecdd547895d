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
#include <memory>
#include <optional>
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
    std::string codec = "lossless"; // "lossless", "raw", "progressive", "progressive-paper"
    // Lossy codecs: the L∞ bound at the finest level, metres (ingest quantization included).
    std::optional<double> max_error;
    int patch_size = 129;             // samples per patch side, 2^n + 1 (33 .. 4097)
    std::string filter = "decimate";  // level filter: "decimate" or "neville"
    // Nodata in the source: "interior" fills voids enclosed by data and keeps nodata that
    // reaches the raster's border (a warped DEM's collar, sea) as nodata, which no renderer
    // draws and queries report as off the terrain; "all" fills every void, "none" none.
    std::string fill_voids = "interior";
    ProgressCallback progress;        // optional
};

struct BuildSummary {
    int64_t width = 0;  // finest samples
    int64_t height = 0;
    int levels = 0;
    int64_t patches = 0;
    uint64_t archive_bytes = 0;
    int64_t voids_filled = 0;
    int64_t voids_kept = 0;    // nodata kept as nodata (BuildParameters::fill_voids)
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
    int64_t samples_checked = 0;       // sample comparisons: every finest sample once per level
    double max_error = 0.0;            // largest |drawn surface − source|, metres
    int64_t bound_violations = 0;      // samples farther from the source than their bound
};

// Checks every checksum and field of `archive_path`, decodes every patch and, with a
// `source_path`, checks every sample of every level against its stored error bound. Never
// throws for problems in the files (they are reported); throws ridge::Cancelled.
RIDGE_API VerifySummary verify(const std::string& archive_path,
                               const std::string& source_path = {},
                               const ProgressCallback& progress = {});

// ---- An open archive and GL-free queries --------------------------------------------------

struct TerrainInfo {
    std::string path;
    int64_t width = 0;           // finest samples, west to east
    int64_t height = 0;          // finest samples, north to south
    double spacing_x = 0.0;      // metres between samples
    double spacing_y = 0.0;
    int levels = 0;              // level 0 is one patch; levels − 1 is the finest
    int patch_size = 0;          // samples per patch side
    int64_t patches = 0;
    std::string codec;           // as `BuildParameters::codec`
    double min_height = 0.0;     // metres, over every level (bounds, not exact extremes)
    double max_height = 0.0;
    // The finest level's L∞ distance from the source, metres (codec + quantization): every
    // finest sample of Terrain::height is within this of the source sample.
    double max_error = 0.0;
    std::string crs_wkt;         // empty when the source had none
    bool geographic = false;     // the CRS is longitude/latitude
    // GDAL's geotransform of the finest grid (pixel-is-area), when the source had one.
    std::optional<std::array<double, 6>> geotransform;
};

// The position of a point in the local terrain frame, metres (see the conventions above).
struct LocalPoint {
    double x = 0.0;
    double y = 0.0;
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

  private:
    friend class Renderer;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// ---- Rendering ----------------------------------------------------------------------------

// A camera in the local frame, looking at a point (z up). Pitch and heading follow from the
// two points; the up direction is the terrain's.
struct CameraPose {
    std::array<double, 3> position{0.0, 0.0, 0.0};
    std::array<double, 3> look_at{0.0, 1.0, 0.0};
    double fov_y_degrees = 60.0;
};

struct DrawParameters {
    std::string scheme = "tess"; // LOD scheme: "tess", "chunked", "brute", "geomorph"
    double max_screen_error_px = 2.0; // ε, pixels
    // Texture detail beside ε: patches are also refined until their level's samples are at
    // most this many pixels apart on screen (colour and normals come from the patch's maps);
    // 0 disables.
    double texel_size_px = 1.0;
    bool skirts = true;
    bool sky = true;
    bool fog = true;
};

struct FrameSummary {
    int patches = 0;       // drawn
    uint64_t triangles = 0; // GPU query results arrive a frame or two late: 0 until then
    double screen_error_px = 0.0; // ε met (raised when the view needed more patches than fit)
    int missing = 0;       // streaming: selected patches drawn by a resident ancestor
};

struct RenderParameters {
    int width = 1920;  // pixels
    int height = 1080;
    int samples = 4;   // MSAA
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
    // The LOD schemes draw() may be asked for. Empty: those that need no heights on the CPU
    // ("tess", "chunked", "brute"); naming "geomorph" decodes patches on the CPU for all.
    std::vector<std::string> schemes;
};

// Draws a terrain into the caller's OpenGL 4.5 core context, which must be current on the
// calling thread from construction to destruction (ridge loads GL through libepoxy, which
// follows whatever context is current). draw() renders into the framebuffer the caller has
// bound and clears it; docs/EMBEDDING.md says which GL state it leaves changed.
class RIDGE_API Renderer {
  public:
    Renderer(const std::string& archive_path, const RendererParameters& parameters = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // One frame of the viewport `width` × `height` (the bound framebuffer's size).
    FrameSummary draw(const CameraPose& camera, int width, int height,
                      const DrawParameters& parameters = {});
    // Blocks until every streamed patch requested so far is decoded (tests, screenshots).
    void waitForStreaming();
    // An oblique view from the south-south-west that frames the whole terrain.
    CameraPose defaultCamera(int width, int height, double fov_y_degrees = 60.0) const;
    // The ground height under local (x, y) from the coarsest level (cheap: camera clamps).
    double groundHeight(double x, double y) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace ridge
