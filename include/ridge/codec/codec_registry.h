#pragma once
// The registry of patch codecs: a codec is its module under src/codec/ and one line in
// src/codec/codec_registry.cpp. Names, ids, lossiness, variants, option forms, messages and
// --help come from here; nothing outside a codec's module switches on its id or its name.
//
// A codec is named by a spec, "NAME[,KEY=VALUE...]": its name or one of its aliases (named
// variants: "progressive-paper"), then options its module parses ("jpeg2000,criterion=rms").
#include "ridge/codec/height_codec.h"

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ridge {

struct CodecInfo {
    const char* name;        // as --codec spells it, and as the archive's metadata records it
    CodecId id;              // the archive header's codec_id: stable, never reused
    const char* description; // one line for --help
    // Decoded heights differ from the input: a build needs a bound (--max-error).
    bool lossy = false;
    // A lossy codec a build may encode finest level first, strip by strip (docs/DESIGN.md,
    // "Build pipeline"): it predicts a patch from its parent only through reconstruct() of
    // the parent's codes, never through a chain of decodes up the pyramid, and its trainer's
    // result does not depend on the order it sees the patches in. Lossless codecs always may.
    bool finest_first = false;
    // Other base names the module answers to (its named variants), and the form of its
    // options after a comma ("" when it takes none), for --help and messages.
    std::vector<const char*> aliases = {};
    const char* option_forms = "";

    // Empty when `spec` (whose base is this codec's name or an alias) is valid; otherwise what
    // is wrong with it, in words that name the option.
    std::string (*spec_problem)(const std::string& spec) = nullptr;
    // The codec a build codes with: `spec` valid, `max_error` the finest-level bound δ_l0 in
    // codes (lossy codecs; > 0 unless the spec says otherwise), `level_count` the pyramid's
    // depth. Throws ridge::Error for settings it cannot take.
    std::unique_ptr<HeightCodec> (*from_spec)(const std::string& spec, double max_error,
                                              int level_count) = nullptr;
    // The codec an archive stores: null when its settings are invalid, with *problem naming
    // the archive's field ("codec_param[1] is 3: ...").
    std::unique_ptr<HeightCodec> (*from_settings)(const CodecSettings& settings,
                                                  std::string* problem) = nullptr;
    // Why this process will not build with `spec` although it is valid (empty: it will);
    // null for codecs that are always available.
    std::string (*unavailable)(const std::string& spec) = nullptr;
    // Variants `ridge codec-bench --ridge-codec all` runs beside the base name (a mode an
    // archive cannot hold but the comparison needs: the fractal paper's, without a bound).
    std::vector<const char*> bench_variants = {};
};

// Every codec, in registration order.
const std::vector<CodecInfo>& codecRegistry();
// The codec whose name or alias is `spec`'s base (before the first comma); null for none.
const CodecInfo* findCodec(const std::string& spec);
// What is wrong with `spec` (an unknown name, with the names there are; or the codec's own
// complaint about its options); empty when it is a valid spec.
std::string codecSpecProblem(const std::string& spec);
// "lossless, raw, progressive, progressive-v1, ...": every name and alias.
std::string codecNameList();
// One line per codec for --help: "NAME: description (also ALIASES; NAME,OPTIONS)".
std::string codecUsage();

// For a codec module's spec parser: calls `option(key, value)` for each ",KEY=VALUE" after
// `base` ("BASE" alone has none), in order. False when `spec` is not `base` followed by
// nothing or by a comma, when an option has no '=', or when `option` refuses one.
bool forEachSpecOption(const std::string& spec, std::string_view base,
                       const std::function<bool(const std::string&, const std::string&)>& option);
// `value` as a whole number in [lo, hi] (decimal digits only, no sign); nullopt otherwise.
std::optional<int> specNumber(const std::string& value, int lo, int hi);

} // namespace ridge
