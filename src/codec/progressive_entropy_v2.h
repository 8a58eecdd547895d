#pragma once
// Entropy half of progressive codec v2: residual grid <-> static-table rANS (CPU side).
//
// The symbols and their order are v1's (progressive_entropy.h): the root patch in raster
// order; a child's R refinements, then its A, B and C prediction errors, each pass in raster
// order. What changed, each measured (docs/PERF.md):
//   * only the patch's coded region is visited (progressive_reconstruction.h, CodedRegion):
//     padding beyond the valid extent costs nothing;
//   * a child whose refinements are all zero (every patch of the nested-bound levels) says
//     so in one flag and codes none;
//   * tokens are signed with one mantissa bit (progressive_tokens.h), coded with static
//     per-archive tables (progressive_tables.h) by interleaved rANS (rans_coder.h); raw
//     bits go to their own stream after the rANS words;
//   * 16 activity contexts per sample class instead of 12.
// Contexts still come from residual magnitudes only, never from heights, so the CPU can
// entropy-decode a patch whose parent lives only on the GPU.
//
// Payload v3 is v2 with contexts that never read the sample just before in the same pass
// (progressive_entropy_v2.cpp, context<>): a row's contexts are known before its symbols, so
// the decoder reads the interleaved rANS lanes side by side instead of one symbol at a time
// (rans::Decoder::decodeRun). Tables, tokens and stream layout are v2's.
//
// Payload v4 is v3 with each A, B and C context split three ways by the parent class: how
// many steps apart the R samples that bracket the sample are (the two beside an A or B sample,
// the four diagonal ones of a C sample: max − min, clamped to 2). Their bins are the parent's
// requantized at the child's step plus the child's refinements, so the parent's
// reconstruction must be on the CPU before a v4 patch is entropy-decoded: where the parent is
// flat at the child's step, a residual is nearly always 0 and codes in a fraction of a bit.
//
// Stream: varint rans_size, then rans_size bytes of rANS (rans_coder.h), then the raw bits
// to the end, LSB first, zero-padded to a byte.
#include "ridge/codec/progressive_reconstruction.h"
#include "ridge/codec/progressive_tables.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ridge {

struct ResidualCodingV2 {
    int version = 2;         // payload 2, 3 or 4: which neighbourhoods give the contexts
    int level = 0;           // selects the tables
    bool root = false;       // the coarsest patch: MED residuals in raster order
    CodedRegion region;      // samples visited
    bool refinements = true; // child: R refinements are in the stream
    // v4, child: the parent's bins at the child's step, n·n in the parent's coordinates with
    // the child's quadrant filled (what the reconstruction's requantizeParent gives), and
    // that quadrant.
    const int32_t* parent_bins = nullptr;
    int child_index = 0;
};

// Appends the stream to `out`. False when a residual is beyond the tokens' range or its
// symbol has no frequency in the table (the tables were not trained on this patch).
bool encodeResidualsV2(const int32_t* residuals, int n, const ResidualCodingV2& coding,
                       const ProgressiveTables& tables, std::vector<uint8_t>& out);

// Decodes exactly `size` bytes into residuals[n·n] (zero outside the coded region and, when
// coding.refinements is false, at the R samples). Returns 0 or a negative CodecStatus.
int decodeResidualsV2(const uint8_t* data, size_t size, int n, const ResidualCodingV2& coding,
                      const ProgressiveTables& tables, int32_t* residuals);

// Adds the symbols encodeResidualsV2 would code to `counts` (training). False when a
// residual is beyond the tokens' range.
bool countResidualsV2(const int32_t* residuals, int n, const ResidualCodingV2& coding,
                      SymbolCounts& counts);

} // namespace ridge
