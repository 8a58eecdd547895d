#pragma once
// `ridge verify`: proves an archive is intact and its error bounds hold.
//
// Without a source: every checksum (header, metadata, index, each patch), every field the
// reader checks when it opens an archive (docs/FORMAT.md), every patch decodes, every patch's
// stored min/max bound its samples, stored λ(d) are not below λ recomputed from the decoded
// samples, and neighbouring patches agree on shared borders.
// With a source: additionally, for every level l and every valid (non-void) sample of the
// source, |bilinear surface of level l - source| <= Err(P) of the patch P covering it, and
// at the level's own sample positions (all levels for decimation, the finest for Neville)
// |decoded - source| <= δ_l.
#include "ridge/core/progress.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ridge {

struct VerifyOptions {
    std::optional<std::string> source;
    Progress progress;
};

struct LevelVerifyReport {
    int level = 0;
    int64_t patches = 0;
    double max_err_bound = 0.0; // largest stored Err(P) of the level (metres)
    // Filled with a source:
    int64_t samples = 0;    // full-resolution samples compared
    double max_error = 0.0; // max |surface - source| (metres)
    double rms_error = 0.0;
    int64_t bound_violations = 0; // samples with |surface - source| > Err(P)
    int64_t level_samples = 0;    // level sample positions compared with the source
    double max_level_error = 0.0; // max |decoded - source| at those positions
    double level_bound = 0.0;     // δ_l
    int64_t level_violations = 0;
};

struct VerifyReport {
    std::vector<std::string> problems; // each names the file and, where it applies, the patch
    std::vector<LevelVerifyReport> levels;
    int64_t patches_checked = 0;
    int64_t source_voids = 0;   // source samples skipped because they are voids
    int64_t nodata_samples = 0; // finest samples the archive keeps as nodata (with a
                                // source; each must be a source void, else a problem)
    bool source_checked = false;
    bool ok() const { return problems.empty(); }
};

// Never throws for archive or source problems: they are collected in the report (a file that
// cannot be opened at all yields a report with one problem). Throws ridge::Cancelled.
VerifyReport verifyArchive(const std::string& archive_path, const VerifyOptions& options);

} // namespace ridge
