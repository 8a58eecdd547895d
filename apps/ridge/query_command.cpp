// `ridge query ARCHIVE [X Y]`: terrain heights at points, without a GL context, like
// gdallocationinfo: one point from the command line, or many from stdin, one "X Y" per line.
//
// Stdin is answered in batches (HeightQuery::sampleBatch: each patch decoded once per batch,
// whatever order the points come in) with buffered output. A batch ends when the input has no
// more bytes ready (or at 65 536 points), so a program that writes one point and waits for
// its answer gets it at once, and a file of points is answered 65 536 at a time.
#include "commands.h"
#include "range_check.h"

#include "ridge/core/error.h"
#include "ridge/core/json_text.h"
#include "ridge/core/line_reader.h"
#include "ridge/pipeline/height_query.h"

#include <fmt/core.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <optional>
#include <string_view>
#include <vector>

namespace ridge::cli {

namespace {

constexpr size_t kBatchPoints = 65536;

// One number of a point, spelled as every number on ridge's command line is
// (detail::parseNumber: decimal only; "-inf" reads, and the range checks refuse it).
std::optional<double> parseToken(std::string_view token)
{
    return detail::parseNumber(std::string(token));
}

// "X Y" or "X,Y" (spaces, tabs and commas all separate); nullopt for anything else.
std::optional<glm::dvec2> parsePoint(std::string_view line)
{
    auto separator = [](char c) { return c == ' ' || c == '\t' || c == ','; };
    std::string_view tokens[3];
    int count = 0;
    for (size_t k = 0; k < line.size();) {
        if (separator(line[k])) {
            ++k;
            continue;
        }
        size_t end = k;
        while (end < line.size() && !separator(line[end]))
            ++end;
        if (count == 3)
            return std::nullopt;
        tokens[count++] = line.substr(k, end - k);
        k = end;
    }
    if (count != 2)
        return std::nullopt;
    const std::optional<double> x = parseToken(tokens[0]), y = parseToken(tokens[1]);
    if (!x || !y)
        return std::nullopt;
    return glm::dvec2(*x, *y);
}

// A point is a short line; longer ones are refused without being held in memory.
constexpr size_t kMaxQueryLineBytes = 4096;

// What a line too long to be a point is echoed as: its start, and how long it was not.
std::string tooLongEcho(std::string_view start, int64_t number)
{
    return std::string(start.substr(0, 32)) + "... (line " + std::to_string(number) +
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
        j["water"] = s.water;
        j["filled"] = s.filled;
    } else {
        j["height"] = nullptr;
    }
    return j;
}

// Answers points as text lines or JSON entries, in the order they are given.
class Answers {
  public:
    explicit Answers(bool json) : json_(json) {}

    // `error`: why the point has no height (a malformed line, a bad coordinate).
    void add(std::string_view echo, const HeightSample* s, std::string_view error = {})
    {
        const bool answered = s && error.empty() && s->on_raster && !s->nodata;
        failures_ += answered ? 0 : 1;
        if (json_) {
            nlohmann::json entry = {{"input", std::string(echo)}};
            if (!error.empty())
                entry["error"] = std::string(error);
            else
                entry.update(sampleJson(*s));
            points_.push_back(std::move(entry));
            return;
        }
        auto out = std::back_inserter(text_);
        if (!error.empty())
            fmt::format_to(out, "{}: error: {}\n", echo, error);
        else if (answered)
            fmt::format_to(out, "{}: {:.3f} m (level {}, within {:g} m of the source{}{})\n", echo,
                           s->height, s->level, s->error_bound, s->water ? "; water" : "",
                           s->filled ? "; filled: a void of the source, its height invented" : "");
        else if (s->nodata)
            fmt::format_to(out,
                           "{}: nodata (the archive keeps no height here; pixel/line {:.2f}, "
                           "{:.2f})\n",
                           echo, s->pixel.x, s->pixel.y);
        else
            fmt::format_to(out, "{}: off the raster (pixel/line {:.2f}, {:.2f})\n", echo,
                           s->pixel.x, s->pixel.y);
        if (text_.size() > (size_t(1) << 16))
            flush();
    }
    // Writes what is buffered and flushes stdout (the other end of a pipe sees it now).
    // A failed write (a full disk, /dev/full, a closed pipe) is a failure naming stdout and
    // why, at once: the answers after it would be lost too.
    void flush()
    {
        errno = 0;
        const bool written = std::fwrite(text_.data(), 1, text_.size(), stdout) == text_.size() &&
                             std::fflush(stdout) == 0;
        text_.clear();
        if (!written)
            throw Error(std::string("standard output: cannot write: ") +
                        std::strerror(errno ? errno : EIO));
    }
    int failures() const { return failures_; }
    nlohmann::json& points() { return points_; }

