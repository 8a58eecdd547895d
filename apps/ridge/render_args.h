#pragma once
// Command-line values shared by `ridge render`, `ridge view` and `ridge bench`.
#include "range_check.h"

#include "ridge/core/error.h"
#include "ridge/render/headless_render.h"
#include "ridge/render/terrain_renderer.h"

#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdio>
#include <map>
#include <string>
#include <system_error>

namespace ridge::cli {

// "WIDTHxHEIGHT", as --size takes it, each side in [1, max_side] pixels.
inline lod::Viewport parseSize(const std::string& text,
                               int max_side = render::HeadlessRenderOptions::kMaxImageSide)
{
    long long w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%lld%c%lld%c", &w, &x, &h, &extra) != 3 ||
        (x != 'x' && x != 'X'))
        throw Error("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1920x1080");
    if (w < 1 || h < 1 || w > max_side || h > max_side)
        throw Error("--size " + text + ": each side must be an integer in [1, " +
                    std::to_string(max_side) + "]");
    return {int(w), int(h)};
}

// A registered LOD scheme's name (render::lodSchemeNames()); `option` names the flag in the
// message.
inline std::string parseLodScheme(const std::string& name, const std::string& option)
{
    for (const std::string& known : render::lodSchemeNames())
        if (name == known)
            return name;
    throw Error(option + " " + name + ": expected " + render::lodSchemeList());
}

// --help text listing every registered scheme with its description.
inline std::string lodSchemeHelp()
{
    std::string help = "LOD scheme:";
    for (const std::string& name : render::lodSchemeNames())
        help += "\n  " + name + ": " + render::lodSchemeDescription(name);
    return help;
}

// The memory, upload and decoding options `ridge view` and `ridge bench` share, bound to the
// renderer's options (whose values are the defaults shown).
inline void addStreamingOptions(CLI::App& command, render::RendererOptions& options)
{
    using Options = render::RendererOptions;
    command.add_option("--vram", options.vram_budget_mb, "Texture memory for resident patches, MB")
        ->capture_default_str()
        ->check(inRange("--vram", Options::kVramBudgetMbRange));
    command
        .add_option("--ram", options.ram_budget_mb,
                    "RAM caches of compressed and decoded patches, MB")
        ->capture_default_str()
        ->check(inRange("--ram", Options::kRamBudgetMbRange));
    command.add_option("--upload-mb", options.upload_budget_mb, "Per-frame upload budget, MB")
        ->capture_default_str()
        ->check(inRange("--upload-mb", Options::kUploadBudgetMbRange));
    command.add_option("--upload-ms", options.upload_budget_ms, "Per-frame upload budget, CPU ms")
        ->capture_default_str()
        ->check(inRange("--upload-ms", Options::kUploadBudgetMsRange));
    command.add_flag_callback(
        "--cpu-decode", [&options] { options.gpu_reconstruction = false; },
        "Decode progressive patches wholly on the CPU (default: entropy decoding on the CPU, "
        "reconstruction on the GPU)");
    command.add_flag_callback(
        "--no-streaming", [&options] { options.streaming = false; },
        "Load every patch before drawing the frame that needs it (stalls)");
}

// --texel-size: the texture-detail criterion beside ε (render::RenderSettings::texel_px).
inline void addTexelSizeOption(CLI::App& command, double& texel_px)
{
    command
        .add_option("--texel-size", texel_px,
                    "Texture detail: refine patches until their samples are at most PX pixels "
                    "apart on screen (colour and normals at about one texel per pixel); 0 "
                    "disables it")
        ->capture_default_str()
        ->check(inRange("--texel-size", render::RenderSettings::kTexelPxRange));
}

// Which LOD rules: the tessellation rule and the coarse selection's bound.
inline void addLodRuleOptions(CLI::App& command, render::RenderSettings& settings)
{
    const std::map<std::string, lod::TessellationRule> rules = {
        {"conservative", lod::TessellationRule::Conservative},
        {"paper", lod::TessellationRule::Paper}};
    command
        .add_option("--tess-rule", settings.tessellation_rule,
                    "tess: conservative (ε on every sample, the default) or paper (Λ at edge "
                    "centres, interior the minimum of the edges)")
        ->transform(CLI::CheckedTransformer(rules, CLI::ignore_case))
        ->default_str("conservative");
    command.add_flag_callback(
        "--on-axis-bound", [&settings] { settings.side_on_bound = false; },
        "Coarse selection without the side-on factor (earlier releases' bound; with "
        "--tess-rule paper, their LOD)");
}

// Scheme "geomorph"'s options: the paper's vertex layouts and regimes.
inline void addGeomorphOptions(CLI::App& command, render::RendererOptions& options)
{
    const std::map<std::string, lod::GeomorphLayout> layouts = {
        {"standard", lod::GeomorphLayout::Standard},
        {"float", lod::GeomorphLayout::FloatMorph},
        {"compact", lod::GeomorphLayout::Compact}};
    command
        .add_option("--geomorph-layout", options.geomorph_layout,
                    "geomorph: vertex layout — standard (CPU morph, positions sent every frame), "
                    "float (GPU morph, float position, target and normal) or compact (block "
                    "coordinates, 16-bit codes, 2-byte hemisphere normal index)")
        ->transform(CLI::CheckedTransformer(layouts, CLI::ignore_case))
        ->default_str("compact");
    const std::map<std::string, lod::HemisphereMap> maps = {
        {"orthographic", lod::HemisphereMap::Orthographic},
        {"concentric", lod::HemisphereMap::Concentric}};
    command
        .add_option("--geomorph-normals", options.geomorph_normal_map,
                    "geomorph compact: hemisphere normal texture — orthographic or concentric "
                    "(Shirley and Chiu's map)")
        ->transform(CLI::CheckedTransformer(maps, CLI::ignore_case))
        ->default_str("orthographic");
    command.add_flag("--geomorph-per-frame", options.geomorph_per_frame,
                     "geomorph: send every drawn patch's vertices every frame (the paper's "
                     "regime, no resident buffers)");
}

} // namespace ridge::cli
