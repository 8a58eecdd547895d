// The public API's build and verify (<ridge/ridge.h>): parameters mapped onto the pipeline's
// options, reports onto the public summaries. No logic of its own.
#include "ridge/ridge.h"

#include "ridge/pipeline/build.h"
#include "ridge/pipeline/verify.h"
#include "ridge/pyramid/level_pyramid.h"

#include <algorithm>

namespace ridge {

static_assert(RIDGE_VERSION_MAJOR == RIDGE_PROJECT_VERSION_MAJOR &&
                  RIDGE_VERSION_MINOR == RIDGE_PROJECT_VERSION_MINOR &&
                  RIDGE_VERSION_PATCH == RIDGE_PROJECT_VERSION_PATCH,
              "ridge.h's RIDGE_VERSION_* must equal the project version in CMakeLists.txt");

const char* versionString()
{
    return RIDGE_PROJECT_VERSION;
}

BuildSummary build(const std::string& source_path, const std::string& archive_path,
                   const BuildParameters& parameters)
{
    BuildOptions options;
    options.codec = parameters.codec;
    options.max_error = parameters.max_error;
    options.patch_size = parameters.patch_size;
    options.filter = parseFilter(parameters.filter.c_str());
    options.ingest.fill_voids = io::parseVoidFill(parameters.fill_voids);
    options.progress = parameters.progress;
    const BuildReport report = buildArchive(source_path, archive_path, options);
    BuildSummary summary;
    summary.width = report.width;
    summary.height = report.height;
    summary.levels = report.level_count;
    summary.patches = report.patch_count;
    summary.archive_bytes = report.archive_bytes;
    summary.voids_filled = report.voids_filled;
    summary.voids_kept = report.voids_kept;
    summary.seconds = report.seconds_total;
    return summary;
}

VerifySummary verify(const std::string& archive_path, const std::string& source_path,
                     const ProgressCallback& progress)
{
    VerifyOptions options;
    if (!source_path.empty())
        options.source = source_path;
    options.progress = progress;
    const VerifyReport report = verifyArchive(archive_path, options);
    VerifySummary summary;
    summary.ok = report.ok();
    summary.problems = report.problems;
    summary.source_checked = report.source_checked;
    for (const LevelVerifyReport& level : report.levels) {
        summary.samples_checked += level.samples;
        summary.max_error = std::max(summary.max_error, level.max_error);
        summary.bound_violations += level.bound_violations + level.level_violations;
    }
    return summary;
}

} // namespace ridge
