// `ridge verify`: decodes every level top-down and checks each patch against its stored
// fields and its neighbours (this file), then what the levels imply for each other
// (verify_hierarchy.cpp) and, with a source, the end-to-end bounds (verify_source.cpp).
#include "ridge/pipeline/verify.h"

#include "verify_internal.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"
#include "ridge/io/geographic.h"
#include "ridge/pipeline/level_decoder.h"
#include "ridge/pyramid/tessellation_block_errors.h"

#include <algorithm>
#include <cmath>

namespace ridge {

namespace verify_detail {

void ProblemList::add(std::string problem)
{
    std::lock_guard lock(mutex_);
    if (out_.size() < kMaxProblems)
        out_.push_back(std::move(problem));
    else
        ++dropped_;
}

void ProblemList::finish()
{
    if (dropped_)
        out_.push_back("... and " + std::to_string(dropped_) + " more problems");
}

namespace {

// One byte per finest sample over the valid extent, W × H row-major: `byteOf(patch, i, j)` of
// the finest patch covering it; empty when a finest patch's masks could not be read.
template <typename ByteOf>
std::vector<uint8_t> finestPlane(const archive::ArchiveReader& reader, const DecodedLevel& finest,
                                 ByteOf byteOf)
{
    const PyramidGeometry& g = reader.geometry();
    const int L = g.finestLevel(), cells = g.cells();
    if (std::find(finest.mask_read.begin(), finest.mask_read.end(), 0) != finest.mask_read.end())
        return {};
    std::vector<uint8_t> plane(static_cast<size_t>(g.width()) * g.height());
    for (int y = 0; y < g.height(); ++y)
        for (int x = 0; x < g.width(); ++x) {
            const int px = std::min(x / cells, g.patchesX(L) - 1);
            const int py = std::min(y / cells, g.patchesY(L) - 1);
            plane[static_cast<size_t>(y) * g.width() + x] = byteOf(
                static_cast<size_t>(py) * g.patchesX(L) + px, x - px * cells, y - py * cells);
        }
    return plane;
}

} // namespace

std::vector<uint8_t> finestValidity(const archive::ArchiveReader& reader,
                                    const DecodedLevel& finest)
{
    return finestPlane(reader, finest, [&](size_t patch, int i, int j) -> uint8_t {
        return finest.validity[patch].sampleValid(i, j) ? 1 : 0;
    });
}

std::vector<uint8_t> finestFlags(const archive::ArchiveReader& reader, const DecodedLevel& finest)
{
    if (!reader.storesSampleFlags())
        return {};
    return finestPlane(reader, finest,
                       [&](size_t patch, int i, int j) { return finest.flags[patch].at(i, j); });
}

} // namespace verify_detail

namespace {

using archive::ArchiveReader;
using namespace verify_detail;

// A decoded patch's right column and bottom row, compared later with the neighbours that own
// those samples (patches write only their own samples, so the loop stays race-free).
struct PatchBorders {
    std::vector<uint16_t> right;
    std::vector<uint16_t> bottom;
    bool decoded = false;
};

// Why patches did not decode, reported once all levels are done so that each failure can say
// how many descendants it leaves unchecked (a progressive patch decodes from its parent: one
// bad byte at the root would otherwise read as a problem in every patch below it).
struct Failures {
    std::vector<std::string> message; // per patch index (PyramidGeometry order); "" = none
    std::vector<int64_t> cause;       // per patch index: the failed ancestor a skipped patch
                                      // needed, -1 for every other patch

