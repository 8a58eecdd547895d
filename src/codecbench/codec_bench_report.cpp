// The bench's report as text tables (for people) and JSON (for scripts and docs/PERF.md).
#include "ridge/codecbench/codec_bench.h"

#include "ridge/core/atomic_output.h"
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"
#include "ridge/core/json_text.h"
#include "ridge/io/dataset_files.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace ridge::codecbench {

namespace {

std::string formatPsnr(double psnr)
{
    if (std::isinf(psnr))
        return "inf";
    if (std::isnan(psnr))
        return "-";
    return fmt::format("{:.2f}", psnr);
}

std::string formatBound(const CodecRow& row)
{
    if (!row.bounded)
        return fmt::format("none ({} samples beyond E)", row.violations);
    return row.bound_ok ? "ok" : fmt::format("VIOLATED ({} samples)", row.violations);
}

// "1 234 567": byte counts as docs/PERF.md writes them.
std::string groupedDigits(uint64_t v)
{
    std::string digits = std::to_string(v), out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0)
            out += ' ';
        out += digits[i];
    }
    return out;
}

// "ridge progressive: bytes fetched per view at 1920×1080, ε = 2 px: near …, mid …, far …"
// under a bound's table, for each of ridge's rows.
std::string formatViewBytes(const CodecBenchReport& r, const CodecRow& row)
{
    if (row.view_bytes.empty())
        return {};
    std::string out = fmt::format("{}: bytes fetched per view at {}×{}, ε = {:g} px", row.codec,
                                  r.view_width, r.view_height, r.view_epsilon_px);
    for (size_t k = 0; k < row.view_bytes.size(); ++k) {
        const ViewBytesFigure& v = row.view_bytes[k];
        out += fmt::format("{} {} {} ({} patches)", k == 0 ? ":" : ",", v.view,
                           groupedDigits(v.bytes), v.patches);
    }
    const bool ancestors = row.view_bytes.front().counts_ancestors;
    out += fmt::format("\n  (cold cache; texel target {:g} px; {})\n", r.view_texel_px,
                       ancestors ? "selected patches and every ancestor, each once"
                                 : "selected patches only: the codec needs no ancestors");
    return out;
}

nlohmann::json finiteOrNull(double v)
{
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

bool hasOverviewRows(const CodecBenchReport& r)
{
    for (const BoundResult& b : r.bounds)
        for (const CodecRow& row : b.rows)
            if (row.scope == "with overviews")
                return true;
    return false;
}

} // namespace

std::string formatCodecBenchTable(const CodecBenchReport& r)
{
    std::string out;
    out += fmt::format(
        "Input: {}, {} x {} samples, metres = {:g} + {:g} * code, heights {:g} .. {:g} m\n",
        r.input_path, r.width, r.height, r.quantization.offset, r.quantization.scale, r.minMetres(),
        r.maxMetres());
    out += fmt::format("Anchors: {}, finest level only; every codec on 1 thread of {}\n",
                       r.tile_size > 0
                           ? fmt::format("independent {} x {} tiles", r.tile_size, r.tile_size)
                           : std::string("the whole grid as one tile"),
                       r.cpu_model);

    size_t name_width = 5;
    for (const CodecInfo& c : r.codecs)
        name_width = std::max(name_width, c.codec.size());
    for (const BoundResult& b : r.bounds) {
        out +=
            fmt::format("\nMax error {:g} m (ridge: end to end; anchors: e = {} code{} = {:g} m)\n",
                        b.max_error_metres, b.max_error_codes, b.max_error_codes == 1 ? "" : "s",
                        b.max_error_codes * r.quantization.scale);
        out += fmt::format("{:<{}}  {:<14} {:>12} {:>8} {:>9} {:>10} {:>9} {:>8} {:>9} {:>9}  {}\n",
                           "codec", name_width, "scope", "bytes", "ratio", "bits/smp", "max err m",
                           "RMSE m", "PSNR dB", "enc MB/s", "dec MB/s", "bound");
        for (const CodecRow& row : b.rows)
            out +=
                fmt::format("{:<{}}  {:<14} {:>12} {:>8.2f} {:>9.3f} {:>10.3f} {:>9.3f} {:>8} "
                            "{:>9.1f} {:>9.1f}  {}\n",
                            row.codec, name_width, row.scope == "pyramid" ? "pyramid *" : row.scope,
                            row.bytes, row.ratio, row.bits_per_sample, row.max_error_metres,
                            row.rmse_metres, formatPsnr(row.psnr_db), row.encode_mb_per_s,
                            row.decode_mb_per_s, formatBound(row));
        for (const CodecRow& row : b.rows)
            if (row.codec_decode_seconds > 0)
                out += fmt::format("{}: the codec alone decodes at {:.1f} MB/s (payloads in "
                                   "memory, no archive I/O, checksums or λ)\n",
                                   row.codec, row.codec_decode_mb_per_s);
        for (const CodecRow& row : b.rows)
            out += formatViewBytes(r, row);
    }

    out += "\n* ridge's bytes are the whole .ridge archive: the finest level AND every coarser "
           "level of "
           "the\n  pyramid, the index, λ tables and metadata. The anchors code the finest level "
           "only.\n";
    if (hasOverviewRows(r)) {
        std::string sizes;
        for (const auto& [w, h] : r.overview_sizes)
            sizes += fmt::format("{}{} x {}", sizes.empty() ? "" : ", ", w, h);
        out += fmt::format("  \"+ overviews\" rows: the anchor on the finest level and on its "
                           "overviews ({}), as a GIS\n  pyramid stores them; ridge's archive "
                           "holds those levels too. Their errors cover every level.\n",
                           sizes.empty() ? "none needed: the grid is small" : sizes);
    }
    out += fmt::format(
        "ratio = finest level as 16-bit samples ({} bytes) / bytes; bits/smp = 8 bytes / "
        "{} samples.\n",
        uint64_t(r.width) * uint64_t(r.height) * 2, uint64_t(r.width) * uint64_t(r.height));
    out +=
        "Errors are measured on every finest-level sample against the ingested codes; PSNR peak = "
        "max - min height.\n";
    out +=
        "MB/s = 10^6 bytes of 16-bit samples per second on one core: encode counts the finest "
        "level "
        "in,\n  decode the samples out (ridge: every level of the pyramid; its encode is the whole "
        "build, its decode\n  opens the archive and decodes every level).\n";
    out += "Views (ridge/stream/view_bytes.h): near 300 m over the top of the terrain's centre "
           "looking north 5° down;\n  mid and far look at the centre from the south, 30° and 60° "
           "above the horizon, from R and 2R\n  (R: the terrain box's half diagonal); the "
           "renderer's own LOD selection.\n";
    out += "Codecs:\n";
    for (const CodecInfo& c : r.codecs)
        out += fmt::format("  {:<{}}  {}: {}{}\n", c.codec, name_width, c.library, c.configuration,
                           c.guarantees_bound ? "" : " (bound not guaranteed by the library)");
    return out;
}

