#include "geoid_shift.h"

#include "number_format.h"

#include "ridge/core/error.h"

#include "proj_support.h"

#include <proj.h>
#include <proj_experimental.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace ridge::io::detail {

namespace {

struct FactoryDeleter {
    void operator()(PJ_OPERATION_FACTORY_CONTEXT* f) const
    {
        proj_operation_factory_context_destroy(f);
    }
};
using Object = ProjObject;
using List = ProjList;

std::string nameOf(const PJ* object)
{
    return projName(object, "unnamed");
}

// The operations PROJ offers from `source` to `target`, best first, under a grid rule.
List operations(PJ_CONTEXT* ctx, const PJ* source, const PJ* target,
                PROJ_GRID_AVAILABILITY_USE grids)
{
    std::unique_ptr<PJ_OPERATION_FACTORY_CONTEXT, FactoryDeleter> factory(
        proj_create_operation_factory_context(ctx, nullptr));
    if (!factory)
        return nullptr;
    proj_operation_factory_context_set_grid_availability_use(ctx, factory.get(), grids);
    proj_operation_factory_context_set_spatial_criterion(
        ctx, factory.get(), PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION);
    return List(proj_create_operations(ctx, source, target, factory.get()));
}

// A real transformation: PROJ's "ballpark" one sets N = 0, which is what this file exists
// to avoid.
bool usable(PJ_CONTEXT* ctx, const PJ* op)
{
    return !proj_coordoperation_has_ballpark_transformation(ctx, op) &&
           proj_coordoperation_is_instantiable(ctx, op);
}

// The grids the non-ballpark operations need and PROJ does not have, for the message.
std::string missingGrids(PJ_CONTEXT* ctx, const PJ* source, const PJ* target)
{
    const List all = operations(ctx, source, target, PROJ_GRID_AVAILABILITY_USED_FOR_SORTING);
    std::string names;
    for (int i = 0, n = all ? proj_list_get_count(all.get()) : 0; i < n; ++i) {
        const Object op(proj_list_get(ctx, all.get(), i));
        if (!op || proj_coordoperation_has_ballpark_transformation(ctx, op.get()))
            continue;
        for (int g = 0, count = proj_coordoperation_get_grid_used_count(ctx, op.get()); g < count;
             ++g) {
            const char *short_name = nullptr, *full = nullptr, *package = nullptr, *url = nullptr;
            int direct = 0, open = 0, available = 0;
            if (proj_coordoperation_get_grid_used(ctx, op.get(), g, &short_name, &full, &package,
                                                  &url, &direct, &open, &available) &&
                !available && short_name && names.find(short_name) == std::string::npos)
                names += std::string(names.empty() ? "" : ", ") + short_name;
        }
    }
    return names;
}

} // namespace

bool wantsGeoidShift(VerticalShift mode, const VerticalDatum& datum)
{
    switch (mode) {
    case VerticalShift::Ellipsoid:
        return true;
    case VerticalShift::None:
        return false;
    case VerticalShift::Auto:
        return datum.epsg.has_value();
    }
    return false;
}

struct GeoidShift::State {
    ProjContext context;
    ProjObject transform; // (x, y, H) east-first → (x, y, h); destroyed before its context
};