    explicit Failures(int64_t patches) : message(patches), cause(patches, -1) {}
};

// Checks one decoded patch's stored metadata against its samples and stored λ (what the
// reader cannot check without decoding; the fields themselves were checked at open).
void checkPatchMetadata(const ArchiveReader& reader, PatchId p, const uint16_t* codes,
                        const std::vector<float>& stored, ProblemList& problems)
{
    const archive::PatchRecord& r = reader.record(p);
    const int n = reader.geometry().patchSize();
    const HeightQuantization q = reader.quantization();
    const auto [lo, hi] = std::minmax_element(codes, codes + static_cast<size_t>(n) * n);
    if (q.toMetres(*lo) < r.min_height || q.toMetres(*hi) > r.max_height)
        problems.add(reader.describe(p) + ": stored min/max do not bound its samples");

    const TessellationBlockLayout layout = reader.blockLayout();
    std::vector<float> computed(layout.valuesPerPatch());
    computeTessellationBlockErrors(codes, layout, computed.data());
    for (size_t i = 0; i < computed.size(); ++i) {
        if (stored[i] < computed[i] * q.scale * (1 - 1e-6)) {
            problems.add(reader.describe(p) +
                         ": stored tessellation block error is below the recomputed one");
            break;
        }
    }
}

// Decodes all patches of a level into `out` and checks each; returns the level's largest
// Err. `parents` is the previous level when the codec predicts from it, else null: a patch
// whose parent did not decode is skipped (its failure names the ancestor).
double decodeAndCheckLevel(const ArchiveReader& reader, int level, DecodedLevel& out,
                           const DecodedLevel* parents, Failures& failures, ProblemList& problems)
{
    const PyramidGeometry& g = reader.geometry();
    const int n = g.patchSize(), cells = g.cells();
    const int nx = g.patchesX(level), ny = g.patchesY(level);
    const size_t patches = static_cast<size_t>(nx) * ny;
    CodeGrid& grid = out.grid;
    grid.width = nx * cells + 1;
    grid.height = ny * cells + 1;
    grid.codes.assign(static_cast<size_t>(grid.width) * grid.height, 0);
    out.decoded.assign(patches, 0);
    out.validity.assign(patches, PatchValidity{});
    out.flags.assign(patches, PatchSampleFlags{});
    out.mask_read.assign(patches, 0);
    std::vector<PatchBorders> borders(patches);

#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
        const PatchId p{level, static_cast<int>(k % nx), static_cast<int>(k / nx)};
        const int64_t index = g.patchIndex(p);
        std::vector<uint16_t> codes(static_cast<size_t>(n) * n), parent;
        std::vector<float> block_errors;
        if (parents) {
            const PatchId up = p.parent();
            if (!parents->patchDecoded(g, up.level, up.x, up.y)) {
                const int64_t up_index = g.patchIndex(up);
                failures.cause[index] =
                    failures.cause[up_index] >= 0 ? failures.cause[up_index] : up_index;
                continue;
            }
            parent.resize(codes.size());
            copyPatchFromGrid(parents->grid, p.x / 2 * cells, p.y / 2 * cells, n, parent.data());
        }
        try {
            const std::vector<uint8_t> blob = reader.readBlob(p);
            // The masks alone, checked (validity, and the sample flags of format v4).
            reader.payloadOffset(p, blob, &out.validity[k], &out.flags[k]);
            out.mask_read[k] = 1;
            reader.decodeBlob(p, blob, codes.data(), parents ? parent.data() : nullptr,
                              &block_errors);
            checkPatchMetadata(reader, p, codes.data(), block_errors, problems);
        } catch (const Error& e) {
            failures.message[index] = e.what();
            continue;
        }
        out.decoded[k] = 1;
        // Own samples: [i0, i0+cells) x [j0, j0+cells), plus the far border on the last patch.
        const int i0 = p.x * cells, j0 = p.y * cells;
        const int ie = std::min(grid.width, i0 + (p.x == nx - 1 ? cells + 1 : cells));
        const int je = std::min(grid.height, j0 + (p.y == ny - 1 ? cells + 1 : cells));
        for (int j = j0; j < je; ++j)
            for (int i = i0; i < ie; ++i)
                grid.at(i, j) = codes[static_cast<size_t>(j - j0) * n + (i - i0)];
        PatchBorders& b = borders[k];
        b.decoded = true;
        for (int t = 0; t < n; ++t) {
            b.right.push_back(codes[static_cast<size_t>(t) * n + cells]);
            b.bottom.push_back(codes[static_cast<size_t>(cells) * n + t]);
        }
    }

