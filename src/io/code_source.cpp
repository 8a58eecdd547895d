#include "code_source.h"

namespace ridge::io::detail {

int32_t CodeSource::seaLevelCode() const
{
    if (!sea_level_)
        return -1;
    // metres = offset + scale · code is increasing in the code (scale > 0): the largest code
    // at or below the sea level, settled exactly on the same formula the rest of ridge uses.
    const double guess = std::floor((*sea_level_ - quantization_.offset) / quantization_.scale);
    int64_t code = static_cast<int64_t>(std::clamp(guess, -1.0, 65535.0));
    while (code < 65535 && quantization_.toMetres(double(code + 1)) <= *sea_level_)
        ++code;
    while (code >= 0 && quantization_.toMetres(double(code)) > *sea_level_)
        --code;
    return static_cast<int32_t>(code);
}

} // namespace ridge::io::detail
