#include "ridge/lod/arrival_blend.h"

#include "ridge/core/parameter_check.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace ridge::lod {

namespace {

bool idLess(PatchId a, PatchId b)
{
    return std::tie(a.level, a.x, a.y) < std::tie(b.level, b.x, b.y);
}

template <class Entry, class Key>
const Entry* findById(const std::vector<Entry>& sorted, PatchId id, Key key)
{
    const auto it = std::lower_bound(sorted.begin(), sorted.end(), id,
                                     [&](const Entry& e, PatchId p) { return idLess(key(e), p); });
    return it != sorted.end() && key(*it) == id ? &*it : nullptr;
}

} // namespace

void ArrivalBlendSettings::validate() const
{
    checkParameter("arrival blend frames", int64_t{max_frames}, 0, kMaxFrames);
    checkParameter("arrival blend pixels per frame", px_per_frame, kPxPerFrameRange);
}

float ArrivalBlends::Link::weight() const
{
    return frames > 0 ? std::max(0.f, float(1.0 - double(age + 1) / double(frames))) : 0.f;
}

ArrivalBlends::ArrivalBlends(ArrivalBlendSettings settings) : settings_(settings)
{
    settings_.validate();
}

void ArrivalBlends::shorten(std::vector<Link>& links)
{
    while (links.size() > size_t(ArrivalBlend::kMaxDepth)) {
        // Link i's own surface weighs w_0 ⋯ w_i (1 − w_(i+1)) in what is drawn (w past the
        // end: 0). Without it, S_i is S_(i+1): the link takes its successor's ancestor and
        // keeps its own weight (the last link simply goes).
        size_t least = 0;
        double least_share = 2.0, through = 1.0;
        for (size_t i = 0; i < links.size(); ++i) {
            through *= links[i].weight();
            const double next = i + 1 < links.size() ? links[i + 1].weight() : 0.0;
            if (const double share = through * (1.0 - next); share < least_share) {
                least_share = share;
                least = i;
            }
        }
        if (least + 1 < links.size()) {
            links[least].from = links[least + 1].from;
            links.erase(links.begin() + std::ptrdiff_t(least + 1));
        } else {
            links.pop_back();
        }
    }
}

void ArrivalBlends::advance(const std::vector<SelectedPatch>& wanted,
                            const std::vector<SelectedPatch>& drawn,
                            const std::function<bool(PatchId)>& resident,
                            const std::function<double(PatchId, PatchId)>& jump_px)
{
    auto fadeKey = [](const Fade& f) { return f.patch; };
    auto drawnKey = [](const Drawn& d) { return d.id; };
    std::vector<Fade> next;
    for (const SelectedPatch& s : drawn) {
        const PatchId p = s.id;
        if (const Fade* f = findById(fades_, p, fadeKey)) {
            // Every link a frame on; the chain ends at the first link whose weight is spent or
            // whose ancestor is no longer there to fade from.
            Fade g{p, {}};
            for (Link l : f->links) {
                ++l.age;
                if (l.weight() <= 0.f || !resident(l.from))
                    break;
                g.links.push_back(l);
            }
            if (!g.links.empty())
                next.push_back(std::move(g));
            continue;
        }
        if (!has_last_ || settings_.max_frames == 0 || findById(last_, p, drawnKey))
            continue; // drawn before: no arrival
        // The drawn ancestor it appears under, if that one stood in for missing patches.
        for (PatchId a = p; a.level > 0;) {
            a = a.parent();
            const Drawn* d = findById(last_, a, drawnKey);
            if (!d)
                continue;
            if (!d->stood_in || !resident(a))
                break;
            Fade fade{p, {Link{a, 0, 0}}};
            double jump = jump_px(a, p);
            // The stand-in's own fade goes on beneath this one, from where it was drawn (it
            // advances from the next frame on): the patch starts on the surface drawn.
            if (const Fade* under = findById(fades_, a, fadeKey))
                for (const Link& l : under->links) {
                    if (!resident(l.from))
                        break;
                    fade.links.push_back(l);
                    jump = std::max(jump, jump_px(l.from, p));
                }
            const double steps = std::ceil(jump / settings_.px_per_frame);
            fade.links[0].frames = std::isfinite(steps)
                                       ? int(std::clamp(steps, 1.0, double(settings_.max_frames)))
                                       : settings_.max_frames;
            if (fade.links[0].weight() > 0.f) {
                shorten(fade.links);
                next.push_back(std::move(fade));
            }
            break;
        }
    }
    std::sort(next.begin(), next.end(),
              [](const Fade& a, const Fade& b) { return idLess(a.patch, b.patch); });
    fades_ = std::move(next);

    // This frame's cover, each entry marked when it stands in (not wanted itself).
    std::vector<PatchId> wanted_ids;
    wanted_ids.reserve(wanted.size());
    for (const SelectedPatch& s : wanted)
        wanted_ids.push_back(s.id);
    std::sort(wanted_ids.begin(), wanted_ids.end(), idLess);
    last_.clear();
    for (const SelectedPatch& s : drawn)
        last_.push_back(
            {s.id, !std::binary_search(wanted_ids.begin(), wanted_ids.end(), s.id, idLess)});
    std::sort(last_.begin(), last_.end(),
              [](const Drawn& a, const Drawn& b) { return idLess(a.id, b.id); });
    has_last_ = true;
}

std::optional<ArrivalBlend> ArrivalBlends::of(PatchId p) const
{
    const Fade* f = findById(fades_, p, [](const Fade& e) { return e.patch; });
    if (!f)
        return std::nullopt;
    ArrivalBlend b;
    for (const Link& l : f->links)
        b.links[size_t(b.depth++)] = {l.from, l.weight()};
    return b;
}

bool ArrivalBlends::standsIn(PatchId p) const
{
    const Drawn* d = findById(last_, p, [](const Drawn& e) { return e.id; });
    return d && d->stood_in;
}

void ArrivalBlends::reset()
{
    fades_.clear();
    last_.clear();
    has_last_ = false;
}

} // namespace ridge::lod