  private:
    bool json_;
    int failures_ = 0;
    fmt::memory_buffer text_;
    nlohmann::json points_ = nlohmann::json::array();
};

// The lines read from stdin and not answered yet: their text (for the echo) and points.
struct PendingLines {
    std::string text;                // the lines, back to back
    std::vector<size_t> begin, size; // each line's place in `text`
    std::vector<std::optional<glm::dvec2>> points;

    void add(std::string_view line)
    {
        begin.push_back(text.size());
        size.push_back(line.size());
        text.append(line);
        points.push_back(parsePoint(line));
    }
    std::string_view line(size_t k) const
    {
        return std::string_view(text).substr(begin[k], size[k]);
    }
    size_t count() const { return points.size(); }
    void clear()
    {
        text.clear();
        begin.clear();
        size.clear();
        points.clear();
    }
};

// Answers every pending line: the well-formed points in one batch, then each line in order.
// A batch that fails as a whole (a corrupt patch) is answered point by point instead, so
// that every other point still gets its height and the failing ones their reason.
void answerPending(HeightQuery& query, PointSpace space, int level, QueryResampling resampling,
                   PendingLines& pending, Answers& answers)
{
    std::vector<glm::dvec2> points;
    for (const auto& p : pending.points)
        if (p)
            points.push_back(*p);
    std::vector<HeightSample> samples(points.size());
    bool batched = true;
    try {
        query.sampleBatch(points, space, level, resampling, samples);
    } catch (const Error&) {
        batched = false;
    }
    size_t next = 0;
    for (size_t k = 0; k < pending.count(); ++k) {
        const std::string_view echo = pending.line(k);
        if (!pending.points[k]) {
            answers.add(echo, nullptr, "expected two numbers, X Y");
            continue;
        }
        const HeightSample& s = samples[next++];
        if (batched && !s.invalid_point) {
            answers.add(echo, &s);
            continue;
        }
        try { // the slow path says why: a bad coordinate, PROJ, a corrupt patch
            const HeightSample one = query.sample(*pending.points[k], space, level, resampling);
            answers.add(echo, &one);
        } catch (const Error& e) {
            answers.add(echo, nullptr, e.what());
        }
    }
    pending.clear();
}

// Whether stdin has bytes to read now (a regular file always has, up to its end).
bool inputReady()
{
    pollfd fd{STDIN_FILENO, POLLIN, 0};
    return ::poll(&fd, 1, 0) > 0;
}

// Reads stdin to its end, answering a batch whenever the input pauses or the batch is full.
void answerStdin(HeightQuery& query, PointSpace space, int level, QueryResampling resampling,
                 Answers& answers)
{
    PendingLines pending;
    std::string partial;   // a line whose end has not arrived yet, at most kMaxQueryLineBytes
    bool skipping = false; // inside a too-long line already answered: drop to its end
    int64_t number = 0;    // of the line being read
    std::vector<char> buffer(size_t(1) << 16);
    // A line longer than any point: answered (in order) as an error, never stored whole.
    auto tooLong = [&](std::string_view start) {
        answerPending(query, space, level, resampling, pending, answers);
        answers.add(tooLongEcho(start, number), nullptr, "not a point: the line is too long");
    };
    auto takeLine = [&](std::string_view line) {
        ++number;
        if (skipping) { // the rest of a too-long line
            skipping = false;
            return;
        }
        if (line.size() > kMaxQueryLineBytes)
            return tooLong(line);
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);
        if (line.find_first_not_of(" \t,") == std::string_view::npos)
            return; // blank lines separate groups, as in gdallocationinfo's input
        pending.add(line);
    };
    for (;;) {
        if (pending.count() >= kBatchPoints || (pending.count() > 0 && !inputReady())) {
            answerPending(query, space, level, resampling, pending, answers);
            answers.flush(); // before waiting: the writer may wait for these answers
        }
        const ssize_t n = ::read(STDIN_FILENO, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            throw Error(std::string("standard input: cannot read: ") + std::strerror(errno));
        if (n == 0)
            break;
        partial.append(buffer.data(), size_t(n));
        size_t start = 0;
        for (size_t end; (end = partial.find('\n', start)) != std::string::npos; start = end + 1)
            takeLine(std::string_view(partial).substr(start, end - start));
        partial.erase(0, start);
        if (partial.size() > kMaxQueryLineBytes) { // bounded memory whatever the input
            if (!skipping) {
                ++number;
                tooLong(partial);
                --number; // takeLine counts it again when its end arrives
                skipping = true;
            }
            partial.clear();
        }
    }
    if (!partial.empty() || skipping)
        takeLine(partial); // a last line without its newline
    answerPending(query, space, level, resampling, pending, answers);
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
    auto* lonlat =
        command_->add_flag("--lonlat", lonlat_, "Points are WGS 84 longitude, latitude in degrees");
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
    command_
        ->add_option("-r,--resampling", resampling_,
                     "nearest: the sample whose pixel holds the point, as gdallocationinfo "
                     "(default); bilinear: the surface between the samples, as drawn")
        ->check(CLI::IsMember({"nearest", "bilinear"}));
    command_->add_flag("--json", json_, "Print a JSON document on stdout");
}

int QueryCommand::run()
{
    // Check the request, then open the archive and check it has the space the points are in.
    if (x_.has_value() != y_.has_value())
        throw Error("query: give both X and Y, or neither (points from stdin)");
    const PointSpace space = lonlat_  ? PointSpace::LonLat
                             : pixel_ ? PointSpace::Pixel
                             : local_ ? PointSpace::Local
                                      : PointSpace::Crs;
    const QueryResampling resampling = parseResampling(resampling_).value();
    HeightQuery query(archive_);
    if (level_ > query.finestLevel())
        throw Error(fmt::format("--level {}: {} has levels 0 to {}", level_, archive_,
                                query.finestLevel()));
    if (space == PointSpace::Crs && !query.georeference().hasGeotransform())
        throw Error(archive_ + ": the archive has no geotransform: give points with --pixel or "
                               "--local");

    // Answer the point given, or every line of stdin.
    Answers answers(json_);
    if (x_) {
        const std::string echo = fmt::format("{} {}", formatNumber(*x_), formatNumber(*y_));
        try {
            const HeightSample s = query.sample({*x_, *y_}, space, level_, resampling);
            answers.add(echo, &s);
        } catch (const Error& e) {
            answers.add(echo, nullptr, e.what());
        }
    } else {
        answerStdin(query, space, level_, resampling, answers);
    }

    // Report: the JSON document, or the text already written; failures on stderr.
    if (json_) {
        const nlohmann::json doc = {{"archive", archive_},
                                    {"space", std::string(pointSpaceName(space))},
                                    {"resampling", std::string(resamplingName(resampling))},
                                    {"level", level_ < 0 ? query.finestLevel() : level_},
                                    {"points", std::move(answers.points())},
                                    {"failed", answers.failures()}};
        fmt::print("{}\n", jsonText(doc));
    }
    answers.flush();
    if (answers.failures() > 0)
        fmt::print(stderr, "ridge: query: {} point(s) without a height\n", answers.failures());
    return answers.failures() > 0 ? 1 : 0;
}

} // namespace ridge::cli
