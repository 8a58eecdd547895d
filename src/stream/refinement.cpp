#include "ridge/stream/refinement.h"

#include <cmath>

namespace ridge::stream {

int stepsForView(const RefinablePayload& payload, double height_scale, double err_metres,
                 double screen_error_px, double epsilon_px)
{
    const int full = payload.fullSteps();
    if (!(err_metres > 0 && std::isfinite(err_metres) && screen_error_px > 0 &&
          std::isfinite(screen_error_px) && epsilon_px > 0 && std::isfinite(epsilon_px)))
        return full;
    const double px_per_metre = screen_error_px / err_metres;
    const double slack_px = epsilon_px - screen_error_px;
    // stepBound need not fall with k (an iterate may overshoot): the first k that fits.
    for (int k = 0; k < full; ++k)
        if (payload.stepBound(k) * height_scale * px_per_metre <= slack_px)
            return k;
    return full;
}

} // namespace ridge::stream
