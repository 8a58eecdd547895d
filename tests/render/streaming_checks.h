#pragma once
// What the streaming tests share (streaming_test.cpp and the schemes' own tests): a scene
// with its own context, a fast fly-over, and the check that drawn patches tile the extent.
#include "fixture_archives.h"
#include "ridge/codec/codec_registry.h"

#include "ridge/gpu/context.h"
#include "ridge/render/terrain_renderer.h"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace ridge::test {

// The drawn patches tile the valid extent without holes or overlaps: every finest cell is
// under exactly one of them (culling off, so the whole extent is drawn).
inline size_t holesOrOverlaps(const PyramidGeometry& g, const std::vector<PatchId>& drawn)
{
    const int W = g.width() - 1, H = g.height() - 1;
    std::vector<uint8_t> count(size_t(W) * H, 0);
    for (PatchId p : drawn) {
        const int64_t span = int64_t(g.cells()) * g.step(p.level);
        for (int64_t r = p.y * span; r < std::min<int64_t>((p.y + 1) * span, H); ++r)
            for (int64_t c = p.x * span; c < std::min<int64_t>((p.x + 1) * span, W); ++c)
                ++count[size_t(r) * W + c];
    }
    size_t bad = 0;
    for (uint8_t c : count)
        bad += c != 1;
    return bad;
}

struct StreamingScene {
    test::ScratchDir dir;
    std::unique_ptr<gpu::HeadlessContext> context = gpu::HeadlessContext::create();
    std::unique_ptr<archive::ArchiveReader> reader;

    explicit StreamingScene(const std::string& codec)
    {
        reader = std::make_unique<archive::ArchiveReader>(test::buildEverestArchive(dir, codec));
    }
};

// The registered codecs whose patches may be decoded on the GPU (a GPU half, declared by the
// codec): the streaming tests run each of them, naming none.
inline std::vector<std::string> gpuDecodedCodecs()
{
    std::vector<std::string> names;
    for (const CodecInfo& c : codecRegistry()) {
        if (!c.lossy || (c.unavailable && !c.unavailable(c.name).empty()))
            continue;
        const auto codec = makeCodec(c.name, 1.0, 5);
        if (codec->capabilities().gpu.first_level >= 0)
            names.push_back(c.name);
    }
    return names;
}

// A low, fast fly-over from the south-west corner to the north-east one.
inline lod::Camera flyover(const render::TerrainRenderer& r, int frame, int frames)
{
    const lod::TerrainFrame& f = r.quadtree().frame();
    const double t = double(frame) / frames;
    const double x = f.extentX() * (0.05 + 0.9 * t), y = f.extentY() * (0.05 + 0.9 * t);
    const glm::dvec3 pos(x, y, r.groundHeight(x, y) + 400.0);
    const glm::dvec3 at(x + 3000.0, y + 3000.0, r.groundHeight(x, y) - 300.0);
    double near_m, far_m;
    r.clipPlanesFor(pos, near_m, far_m);
    return lod::Camera(pos, at, 60.0, {320, 180}, near_m, far_m);
}

} // namespace ridge::test
