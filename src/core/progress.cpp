#include "ridge/core/progress.h"

#include "ridge/core/error.h"

namespace ridge {

void reportProgress(const Progress& progress, double fraction)
{
    if (progress && !progress(fraction))
        throw Cancelled();
}

void reportDone(const Progress& progress)
{
    if (progress)
        (void)progress(1.0);
}

Progress subProgress(const Progress& parent, double begin, double end)
{
    if (!parent)
        return {};
    return [parent, begin, end](double f) { return parent(begin + (end - begin) * f); };
}

} // namespace ridge
