#include "ridge/core/progress.h"

#include "ridge/core/error.h"

namespace ridge {

void reportProgress(const Progress& progress, double fraction)
{
    if (progress && !progress(fraction))
        throw Cancelled();
}

Progress subProgress(const Progress& parent, double begin, double end)
{
    if (!parent)
        return {};
    return [parent, begin, end](double f) { return parent(begin + (end - begin) * f); };
}

} // namespace ridge
