#pragma once
// What every PROJ caller in io shares (internal to ridge_io): owners of PROJ's objects, a
// private silent context, and PROJ's words for an error and a name. PROJ headers stay out of
// public headers; this one is included by io's .cpp files only.
#include "ridge/core/error.h"

#include <proj.h>

#include <memory>
#include <string>

namespace ridge::io::detail {

struct ProjContextDeleter {
    void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct ProjObjectDeleter {
    void operator()(PJ* p) const { proj_destroy(p); }
};
struct ProjListDeleter {
    void operator()(PJ_OBJ_LIST* l) const { proj_list_destroy(l); }
};
using ProjContext = std::unique_ptr<PJ_CONTEXT, ProjContextDeleter>;
using ProjObject = std::unique_ptr<PJ, ProjObjectDeleter>;
using ProjList = std::unique_ptr<PJ_OBJ_LIST, ProjListDeleter>;

// A private context: PROJ objects are not thread-safe, and its errors stay ours. Its own log
// is off: errors come back through the calls and are worded by the caller (PROJ would print
// "proj_create_from_database: crs not found", or a line per point a projection cannot take,
// on stderr besides). Throws ridge::Error, `what` first, when PROJ cannot make one.
inline ProjContext newProjContext(const std::string& what = {})
{
    ProjContext c(proj_context_create());
    if (!c)
        throw Error((what.empty() ? std::string() : what + ": ") +
                    "PROJ context could not be created");
    proj_log_level(c.get(), PJ_LOG_NONE);
    return c;
}

// PROJ's text for error `code` (the context's last error by default).
inline std::string projError(PJ_CONTEXT* context, int code)
{
    const char* text = code ? proj_context_errno_string(context, code) : nullptr;
    return text ? text : "unknown PROJ error";
}
inline std::string projError(PJ_CONTEXT* context)
{
    return projError(context, proj_context_errno(context));
}

// The object's name, `fallback` when it has none (or there is no object).
inline std::string projName(const PJ* object, const char* fallback = "")
{
    const char* name = object ? proj_get_name(object) : nullptr;
    return name ? name : fallback;
}

} // namespace ridge::io::detail
