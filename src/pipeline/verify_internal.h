#pragma once
// The parts of `ridge verify` (verify.cpp decodes the levels; verify_hierarchy.cpp checks what
// one level must be given the next; verify_source.cpp compares with the source raster).
// Internal to ridge_pipeline.
#include "ridge/archive/archive_reader.h"
#include "ridge/core/height_grid.h"
#include "ridge/core/progress.h"
#include "ridge/pipeline/verify.h"
#include "ridge/pyramid/sample_flags.h"
#include "ridge/pyramid/validity_pyramid.h"

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace ridge::verify_detail {

// Collects problems from parallel loops; keeps the first kMaxProblems.
class ProblemList {
  public:
    explicit ProblemList(std::vector<std::string>& out) : out_(out) {}
    void add(std::string problem);
    // Appends "... and N more problems" when some were dropped.
    void finish();

  private:
    static constexpr size_t kMaxProblems = 100;
    std::vector<std::string>& out_;
    std::mutex mutex_;
    size_t dropped_ = 0;
};

// One level as verify decoded it.
struct DecodedLevel {
    // The level's codes over whole patches (padding included), so that the next level can
    // take its parents from it: (patchesX · C + 1) × (patchesY · C + 1).
    CodeGrid grid;
    // Per patch of the level, row-major: decoded and its own checks run. Samples of a patch
    // that is not are never compared with anything (its failure is reported once).
    std::vector<uint8_t> decoded;
    // Per patch: its stored validity mask (kind only, unless Mixed), when the mask itself read.
    std::vector<PatchValidity> validity;
    // Per patch: its stored sample flags (format v4), read with the mask.
    std::vector<PatchSampleFlags> flags;
    std::vector<uint8_t> mask_read;

    bool patchDecoded(const PyramidGeometry& g, int level, int x, int y) const
    {
        return decoded[static_cast<size_t>(y) * g.patchesX(level) + x] != 0;
    }
};

// The finest level's sample validity over the valid extent, W × H row-major (1 = data), from
// the stored masks; empty when a finest mask could not be read (the failure is reported).
std::vector<uint8_t> finestValidity(const archive::ArchiveReader& reader,
                                    const DecodedLevel& finest);

// The finest level's sample flags over the valid extent, W × H row-major; empty when a
// finest patch's flags could not be read (reported) or the archive stores none (format < 4).
std::vector<uint8_t> finestFlags(const archive::ArchiveReader& reader, const DecodedLevel& finest);

// Every stored patch's flags equal those the format derives from the finest level's
// (docs/FORMAT.md, "Sample flags": a coarse sample takes the finest sample's at its position),
// and the metadata's water.samples counts the finest water samples.
void checkSampleFlagsPyramid(const archive::ArchiveReader& reader,
                             const std::vector<DecodedLevel>& levels,
                             const std::vector<uint8_t>& finest_flags, ProblemList& problems);

// Err_Appr(P) >= Err_Int(P) + max Err_Appr(child) for every patch whose level and children
// decoded, with Err_Int measured on the decoded levels (docs/FORMAT.md, "Error bounds"):
// exact for lossless codecs; for lossy ones the decoded samples lie within the codec bounds
// of the coded ones, so Err_Int of the coded levels is at least the measured one minus
// (δ'_l + δ'_{l+1}) (codec bounds), and that is what is required. Catches an Err_Appr
// understated anywhere without the source.
void checkErrorBounds(const archive::ArchiveReader& reader, const std::vector<DecodedLevel>& levels,
                      ProblemList& problems);

// Every stored mask equals the one the format derives from the finest level's sample validity
// (docs/FORMAT.md, "Validity mask": coarse samples for either filter, drawable cells at every
// level). `finest_valid` as finestValidity returns it (non-empty).
void checkValidityPyramid(const archive::ArchiveReader& reader,
                          const std::vector<DecodedLevel>& levels,
                          const std::vector<uint8_t>& finest_valid, ProblemList& problems);

// The end-to-end bound against the source on every valid sample of every level, the finest
// validity against the source's voids both ways (`finest_valid` may be empty: then the voids
// are not compared), and the finest flags (`finest_flags`, may be empty) against the source:
// filled exactly on the voids the build filled, and water where the sea level says so (on
// measured samples; a water layer only adds water, which the source cannot confirm).
void compareWithSource(const archive::ArchiveReader& reader,
                       const std::vector<DecodedLevel>& levels,
                       const std::vector<uint8_t>& finest_valid,
                       const std::vector<uint8_t>& finest_flags, const std::string& source_path,
                       VerifyReport& report, ProblemList& problems, const Progress& progress);

} // namespace ridge::verify_detail
