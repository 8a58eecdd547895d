#pragma once
// Command-line values shared by `ridge render`, `ridge view` and `ridge bench`.
#include "ridge/core/error.h"
#include "ridge/render/terrain_renderer.h"

#include <charconv>
#include <string>
#include <system_error>

namespace ridge::cli {

// "WIDTHxHEIGHT", as --size takes it.
inline lod::Viewport parseSize(const std::string& text)
{
    int w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
        w <= 0 || h <= 0)
        throw Error("--size " + text + ": expected WIDTHxHEIGHT, e.g. 1920x1080");
    return {w, h};
}

// "tess", "chunked" or "brute"; `option` names the flag in the message.
inline render::LodScheme parseLodScheme(const std::string& name, const std::string& option)
{
    if (name == "tess")
        return render::LodScheme::Tessellation;
    if (name == "chunked")
        return render::LodScheme::ChunkedLod;
    if (name == "brute")
        return render::LodScheme::BruteForce;
    throw Error(option + " " + name + ": expected tess, chunked or brute");
}

} // namespace ridge::cli
