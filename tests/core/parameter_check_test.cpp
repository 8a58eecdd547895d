#include "ridge/core/parameter_check.h"

#include "ridge/core/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ridge {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

std::string messageOf(double value, ValueRange range)
{
    try {
        checkParameter("epsilon_px", value, range);
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

TEST(ParameterCheck, NanAndInfinitiesAreOutsideEveryRange)
{
    for (ValueRange r : {ValueRange::any(), ValueRange::positive(), ValueRange::nonNegative(),
                         ValueRange::closed(-1e308, 1e308)}) {
        EXPECT_FALSE(r.contains(kNan));
        EXPECT_FALSE(r.contains(kInf));
        EXPECT_FALSE(r.contains(-kInf));
    }
}

TEST(ParameterCheck, OpenEndsExcludeTheirBound)
{
    EXPECT_FALSE(ValueRange::positive().contains(0.0));
    EXPECT_TRUE(ValueRange::nonNegative().contains(0.0));
    EXPECT_TRUE(ValueRange::openClosed(0, 90).contains(90.0));
    EXPECT_FALSE(ValueRange::openClosed(0, 90).contains(0.0));
    EXPECT_FALSE(ValueRange::closedOpen(0, 360).contains(360.0));
    EXPECT_TRUE(ValueRange::closedOpen(0, 360).contains(0.0));
}

TEST(ParameterCheck, MessagesNameTheParameterTheValueAndTheRangeReadably)
{
    EXPECT_EQ(messageOf(kNan, ValueRange::closed(0.05, 1000)),
              "epsilon_px is nan: must be a number in [0.05, 1000]");
    EXPECT_EQ(messageOf(0, ValueRange::positive()), "epsilon_px is 0: must be a finite number > 0");
    EXPECT_EQ(messageOf(-kInf, ValueRange::any()), "epsilon_px is -inf: must be a finite number");
    EXPECT_EQ(messageOf(1e300, ValueRange::openClosed(0, 90)),
              "epsilon_px is 1e+300: must be a number in (0, 90]");
    EXPECT_EQ(messageOf(2, ValueRange::positive()), "");
}

TEST(ParameterCheck, VectorsReportEveryComponent)
{
    const double camera[3] = {kNan, 0.0, 12.5};
    try {
        checkParameters("camera position", camera, 3, ValueRange::any());
        FAIL() << "accepted a NaN component";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(),
                     "camera position is (nan, 0, 12.5): every component must be a finite number");
    }
    const double fine[3] = {1, 2, 3};
    EXPECT_NO_THROW(checkParameters("camera position", fine, 3, ValueRange::any()));
}

TEST(ParameterCheck, IntegersAreCheckedAgainstTheirRange)
{
    EXPECT_NO_THROW(checkParameter("frames", int64_t{1}, 1, 1000000));
    EXPECT_THROW(checkParameter("frames", int64_t{0}, 1, 1000000), Error);
}

} // namespace
} // namespace ridge