std::string formatCodecBenchJson(const CodecBenchReport& r)
{
    nlohmann::json j;
    j["input"] = {{"path", r.input_path},
                  {"width", r.width},
                  {"height", r.height},
                  {"height_scale", r.quantization.scale},
                  {"height_offset", r.quantization.offset},
                  {"quantization_error", r.quantization.max_error},
                  {"min_metres", r.minMetres()},
                  {"max_metres", r.maxMetres()}};
    j["tile_size"] = r.tile_size;
    nlohmann::json overview_sizes = nlohmann::json::array();
    for (const auto& [w, h] : r.overview_sizes)
        overview_sizes.push_back({{"width", w}, {"height", h}});
    j["overview_sizes"] = overview_sizes;
    j["ridge_codecs"] = r.ridge_codecs;
    j["machine"] = {{"cpu_model", r.cpu_model}, {"threads", r.threads}};
    j["views"] = {{"width", r.view_width},
                  {"height", r.view_height},
                  {"epsilon_px", r.view_epsilon_px},
                  {"texel_px", r.view_texel_px},
                  {"definition",
                   "ridge/stream/view_bytes.h: near, mid, far from the archive's "
                   "extents; cold cache, ancestors counted when the codec needs them"}};
    j["notes"] = {
        {"ridge_scope", "whole archive: every level of the pyramid, index, block errors, metadata"},
        {"anchor_scope", "finest level only, independent tiles"},
        {"overviews_scope",
         "'+ overviews' rows: the finest level and every overview (every 2^k-th sample) "
         "in independent tiles; errors over every level"},
        {"ratio", "width * height * 2 / bytes"},
        {"bits_per_sample", "8 * bytes / (width * height)"},
        {"mb_per_s",
         "1e6 bytes of 16-bit samples per second, one thread; ridge decode counts all levels"},
        {"psnr_peak", "max - min height of the source; null psnr = exact"}};
    nlohmann::json codecs = nlohmann::json::array();
    for (const CodecInfo& c : r.codecs)
        codecs.push_back({{"codec", c.codec},
                          {"library", c.library},
                          {"configuration", c.configuration},
                          {"guarantees_bound", c.guarantees_bound}});
    j["codecs"] = codecs;
    nlohmann::json bounds = nlohmann::json::array();
    for (const BoundResult& b : r.bounds) {
        nlohmann::json rows = nlohmann::json::array();
        for (const CodecRow& row : b.rows) {
            rows.push_back({{"codec", row.codec},
                            {"scope", row.scope},
                            {"bytes", row.bytes},
                            {"ratio", row.ratio},
                            {"bits_per_sample", row.bits_per_sample},
                            {"max_error_codes", row.max_error_codes},
                            {"max_error_metres", row.max_error_metres},
                            {"rmse_metres", row.rmse_metres},
                            {"psnr_db", finiteOrNull(row.psnr_db)},
                            {"encode_seconds", row.encode_seconds},
                            {"decode_seconds", row.decode_seconds},
                            {"encode_bytes", row.encode_bytes},
                            {"decode_bytes", row.decode_bytes},
                            {"encode_mb_per_s", row.encode_mb_per_s},
                            {"decode_mb_per_s", row.decode_mb_per_s},
                            {"codec_decode_seconds", row.codec_decode_seconds},
                            {"codec_decode_bytes", row.codec_decode_bytes},
                            {"codec_decode_mb_per_s", row.codec_decode_mb_per_s},
                            {"violations", row.violations},
                            {"bound_ok", row.bound_ok},
                            {"bounded", row.bounded}});
            if (!row.view_bytes.empty()) {
                nlohmann::json views = nlohmann::json::object();
                for (const ViewBytesFigure& v : row.view_bytes)
                    views[v.view] = {{"bytes", v.bytes},
                                     {"patches", v.patches},
                                     {"selected", v.selected},
                                     {"counts_ancestors", v.counts_ancestors}};
                rows.back()["view_bytes"] = views;
            }
        }
        bounds.push_back({{"max_error_metres", b.max_error_metres},
                          {"max_error_codes", b.max_error_codes},
                          {"rows", rows}});
    }
    j["bounds"] = bounds;
    return jsonText(j) + "\n";
}

void writeCodecBenchJson(const CodecBenchReport& report, const std::string& path)
{
    refuseOutputOverInput(path, io::datasetFiles(report.input_path));
    writeFileAtomically(path, formatCodecBenchJson(report));
}

} // namespace ridge::codecbench
