// `ridge query ARCHIVE [X Y]`: terrain heights at points, without a GL context, like
// gdallocationinfo: one point from the command line, or many from stdin, one "X Y" per line.
#include "commands.h"
#include "range_check.h"

#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/core/line_reader.h"
#include "ridge/pipeline/height_query.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <optional>
#include <sstream>
#include <unistd.h>

namespace ridge::cli {

namespace {

// "X Y" or "X,Y" (spaces and commas both separate); nullopt for anything else.
std::optional<glm::dvec2> parsePoint(const std::string& line)
{
    std::string text = line;
    for (char& c : text)
        if (c == ',' || c == '\t')
            c = ' ';
    std::istringstream in(text);
    std::string a, b, extra;
    if (!(in >> a >> b) || (in >> extra))
        return std::nullopt;
    const std::optional<double> x = detail::parseNumber(a), y = detail::parseNumber(b);
    if (!x || !y)
        return std::nullopt;
    return glm::dvec2(*x, *y);
}

// A point is a short line; longer ones are refused without being held in memory.
constexpr size_t kMaxQueryLineBytes = 4096;

// What a line too long to be a point is echoed as: its start, and how long it was not.
std::string tooLongEcho(const LineReader::Line& line)
{
    return line.text.substr(0, 32) + "... (line " + std::to_string(line.number) +
           " is longer than " + std::to_string(kMaxQueryLineBytes) + " bytes)";
}

nlohmann::json sampleJson(const HeightSample& s)
{
    nlohmann::json j = {{"on_raster", s.on_raster},
                        {"nodata", s.nodata},
                        {"local", {s.local.x, s.local.y}},
                        {"pixel", {s.pixel.x, s.pixel.y}}};
    if (s.on_raster && !s.nodata) {
        j["height"] = s.height;
        j["level"] = s.level;
        j["patch"] = {s.patch.level, s.patch.x, s.patch.y};
        j["error_bound"] = s.error_bound;
    } else {
        j["height"] = nullptr;
    }
    return j;
}

} // namespace

void QueryCommand::registerWith(CLI::App& app)
{
    command_ = app.add_subcommand(
        "query", "Terrain height at points (like gdallocationinfo): X Y, or one point a line on "
                 "stdin");
    command_->add_option("archive", archive_, "Archive (.ridge)")->required();
    command_->add_option("x", x_, "X in the archive CRS (with --lonlat longitude, --pixel pixel)");
    command_->add_option("y", y_, "Y in the archive CRS (with --lonlat latitude, --pixel line)");
    auto* lonlat = command_->add_flag("--lonlat", lonlat_,
                                      "Points are WGS 84 longitude, latitude in degrees");
    auto* pixel = command_->add_flag(
        "--pixel", pixel_,
        "Points are GDAL pixel/line (pixel-is-area: sample (0,0)'s centre is 0.5,0.5)");
    auto* local = command_->add_flag(
        "--local", local_,
        "Points are terrain-frame metres (x east of the first column, y north of the last row, as "
        "render --camera takes them)");
    lonlat->excludes(pixel)->excludes(local);
    pixel->excludes(local);
    command_->add_option("--level", level_, "Level whose surface is read (default: the finest)")
        ->check(inIntegerRange("--level", 0, 32));
    command_->add_flag("--json", json_, "Print a JSON document on stdout");
}

int QueryCommand::run()
{
    if (x_.has_value() != y_.has_value())
        throw Error("query: give both X and Y, or neither (points from stdin)");
    const PointSpace space = lonlat_ ? PointSpace::LonLat
                             : pixel_ ? PointSpace::Pixel
                             : local_ ? PointSpace::Local
                                      : PointSpace::Crs;
    HeightQuery query(archive_);
    if (level_ > query.finestLevel())
        throw Error(fmt::format("--level {}: {} has levels 0 to {}", level_, archive_,
                                query.finestLevel()));
    if (space == PointSpace::Crs && !query.georeference().hasGeotransform())
        throw Error(archive_ + ": the archive has no geotransform: give points with --pixel or "
                               "--local");
    int failures = 0;
    nlohmann::json points = nlohmann::json::array();
    // One point: echoed as given, then its height, or a note saying why there is none.
    auto answer = [&](const std::string& echo, std::optional<glm::dvec2> point) {
        nlohmann::json entry = {{"input", echo}};
        std::string text;
        if (!point) {
            ++failures;
            entry["error"] = "expected two numbers, X Y";
            text = "error: expected two numbers, X Y";
        } else {
            try {
                const HeightSample s = query.sample(*point, space, level_);
                entry.update(sampleJson(s));
                if (s.on_raster && !s.nodata) {
                    text = fmt::format("{:.3f} m (level {}, within {:g} m of the source)",
                                       s.height, s.level, s.error_bound);
                } else if (s.nodata) {
                    ++failures;
                    text = fmt::format("nodata (the archive keeps no height here; pixel/line "
                                       "{:.2f}, {:.2f})",
                                       s.pixel.x, s.pixel.y);
                } else {
                    ++failures;
                    text = fmt::format("off the raster (pixel/line {:.2f}, {:.2f})", s.pixel.x,
                                       s.pixel.y);
                }
            } catch (const Error& e) {
                ++failures; // a bad coordinate (out of range, PROJ refuses it): next point
                entry["error"] = e.what();
                text = std::string("error: ") + e.what();
            }
        }
        if (json_)
            points.push_back(entry);
        else
            fmt::print("{}: {}\n", echo, text);
    };
    if (x_) {
        answer(fmt::format("{} {}", formatNumber(*x_), formatNumber(*y_)),
               glm::dvec2(*x_, *y_));
    } else {
        LineReader lines(STDIN_FILENO, "standard input", kMaxQueryLineBytes);
        while (const std::optional<LineReader::Line> in = lines.next()) {
            const std::string& line = in->text;
            if (!in->too_long && line.find_first_not_of(" \t\r,") == std::string::npos)
                continue; // blank lines separate groups, as in gdallocationinfo's input
            if (in->too_long) // answered, not stored or echoed whole
                answer(tooLongEcho(*in), std::nullopt);
            else
                answer(line, parsePoint(line));
            if (!json_)
                std::fflush(stdout); // a pipe's other end sees each answer as it comes
        }
    }
    if (json_) {
        const nlohmann::json doc = {{"archive", archive_},
                                    {"space", std::string(pointSpaceName(space))},
                                    {"level", level_ < 0 ? query.finestLevel() : level_},
                                    {"points", points},
                                    {"failed", failures}};
        fmt::print("{}\n", jsonText(doc));
    }
    if (failures > 0)
        fmt::print(stderr, "ridge: query: {} point(s) without a height\n", failures);
    return failures > 0 ? 1 : 0;
}

} // namespace ridge::cli
