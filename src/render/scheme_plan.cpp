#include "scheme_plan.h"

#include "terrain_scheme.h"

#include "ridge/core/error.h"

#include <algorithm>

namespace ridge::render {

SchemePlan planSchemes(const archive::ArchiveReader& reader, const lod::TerrainFrame& frame,
                       const RendererOptions& options)
{
    SchemePlan out;
    auto add = [&](const SchemeInfo& info, SchemeOptions own, const SchemeNeeds& needs) {
        out.infos.push_back(&info);
        out.names.push_back(info.name);
        out.own.push_back(std::move(own));
        out.slot_bytes += needs.slot_bytes;
        out.fixed_bytes += needs.fixed_bytes;
        out.codes_on_cpu = out.codes_on_cpu || needs.codes_on_cpu;
        out.product.push_back(needs.preparation ? int(out.preparations.size()) : -1);
        out.eager.push_back(needs.slot_bytes > 0.0 || needs.preparation);
        if (needs.preparation)
            out.preparations.push_back(needs.preparation);
    };
    if (options.schemes.empty()) {
        // Schemes by default: those that can draw this archive in the frame it gets.
        const bool wrapping_globe = frame.onEllipsoid() && frame.geodetic().wrap_columns > 0;
        for (const SchemeInfo& info : schemeRegistry()) {
            if (wrapping_globe && !info.promises.wrapping_globe)
                continue; // a scheme that cannot wrap with the globe
            SchemeOptions own = parseSchemeSpec(info.name);
            SchemeNeeds needs;
            try {
                needs = info.needs(reader, frame, options, own);
            } catch (const Error&) {
                continue; // a scheme that cannot draw this archive (rings: patches too small)
            }
            // Nor one whose fixed memory (clipmaps' level windows) would take more than a
            // quarter of the texture budget from the slots every scheme draws from.
            const double budget = options.vram_budget_mb * 1024.0 * 1024.0;
            if (!needs.codes_on_cpu && needs.fixed_bytes <= 0.25 * budget)
                add(info, std::move(own), needs);
        }
    } else {
        for (const std::string& spec : options.schemes) { // validate(): one spec per scheme
            SchemeOptions own = parseSchemeSpec(spec);
            const SchemeInfo& info = schemeNamed(own.scheme());
            const SchemeNeeds needs = info.needs(reader, frame, options, own);
            add(info, std::move(own), needs);
        }
    }
    return out;
}

Schemes::Schemes(const SchemePlan& plan, const SchemeResources& shared)
    : plan_(plan), shared_(std::make_unique<const SchemeResources>(shared)),
      schemes_(plan.infos.size())
{
    for (size_t k = 0; k < plan_.infos.size(); ++k)
        if (plan_.eager[k])
            get(plan_.names[k]);
}

Schemes::~Schemes() = default;

TerrainScheme& Schemes::get(const std::string& name)
{
    const auto found = std::find(plan_.names.begin(), plan_.names.end(), name);
    if (found == plan_.names.end()) {
        std::string built;
        for (const std::string& n : plan_.names)
            built += (built.empty() ? "" : ", ") + n;
        throw Error(shared_->reader.path() + ": LOD scheme '" + name +
                    "' is not one this renderer was built for (RendererOptions::schemes: " + built +
                    ")");
    }
    const size_t k = size_t(found - plan_.names.begin());
    if (!schemes_[k]) {
        const SchemeResources& s = *shared_;
        schemes_[k] = plan_.infos[k]->make(SchemeResources{s.reader, s.quadtree, s.options,
                                                           plan_.own[k], s.textures, s.residency,
                                                           s.slots, plan_.product[k]});
    }
    return *schemes_[k];
}

size_t Schemes::upload(const stream::DecodedPatch& patch, int slot)
{
    size_t bytes = 0;
    for (const auto& scheme : schemes_)
        if (scheme)
            bytes += scheme->upload(patch, slot);
    return bytes;
}

size_t Schemes::plannedUploadBytes(const stream::DecodedPatch& patch) const
{
    size_t bytes = 0;
    for (const auto& scheme : schemes_)
        if (scheme)
            bytes += scheme->plannedUploadBytes(patch);
    return bytes;
}

} // namespace ridge::render
