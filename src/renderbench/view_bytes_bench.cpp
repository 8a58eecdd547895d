// GL-free: selection on the CPU over the archive's index; nothing here touches the GPU layer.
#include "ridge/renderbench/view_bytes_bench.h"

#include "ridge/lod/archive_frame.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/atomic_output.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/json_text.h"
#include "ridge/lod/coarse_terrain.h"
#include "ridge/stream/view_bytes.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <numeric>

namespace ridge::renderbench {
namespace {

// The renderer's camera-placement terrain (TerrainRenderer builds the same from the root,
// with the root's box made by the frame: oriented on a globe).
lod::CoarseTerrain coarseTerrainOf(const archive::ArchiveReader& reader,
                                   const lod::PatchQuadtree& quadtree)
{
    const int n = reader.geometry().patchSize();
    std::vector<uint16_t> root(size_t(n) * size_t(n));
    reader.decodePatch(PatchId{0, 0, 0}, root.data()); // the root needs no parent
    const lod::PatchBounds& b = quadtree.bounds(PatchId{0, 0, 0});
    return lod::CoarseTerrain(quadtree.frame(), b.min_height, b.max_height, std::move(root),
                              reader.quantization());
}

void summarise(ViewBytesBenchReport& r, std::vector<char>& on_path,
               const archive::ArchiveReader& reader)
{
    std::vector<uint64_t> bytes;
    for (const ViewBytesFrameRecord& f : r.frames)
        bytes.push_back(f.bytes);
    std::sort(bytes.begin(), bytes.end());
    r.bytes_min = bytes.front();
    r.bytes_median = bytes[bytes.size() / 2];
    r.bytes_max = bytes.back();
    r.bytes_mean =
        double(std::accumulate(bytes.begin(), bytes.end(), uint64_t{0})) / double(bytes.size());
    for (size_t i = 0; i < on_path.size(); ++i)
        if (on_path[i]) {
            r.path_bytes += reader.index()[i].size;
            ++r.path_patches;
        }
    r.near_frame = 0;
    r.mid_frame = r.frames.size() / 2;
    r.far_frame = r.frames.size() - 1;
}

std::string mib(uint64_t bytes)
{
    return fmt::format("{:.2f} MiB", double(bytes) / 1048576.0);
}

} // namespace

ViewBytesBenchReport runViewBytesBench(const std::string& archive, const RenderBenchOptions& o)
{
    o.validate();
    ViewBytesBenchReport r;
    r.archive = archive;
    r.options = o;
    const archive::ArchiveReader reader(archive);
    r.codec = reader.codec().name();
    for (const archive::PatchRecord& rec : reader.index())
        r.archive_blob_bytes += rec.size;
    // The frame the renderer would draw in (--frame): the same selection, on the globe too.
    const lod::PatchQuadtree quadtree = lod::PatchQuadtree::fromArchive(
        reader, lod::terrainFrameOf(reader, o.renderer.frame, archive));
    const lod::CoarseTerrain coarse = coarseTerrainOf(reader, quadtree);
    const lod::PatchBounds& root = quadtree.bounds(PatchId{0, 0, 0});
    const std::vector<lod::CameraPose> path = lod::makeCameraPath(
        quadtree.frame(), root.min_height, root.max_height,
        [&](double x, double y) { return coarse.groundHeight(x, y); }, o.path, o.frames);

    lod::SelectionSettings settings = stream::rendererSelectionSettings(o.epsilon_px, o.texel_px);
    settings.cull = o.cull;
    settings.side_on = o.side_on_bound;
    std::vector<char> on_path(reader.index().size(), 0);
    for (const lod::CameraPose& pose : path) {
        double near_m = 1.0, far_m = 1e6;
        coarse.clipPlanesFor(pose.position, near_m, far_m);
        // Upright to the local up, as TerrainRenderer::cameraLookingAt keeps it.
        const lod::Camera camera(pose.position, pose.look_at, 60.0, o.viewport, near_m, far_m,
                                 quadtree.frame().upThrough(pose.position));
        const lod::Selection selection = quadtree.select(camera, settings);
        r.counts_ancestors = reader.codec().capabilities().needs_ancestors;
        const std::vector<PatchId> fetched =
            stream::patchesToFetch(reader.geometry(), selection.patches, r.counts_ancestors);
        ViewBytesFrameRecord f;
        f.position = pose.position;
        f.selected = selection.patches.size();
        f.patches = fetched.size();
        for (const PatchId p : fetched) {
            f.bytes += reader.record(p).size;
            on_path[size_t(reader.geometry().patchIndex(p))] = 1;
        }
        r.frames.push_back(f);
    }
    summarise(r, on_path, reader);
    return r;
}

std::string formatViewBytesSummary(const ViewBytesBenchReport& r)
{
    const RenderBenchOptions& o = r.options;
    std::string out = fmt::format(
        "{}: {} codec, {} of blobs; path {}, {} frames at {}x{}, ε {:g} px, texel {:g} px\n",
        r.archive, r.codec, mib(r.archive_blob_bytes), o.path.kind, r.frames.size(),
        o.viewport.width, o.viewport.height, o.epsilon_px, o.texel_px);
    out += fmt::format("bytes fetched per view, cold cache ({}):\n",
                       r.counts_ancestors ? "selected patches and every ancestor, each once"
                                          : "selected patches only");
    const auto frameLine = [&](const char* name, size_t k) {
        const ViewBytesFrameRecord& f = r.frames[k];
        return fmt::format("  {:<4} (frame {:>5}, camera at {:.0f} {:.0f} {:.0f} m): {:>10} bytes "
                           "({}), {} patches, {} drawn\n",
                           name, k, f.position.x, f.position.y, f.position.z, f.bytes, mib(f.bytes),
                           f.patches, f.selected);
    };
    out += frameLine("near", r.near_frame);
    out += frameLine("mid", r.mid_frame);
    out += frameLine("far", r.far_frame);
    out += fmt::format("  per frame: min {}, median {}, max {}, mean {:.0f} bytes\n", r.bytes_min,
                       r.bytes_median, r.bytes_max, r.bytes_mean);
    out += fmt::format("  whole path, nothing evicted: {} bytes ({}), {} patches\n", r.path_bytes,
                       mib(r.path_bytes), r.path_patches);
    return out;
}

std::string formatViewBytesJson(const ViewBytesBenchReport& r)
{
    nlohmann::json frames = nlohmann::json::array();
    for (const ViewBytesFrameRecord& f : r.frames)
        frames.push_back({{"position", {f.position.x, f.position.y, f.position.z}},
                          {"bytes", f.bytes},
                          {"patches", f.patches},
                          {"selected", f.selected}});
    const RenderBenchOptions& o = r.options;
    const nlohmann::json j = {{"archive", r.archive},
                              {"codec", r.codec},
                              {"counts_ancestors", r.counts_ancestors},
                              {"archive_blob_bytes", r.archive_blob_bytes},
                              {"path", o.path.kind},
                              {"speed_mps", o.path.speed_mps},
                              {"size", {o.viewport.width, o.viewport.height}},
                              {"epsilon_px", o.epsilon_px},
                              {"texel_px", o.texel_px},
                              {"cull", o.cull},
                              {"summary",
                               {{"near_frame", r.near_frame},
                                {"mid_frame", r.mid_frame},
                                {"far_frame", r.far_frame},
                                {"near_bytes", r.frames[r.near_frame].bytes},
                                {"mid_bytes", r.frames[r.mid_frame].bytes},
                                {"far_bytes", r.frames[r.far_frame].bytes},
                                {"bytes_min", r.bytes_min},
                                {"bytes_median", r.bytes_median},
                                {"bytes_max", r.bytes_max},
                                {"bytes_mean", r.bytes_mean},
                                {"path_bytes", r.path_bytes},
                                {"path_patches", r.path_patches}}},
                              {"frames", frames}};
    return jsonText(j) + "\n";
}

void writeViewBytesJson(const ViewBytesBenchReport& r, const std::string& path)
{
    refuseOutputOverInput(path, {r.archive, r.options.path.kind}); // kind: maybe a pose file
    writeFileAtomically(path, formatViewBytesJson(r));
}

} // namespace ridge::renderbench