    // Shared borders: a patch's right column / bottom row must equal the samples written by
    // the patches that own them (skipping owners that failed to decode; they are reported).
    auto ownerDecoded = [&](int i, int j) {
        const int ox = std::min(i / cells, nx - 1), oy = std::min(j / cells, ny - 1);
        return borders[static_cast<size_t>(oy) * nx + ox].decoded;
    };
    double max_err = 0.0;
    for (int64_t k = 0; k < int64_t{nx} * ny; ++k) {
        const PatchId p{level, static_cast<int>(k % nx), static_cast<int>(k / nx)};
        max_err = std::max(max_err, double(reader.record(p).err));
        const PatchBorders& b = borders[k];
        if (!b.decoded)
            continue;
        const int i0 = p.x * cells, j0 = p.y * cells;
        bool right_ok = true, bottom_ok = true;
        for (int t = 0; t < n; ++t) {
            const int ir = i0 + cells, jr = j0 + t; // right column sample
            if (p.x + 1 < nx && jr < grid.height && ownerDecoded(ir, jr))
                right_ok &= grid.at(ir, jr) == b.right[t];
            const int ib = i0 + t, jb = j0 + cells; // bottom row sample
            if (p.y + 1 < ny && ib < grid.width && ownerDecoded(ib, jb))
                bottom_ok &= grid.at(ib, jb) == b.bottom[t];
        }
        if (!right_ok)
            problems.add(reader.describe(p) + ": right border differs from its east neighbour");
        if (!bottom_ok)
            problems.add(reader.describe(p) + ": bottom border differs from its south neighbour");
    }
    return max_err;
}

// One problem per patch that did not decode, in index order, saying how many patches below
// it were skipped for it; a decoder disabled in this process (HTJ2K without
// RIDGE_ALLOW_HTJ2K) fails every patch for the same reason, which is said once.
void reportFailures(const Failures& failures, ProblemList& problems)
{
    std::vector<int64_t> skipped_below(failures.message.size(), 0);
    for (const int64_t cause : failures.cause)
        if (cause >= 0)
            ++skipped_below[static_cast<size_t>(cause)];
    const std::string disabled = codecStatusMessage(kCodecDisabled);
    int64_t disabled_count = 0;
    std::string first_disabled;
    for (size_t i = 0; i < failures.message.size(); ++i) {
        const std::string& m = failures.message[i];
        if (m.empty())
            continue;
        if (m.size() >= disabled.size() &&
            m.compare(m.size() - disabled.size(), disabled.size(), disabled) == 0) {
            if (disabled_count++ == 0)
                first_disabled = m;
            disabled_count += skipped_below[i];
            continue;
        }
        const int64_t below = skipped_below[i];
        problems.add(below == 0 ? m
                                : m + " (the " + std::to_string(below) +
                                      " patches below it decode from it and are not checked)");
    }
    if (disabled_count > 0)
        problems.add(first_disabled + " (" + std::to_string(disabled_count) +
                     " patches are not checked for this reason)");
}

} // namespace

VerifyReport verifyArchive(const std::string& archive_path, const VerifyOptions& options)
{
    VerifyReport report;
    ProblemList problems(report.problems);
    try {
        // 1. Header, metadata and index: checksums and every field (the reader refuses a
        // corrupt or inconsistent file, naming the field).
        const ArchiveReader reader(archive_path);
        const PyramidGeometry& g = reader.geometry();

        // A CRS nothing can read: extract refuses to write it, lon/lat cannot be converted.
        if (const std::string& wkt = reader.metadata().georeference.crs_wkt; !wkt.empty())
            if (const std::string why = io::crsReadProblem(wkt); !why.empty())
                problems.add(archive_path +
                             ": metadata: georeference.crs_wkt is not a CRS PROJ can read (" + why +
                             "): extract cannot write it and longitude/latitude cannot "
                             "be converted");

        // 2. Every patch: checksum, mask, decode, min/max, λ, shared borders.
        const double decode_share = options.source ? 0.3 : 0.9;
        std::vector<DecodedLevel> levels(g.levelCount());
        Failures failures(g.patchCount());
        for (int l = 0; l < g.levelCount(); ++l) {
            LevelVerifyReport lr;
            lr.level = l;
            lr.patches = g.patchCount(l);
            const DecodedLevel* parents = reader.codec().needsParent(l) ? &levels[l - 1] : nullptr;
            lr.max_err_bound =
                decodeAndCheckLevel(reader, l, levels[l], parents, failures, problems);
            lr.level_bound = reader.levelErrorBound(l);
            report.levels.push_back(lr);
            report.patches_checked += lr.patches;
            reportProgress(options.progress, decode_share * double(l + 1) / g.levelCount());
        }
        reportFailures(failures, problems);

        // 3. What the levels imply for each other, without the source: each Err_Appr covers
        // the decoded levels' Err_Int, each mask is the one the finest level determines.
        checkErrorBounds(reader, levels, problems);
        const std::vector<uint8_t> finest_valid = finestValidity(reader, levels.back());
        if (reader.storesValidity() && !finest_valid.empty())
            checkValidityPyramid(reader, levels, finest_valid, problems);
        const std::vector<uint8_t> finest_flags = finestFlags(reader, levels.back());
        if (!finest_flags.empty())
            checkSampleFlagsPyramid(reader, levels, finest_flags, problems);
        reportProgress(options.progress, options.source ? 0.35 : 1.0);

        // 4. The end-to-end bound against the source, on every valid sample of every level,
        // and the kept voids against the source's.
        if (options.source)
            compareWithSource(reader, levels, finest_valid, finest_flags, *options.source, report,
                              problems, subProgress(options.progress, 0.35, 1.0));
    } catch (const Cancelled&) {
        throw;
    } catch (const Error& e) {
        problems.add(e.what());
    }
    problems.finish();
    return report;
}

} // namespace ridge
