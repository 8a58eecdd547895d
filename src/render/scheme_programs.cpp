#include "scheme_programs.h"

#include "terrain_scheme.h"

#include "ridge/core/error.h"

namespace ridge::render {

// RIDGE_SURFACE of terrain_common.glsl: 0 plane, 1 geographic grid on the ellipsoid, 2
// projected grid on the ellipsoid.
static int surfaceKind(const lod::TerrainFrame& frame)
{
    return !frame.onEllipsoid() ? 0 : frame.projectedGrid() ? 2 : 1;
}

SchemePrograms::SchemePrograms(const SchemeResources& r, std::vector<gpu::ShaderStage> surface,
                               std::string fragment)
    : SchemePrograms(r, std::move(surface), {{}}, std::move(fragment))
{
}

SchemePrograms::SchemePrograms(const SchemeResources& r, std::vector<gpu::ShaderStage> surface,
                               std::vector<std::vector<std::string>> variants, std::string fragment)
    : fades_(r.options.streaming && r.options.arrival_blend.max_frames > 0),
      surface_(std::move(surface)), fragment_(std::move(fragment)), variants_(variants.size())
{
    const std::vector<std::string> archive_defines = {
        "RIDGE_SURFACE " + std::to_string(surfaceKind(r.quadtree.frame())),
        std::string("RIDGE_WATER_FROM_HEIGHT ") + (r.reader.storesSampleFlags() ? "0" : "1")};
    for (size_t i = 0; i < variants.size(); ++i) {
        variants_[i].defines = archive_defines;
        variants_[i].defines.insert(variants_[i].defines.end(), variants[i].begin(),
                                    variants[i].end());
    }
}

std::array<const gpu::ShaderProgram*, 2> SchemePrograms::get(bool capture, bool fading,
                                                             size_t variant)
{
    if (variant >= variants_.size())
        throw Error("scheme program variant " + std::to_string(variant) + " of " +
                    std::to_string(variants_.size()) + " requested");
    Variant& v = variants_[variant];
    const int c = capture ? 1 : 0;
    const int f = fading && fades_ ? 1 : 0;
    if (!v.compiled[c][f]) {
        const std::vector<std::string> varyings =
            capture ? std::vector<std::string>{"Capture.tf_position", "Capture.tf_instance",
                                               "Capture.tf_skirt"}
                    : std::vector<std::string>{};
        for (int clip = 0; clip < 2; ++clip) {
            std::vector<gpu::ShaderStage> stages = surface_;
            if (clip)
                stages.push_back({GL_GEOMETRY_SHADER, "terrain_clip.geom"});
            if (!capture)
                stages.push_back({GL_FRAGMENT_SHADER, fragment_});
            std::vector<std::string> defines = v.defines;
            defines.push_back(std::string("RIDGE_ARRIVAL_BLEND ") + (f ? "1" : "0"));
            v.programs[c][f][clip] = gpu::ShaderProgram(stages, varyings, defines);
        }
        v.compiled[c][f] = true;
    }
    return {&v.programs[c][f][0], &v.programs[c][f][1]};
}

} // namespace ridge::render
