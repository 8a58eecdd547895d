// Embedding ridge: build an archive from a GeoTIFF, open it, ask heights without a GL context,
// verify it against its source, and render a PNG headless.
//   ridge_embed SOURCE.tif OUTPUT_DIR
#include <ridge/ridge.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

int main(int argc, char** argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SOURCE OUTPUT_DIR\n", argv[0]);
        return 2;
    }
    const std::string source = argv[1], dir = argv[2];
    const std::string archive = dir + "/terrain.ridge", png = dir + "/terrain.png";
    try {
        std::printf("ridge %s\n", ridge::versionString());

        ridge::BuildParameters build;
        build.codec = "progressive"; // L∞-bounded, GPU-decodable
        build.max_error = 1.0;       // metres, end to end
        build.patch_size = 65;
        const ridge::BuildSummary built = ridge::build(source, archive, build);
        std::printf("built %s: %lld x %lld samples, %d levels, %lld patches, %llu bytes\n",
                    archive.c_str(), (long long)built.width, (long long)built.height, built.levels,
                    (long long)built.patches, (unsigned long long)built.archive_bytes);

        const ridge::Terrain terrain(archive);
        const ridge::TerrainInfo& info = terrain.info();
        std::printf("spacing %.2f x %.2f m, heights %.1f .. %.1f m, bound %.3f m\n", info.spacing_x,
                    info.spacing_y, info.min_height, info.max_height, info.max_error);

        // Heights without a GL context: the centre of the terrain, in local metres, and the
        // same point as longitude/latitude through PROJ.
        const double cx = 0.5 * (info.width - 1) * info.spacing_x;
        const double cy = 0.5 * (info.height - 1) * info.spacing_y;
        const std::optional<double> h = terrain.height(cx, cy);
        const std::optional<double> coarse = terrain.heightAtLevel(cx, cy, 0);
        std::printf("height at the centre: %.2f m (level 0 draws %.2f m)\n", h.value_or(NAN),
                    coarse.value_or(NAN));
        if (info.geotransform) {
            const auto [lon, lat] = terrain.lonLatFromLocal(cx, cy);
            const ridge::LocalPoint p = terrain.localFromLonLat(lon, lat);
            std::printf("centre at %.6f E, %.6f N (back to local: %.3f, %.3f)\n", lon, lat, p.x,
                        p.y);
        }
        if (terrain.height(-1e6, -1e6))
            throw ridge::Error("a point off the terrain had a height");

        const ridge::VerifySummary verified = ridge::verify(archive, source);
        std::printf("verify: %s, %lld comparisons, max error %.3f m, %lld violations\n",
                    verified.ok ? "ok" : "FAILED", (long long)verified.samples_checked,
                    verified.max_error, (long long)verified.bound_violations);
        for (const std::string& problem : verified.problems)
            std::fprintf(stderr, "  %s\n", problem.c_str());

        ridge::RenderParameters render;
        render.width = 320;
        render.height = 180;
        const ridge::FrameSummary frame = ridge::renderPng(archive, png, render);
        std::printf("rendered %s: %d patches, %llu triangles\n", png.c_str(), frame.patches,
                    (unsigned long long)frame.triangles);

        // Errors are ridge::Error and name the parameter.
        try {
            render.width = 0;
            ridge::renderPng(archive, png, render);
            return 1;
        } catch (const ridge::Error& e) {
            std::printf("refused as expected: %s\n", e.what());
        }
        return verified.ok ? 0 : 1;
    } catch (const ridge::Error& e) {
        std::fprintf(stderr, "ridge_embed: %s\n", e.what());
        return 1;
    }
}
