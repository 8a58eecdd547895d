#include "ridge/io/crs_summary.h"

#include "ridge/core/error.h"

#include "proj_support.h"

#include <proj.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <memory>

namespace ridge::io {

namespace {

// Longest --vertical-datum name kept: EPSG's longest vertical CRS names are about 60 characters.
constexpr size_t kMaxDatumNameLength = 120;

using detail::projError;
using Context = detail::ProjContext;
using Object = detail::ProjObject;
using List = detail::ProjList;

// A whole decimal number in int range; nullopt for anything else.
std::optional<int> parseCode(const char* text)
{
    if (!text)
        return std::nullopt;
    const std::string s = text;
    int value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec != std::errc() || end != s.data() + s.size() || value <= 0)
        return std::nullopt;
    return value;
}

bool isEpsg(const char* authority)
{
    return authority && std::string(authority) == "EPSG";
}

// The EPSG code `object` states (its first identifier), else the one PROJ identifies it as
// with 100 % confidence (a WKT without ID[] that matches an EPSG definition exactly).
std::optional<int> epsgOf(PJ_CONTEXT* context, PJ* object)
{
    for (int i = 0; proj_get_id_code(object, i); ++i)
        if (isEpsg(proj_get_id_auth_name(object, i)))
            return parseCode(proj_get_id_code(object, i));
    int* confidence = nullptr;
    const List matches(proj_identify(context, object, "EPSG", nullptr, &confidence));
    std::optional<int> code;
    if (matches && confidence && proj_list_get_count(matches.get()) > 0 && confidence[0] == 100) {
        const Object best(proj_list_get(context, matches.get(), 0));
        if (best && isEpsg(proj_get_id_auth_name(best.get(), 0)))
            code = parseCode(proj_get_id_code(best.get(), 0));
    }
    proj_int_list_destroy(confidence);
    return code;
}

std::string lower(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

std::string trimmed(const std::string& s)
{
    const size_t first = s.find_first_not_of(" \t");
    if (first == std::string::npos)
        return {};
    return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

const char* typeName(PJ_TYPE type)
{
    switch (type) {
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS:
        return "geographic";
    case PJ_TYPE_GEOCENTRIC_CRS:
        return "geocentric";
    case PJ_TYPE_PROJECTED_CRS:
        return "projected";
    case PJ_TYPE_COMPOUND_CRS:
        return "compound";
    case PJ_TYPE_ENGINEERING_CRS:
        return "engineering";
    default:
        return "non-vertical";
    }
}

} // namespace

std::string VerticalDatum::describe() const
{
    if (name.empty())
        return {};
    return epsg ? name + " (EPSG:" + std::to_string(*epsg) + ")" : name;
}

CrsSummary summarizeCrs(const std::string& crs_wkt, const std::string& what)
{
    CrsSummary summary;
    if (crs_wkt.empty())
        return summary;
    const Context context = detail::newProjContext();
    PJ_CONTEXT* ctx = context.get();
    Object crs(proj_create(ctx, crs_wkt.c_str()));
    if (!crs)
        throw Error(what + ": PROJ cannot read the CRS (" + projError(ctx) + ")");
    // A BoundCRS (WKT1 with TOWGS84) describes its source CRS.
    if (proj_get_type(crs.get()) == PJ_TYPE_BOUND_CRS)
        if (Object source{proj_get_source_crs(ctx, crs.get())})
            crs = std::move(source);
    summary.name = detail::projName(crs.get());
    summary.epsg = epsgOf(ctx, crs.get());
    const PJ_TYPE type = proj_get_type(crs.get());
    if (type == PJ_TYPE_COMPOUND_CRS) {
        const Object horizontal(proj_crs_get_sub_crs(ctx, crs.get(), 0));
        const Object vertical(proj_crs_get_sub_crs(ctx, crs.get(), 1));
        if (horizontal)
            summary.horizontal_epsg = epsgOf(ctx, horizontal.get());
        if (vertical && proj_get_type(vertical.get()) == PJ_TYPE_VERTICAL_CRS) {
            summary.vertical.name = detail::projName(vertical.get());
            summary.vertical.epsg = epsgOf(ctx, vertical.get());
            summary.vertical.origin = "source CRS";
        }
    } else {
        summary.horizontal_epsg = summary.epsg;
        if (type == PJ_TYPE_GEOGRAPHIC_3D_CRS) {
            // Heights above the CRS's ellipsoid: a vertical reference without an EPSG
            // vertical CRS of its own.
            summary.vertical.name = "ellipsoidal height (" + summary.name + ")";
            summary.vertical.origin = "source CRS";
        }
    }
    return summary;
}

VerticalDatum resolveVerticalDatum(const std::string& text)
{
    const std::string given = trimmed(text);
    const std::string quoted = "vertical_datum '" + text + "'";
    if (given.empty())
        throw Error(quoted + ": empty; name a vertical datum or give its EPSG code (e.g. "
                             "EPSG:5773 for EGM96 height)");
    if (given.size() > kMaxDatumNameLength)
        throw Error("vertical_datum: " + std::to_string(given.size()) + " characters; at most " +
                    std::to_string(kMaxDatumNameLength));
    for (const char c : given)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
            throw Error("vertical_datum: contains a control character");

    const Context context = detail::newProjContext();
    PJ_CONTEXT* ctx = context.get();
    VerticalDatum datum;
    datum.origin = "--vertical-datum";
    std::string digits = given;
    if (lower(digits).rfind("epsg:", 0) == 0)
        digits = trimmed(digits.substr(5));
    if (!digits.empty() && digits.find_first_not_of("0123456789") == std::string::npos) {
        const std::optional<int> code = parseCode(digits.c_str());
        const Object crs(code ? proj_create_from_database(ctx, "EPSG", digits.c_str(),
                                                          PJ_CATEGORY_CRS, 0, nullptr)
                              : nullptr);
        if (!crs)
            throw Error(quoted + ": PROJ's database has no EPSG CRS " + digits);
        const PJ_TYPE type = proj_get_type(crs.get());
        if (type != PJ_TYPE_VERTICAL_CRS)
            throw Error(quoted + ": EPSG:" + digits + " (" + detail::projName(crs.get()) +
                        ") is a " + typeName(type) +
                        " CRS, not a vertical one (e.g. EPSG:5773, EGM96 "
                        "height; EPSG:3855, EGM2008 height)");
        datum.name = detail::projName(crs.get());
        datum.epsg = code;
        return datum;
    }
    // A name: EPSG's spelling and code when its database knows it as a vertical CRS.
    PJ_TYPE types[] = {PJ_TYPE_VERTICAL_CRS};
    const List matches(proj_create_from_name(ctx, "EPSG", given.c_str(), types, 1, 0, 0, nullptr));
    const int count = matches ? proj_list_get_count(matches.get()) : 0;
    for (int i = 0; i < count; ++i) {
        const Object match(proj_list_get(ctx, matches.get(), i));
        if (match && lower(detail::projName(match.get())) == lower(given)) {
            datum.name = detail::projName(match.get());
            datum.epsg = epsgOf(ctx, match.get());
            return datum;
        }
    }
    datum.name = given; // a local or unregistered datum: kept as the user wrote it
    return datum;
}

} // namespace ridge::io
