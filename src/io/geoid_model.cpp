#include "ridge/io/geoid_model.h"

#include "geoid_shift.h"

#include <vector>

namespace ridge::io {

namespace {

// WGS 84 longitude/latitude: the points' CRS (the shift's horizontal part).
constexpr const char* kWgs84Wkt =
    "GEOGCRS[\"WGS 84\",DATUM[\"World Geodetic System 1984\",ELLIPSOID[\"WGS 84\",6378137,"
    "298.257223563,LENGTHUNIT[\"metre\",1]]],PRIMEM[\"Greenwich\",0,ANGLEUNIT[\"degree\","
    "0.0174532925199433]],CS[ellipsoidal,2],AXIS[\"geodetic latitude (Lat)\",north,ORDER[1],"
    "ANGLEUNIT[\"degree\",0.0174532925199433]],AXIS[\"geodetic longitude (Lon)\",east,ORDER[2],"
    "ANGLEUNIT[\"degree\",0.0174532925199433]],ID[\"EPSG\",4326]]";

} // namespace

struct GeoidModel::State {
    detail::GeoidShift shift;
    mutable std::vector<double> x, y;
};

GeoidModel::GeoidModel(const std::string& what, int vertical_epsg, const std::string& datum_name)
    : state_(new State{detail::GeoidShift(what, kWgs84Wkt,
                                          VerticalDatum{datum_name, vertical_epsg, "archive"},
                                          {0, 1, 0, 0, 0, -1}),
                       {},
                       {}})
{
}

GeoidModel::~GeoidModel() = default;

void GeoidModel::undulations(std::span<const std::array<double, 2>> lonlat,
                             std::span<double> out) const
{
    if (out.size() != lonlat.size())
        throw Error("geoid undulations: " + std::to_string(out.size()) + " outputs for " +
                    std::to_string(lonlat.size()) + " points");
    State& s = *state_;
    s.x.resize(lonlat.size());
    s.y.resize(lonlat.size());
    for (size_t i = 0; i < lonlat.size(); ++i) {
        s.x[i] = lonlat[i][0];
        s.y[i] = lonlat[i][1];
    }
    s.shift.undulationsAt(s.x.data(), s.y.data(), lonlat.size(), out.data());
}

const std::string& GeoidModel::operation() const
{
    return state_->shift.operation();
}

} // namespace ridge::io
