#pragma once
// A LOD scheme's own options: declared by the scheme's module (SchemeInfo::options in
// src/render/terrain_scheme.h), spelt after the scheme's name in a spec string
//
//   NAME[,KEY=VALUE...]          e.g. "chunked,meshes=off,tolerance=0.5"
//
// as the command line's --lod, RendererOptions::schemes and the public API's scheme lists take
// it, and read back by the module from a SchemeOptions value. Plain C++ (no GL): the parser and
// the descriptors are checked without a context.
//
// Every option has a kind that says how its value is spelt and checked:
//   number   a decimal number within a ValueRange (NaN and infinities are refused by name)
//   integer  decimal digits within [min, max]
//   choice   one of a few names
//   flag     on or off
// Options not given take their declared default; a key may be given once.
#include "ridge/core/parameter_check.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ridge::render {

struct SchemeOption {
    enum class Kind : uint8_t { Number, Integer, Choice, Flag };

    std::string key;  // as the spec spells it: lower case, digits and '-'
    std::string help; // one line for --help
    Kind kind = Kind::Flag;
    ValueRange range;                 // Number
    int64_t min = 0, max = 0;         // Integer, inclusive
    std::vector<std::string> choices; // Choice
    std::string default_value;        // as a spec spells it ("0.5", "on", "compact")

    static SchemeOption number(std::string key, std::string help, ValueRange range,
                               double default_value);
    static SchemeOption integer(std::string key, std::string help, int64_t min, int64_t max,
                                int64_t default_value);
    static SchemeOption choice(std::string key, std::string help, std::vector<std::string> choices,
                               std::string default_value);
    static SchemeOption flag(std::string key, std::string help, bool default_value);

    // What a value must be: "a number in [0, 100]", "an integer in [1, 16]", "one of
    // standard, float, compact", "on or off".
    std::string describe() const;
    // How a spec spells a value of it: "K", "N", "standard|float|compact", "on|off".
    std::string placeholder() const;
};

// One scheme's options, every declared one with its value (given or default).
class SchemeOptions {
  public:
    SchemeOptions() = default;

    const std::string& scheme() const { return scheme_; }
    // The value of option `key`, which must be declared with that kind: a mismatch is a
    // programming error of the module (ridge::Error naming the scheme and the key).
    double number(std::string_view key) const;
    int64_t integer(std::string_view key) const;
    const std::string& choice(std::string_view key) const;
    bool flag(std::string_view key) const;
    // The whole spec, every option in declaration order: "chunked,meshes=on,tolerance=0.5".
    std::string spec() const;

  private:
    struct Value {
        std::string key;
        SchemeOption::Kind kind;
        std::string text; // canonical spelling
        double number = 0.0;
        int64_t integer = 0;
        bool flag = false;
    };
    std::string scheme_;
    std::vector<Value> values_;

    const Value& at(std::string_view key, SchemeOption::Kind kind) const;
    friend SchemeOptions parseSchemeOptions(const std::string& scheme,
                                            const std::vector<SchemeOption>& declared,
                                            std::string_view pairs, std::string_view what);
};

// `pairs` ("KEY=VALUE,KEY=VALUE", or empty) as options of `scheme`, which declares `declared`.
// Throws ridge::Error, prefixed "WHAT SCHEME: ", for an empty or malformed pair ("meshes",
// "=on", "meshes="), an undeclared key (the message lists the keys the scheme takes), a key
// given twice, and a value its option refuses: "--lod chunked: tolerance=nan: must be a
// number in [0, 100]".
SchemeOptions parseSchemeOptions(const std::string& scheme,
                                 const std::vector<SchemeOption>& declared, std::string_view pairs,
                                 std::string_view what = "LOD scheme");

// ---- The registered schemes' options (src/render/scheme_registry.cpp) ------------------------

// The options scheme `name` declares; throws ridge::Error for a name that is not registered.
const std::vector<SchemeOption>& lodSchemeOptions(const std::string& name);
// A spec ("NAME[,KEY=VALUE...]") of a registered scheme, checked as parseSchemeOptions does.
// `what` starts every message: "--lod" for the command line. An unregistered name:
// "--lod fancy: not a LOD scheme; expected one of ...".
SchemeOptions parseSchemeSpec(std::string_view spec, std::string_view what = "LOD scheme");
// For every registered scheme in order: its name (every option at its default), then for each
// of its choice and on/off options each value other than the default, alone (NAME,KEY=VALUE):
// for tests and benchmarks that cover every variant of every scheme without naming one.
std::vector<std::string> lodSchemeVariants();

} // namespace ridge::render