GeoidShift::GeoidShift(const std::string& path, const std::string& horizontal_wkt,
                       const VerticalDatum& from, const std::array<double, 6>& gt)
    : state_(std::make_unique<State>()), path_(path), from_(from), gt_(gt)
{
    const std::string what = path + ": heights above " +
                             (from.known() ? from.describe() : std::string("an unknown datum"));
    if (!from.epsg)
        throw Error(what + " cannot be shifted to the ellipsoid: name the heights' datum by its "
                           "EPSG code (--vertical-datum EPSG:5773 for EGM96 height) or keep "
                           "them as they are (--novshift)");
    if (horizontal_wkt.empty())
        throw Error(what + " cannot be shifted to the ellipsoid: the raster has no CRS");
    State& s = *state_;
    s.context = newProjContext(path);
    PJ_CONTEXT* ctx = s.context.get();

    Object crs(proj_create(ctx, horizontal_wkt.c_str()));
    if (!crs)
        throw Error(path + ": PROJ cannot read its CRS (" + projError(ctx) + ")");
    if (proj_get_type(crs.get()) == PJ_TYPE_COMPOUND_CRS)
        crs.reset(proj_crs_get_sub_crs(ctx, crs.get(), 0));
    if (crs && proj_get_type(crs.get()) == PJ_TYPE_GEOGRAPHIC_3D_CRS)
        crs.reset(proj_crs_demote_to_2D(ctx, nullptr, crs.get()));
    if (!crs)
        throw Error(path + ": PROJ cannot take the horizontal part of its CRS (" + projError(ctx) +
                    ")");
    const PJ_TYPE type = proj_get_type(crs.get());
    geographic_ = type == PJ_TYPE_GEOGRAPHIC_2D_CRS;

    const std::string code = std::to_string(*from.epsg);
    const Object vertical(
        proj_create_from_database(ctx, "EPSG", code.c_str(), PJ_CATEGORY_CRS, 0, nullptr));
    if (!vertical || proj_get_type(vertical.get()) != PJ_TYPE_VERTICAL_CRS)
        throw Error(what + ": EPSG:" + code + " is not a vertical CRS in PROJ's database");
    const Object source(proj_create_compound_crs(ctx, nullptr, crs.get(), vertical.get()));
    const Object target(proj_crs_promote_to_3D(ctx, nullptr, crs.get()));
    if (!source || !target)
        throw Error(what + ": PROJ cannot form the 3-D CRSs of the shift (" + projError(ctx) + ")");
    const Object geodetic(proj_crs_get_geodetic_crs(ctx, crs.get()));
    target_ = nameOf(geodetic.get()) + " ellipsoidal height";

    const List found = operations(ctx, source.get(), target.get(),
                                  PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID);
    Object chosen;
    for (int i = 0, n = found ? proj_list_get_count(found.get()) : 0; i < n && !chosen; ++i) {
        Object op(proj_list_get(ctx, found.get(), i));
        if (op && usable(ctx, op.get()))
            chosen = std::move(op);
    }
    if (!chosen) {
        const std::string grids = missingGrids(ctx, source.get(), target.get());
        throw Error(what + " cannot be shifted to " + target_ + ": " +
                    (grids.empty() ? std::string("PROJ knows no transformation between them")
                                   : "PROJ's transformation needs the grid " + grids +
                                         ", which is not installed (Debian's proj-data ships "
                                         "egm96_15.gtx; put the grid in /usr/share/proj)") +
                    "; --novshift keeps the heights as they are");
    }
    operation_ = nameOf(chosen.get());
    s.transform.reset(proj_normalize_for_visualization(ctx, chosen.get()));
    if (!s.transform)
        throw Error(what + ": PROJ cannot order the CRS's axes east first (" + projError(ctx) +
                    ")");
}

GeoidShift::~GeoidShift() = default;

void GeoidShift::undulations(int y0, int rows, int width, double* out) const
{
    std::vector<double> x(static_cast<size_t>(width));
    std::vector<double> y(x.size());
    for (int r = 0; r < rows; ++r) {
        const double row = y0 + r + 0.5;
        for (int c = 0; c < width; ++c) {
            const double col = c + 0.5;
            x[c] = gt_[0] + col * gt_[1] + row * gt_[2];
            y[c] = gt_[3] + col * gt_[4] + row * gt_[5];
        }
        try {
            undulationsAt(x.data(), y.data(), size_t(width), out + static_cast<size_t>(r) * width);
        } catch (const OutsideGrid& e) {
            throw Error(path_ + ": sample (" + std::to_string(e.index) + ", " +
                        std::to_string(y0 + r) + ") at " + e.where + " is outside what " +
                        operation_ + " covers: its height cannot be shifted to the ellipsoid");
        }
    }
}

void GeoidShift::undulationsAt(double* x, double* y, size_t count, double* out) const
{
    for (size_t i = 0; i < count; ++i) {
        if (geographic_) {
            // Longitudes 0..360 (and the repeated column of a globe) onto the grid's
            // −180..180; pole rows' centres may land a rounding error past ±90°.
            x[i] = std::remainder(x[i], 360.0);
            y[i] = std::clamp(y[i], -90.0, 90.0);
        }
        out[i] = 0.0; // H = 0 in: h = N out
    }
    proj_errno_reset(state_->transform.get());
    proj_trans_generic(state_->transform.get(), PJ_FWD, x, sizeof(double), count, y, sizeof(double),
                       count, out, sizeof(double), count, nullptr, 0, 0);
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(out[i]) || std::abs(out[i]) > 1000.0)
            throw OutsideGrid{i, "x " + formatNumber(x[i]) + ", y " + formatNumber(y[i])};
}

} // namespace ridge::io::detail
