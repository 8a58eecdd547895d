#pragma once
// What a CRS says in the words gdalinfo and a GIS user use: its name, its EPSG code, and the
// vertical datum its heights refer to. Read through PROJ (only src/io talks to PROJ).
#include <optional>
#include <string>

namespace ridge::io {

// The datum heights are measured from: a vertical CRS ("EGM96 height", EPSG:5773) or, when
// the user names one PROJ does not know, that name alone.
struct VerticalDatum {
    std::string name;        // empty: not known
    std::optional<int> epsg; // the EPSG code of the vertical CRS, when it has one
    // Where it came from: "source CRS" (the vertical part of the source's compound CRS) or
    // "--vertical-datum" (given at build); empty when name is.
    std::string origin;

    bool known() const { return !name.empty(); }
    // "EGM96 height (EPSG:5773)", or the bare name without a code; "" when unknown.
    std::string describe() const;
};

struct CrsSummary {
    std::string name;        // PROJ's name of the whole CRS ("WGS 84 / UTM zone 45N")
    std::optional<int> epsg; // the whole CRS's EPSG code, stated in the WKT or identified by
                             // PROJ with full confidence; none for compound CRSs without one
    // The horizontal part's code (the CRS itself when it is not compound).
    std::optional<int> horizontal_epsg;
    VerticalDatum vertical; // origin "source CRS" when the CRS has a vertical part
};

// Summarises `crs_wkt` (any WKT or definition PROJ reads). Throws ridge::Error naming
// `what` when PROJ cannot read it; an empty `crs_wkt` gives an empty summary.
CrsSummary summarizeCrs(const std::string& crs_wkt, const std::string& what);

// The vertical datum `text` names (`build --vertical-datum`): an EPSG code ("5773",
// "EPSG:5773") of a vertical CRS, or a name. A name PROJ's database holds as a vertical CRS
// (case-insensitively) takes its canonical spelling and code; another name is kept as given,
// without a code. Throws ridge::Error ("vertical_datum ...: ...") for an empty or overlong
// name, control characters, an EPSG code PROJ does not know, or one that is not a vertical
// CRS (EPSG:4326 is horizontal).
VerticalDatum resolveVerticalDatum(const std::string& text);

} // namespace ridge::io
