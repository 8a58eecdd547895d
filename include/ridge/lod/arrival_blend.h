#pragma once
// Arrivals that do not pop. While streaming, a selected patch that is not resident is drawn by
// its finest resident ancestor (ridge/lod/resident_cover.h). When the patch arrives it would
// replace that ancestor's surface at once: a jump of up to Err(A) + Err(P) metres, tens of
// pixels near the camera. Instead the patch fades in: for n frames its heights are
//
//   z = mix(z_P, S, w),   w = 1 − (a + 1) / n   (a: frames since it arrived, 0 .. n − 1)
//
// with S the surface drawn there the frame before, so each frame moves the surface by at most
// |S − z_P| / n. S is the ancestor's surface A (linear on its cell triangles, as its full grid
// draws it) — or, when A was itself still fading in over its own ancestor A', the mix that was
// drawn, mix(z_A, S_A, w_A), whose fade goes on beneath. Arrivals cascade (a parent before its
// children, as progressive codecs need, and every level at once after a teleport), so S is a
// chain of nested fades, each with its own weight:
//
//   S_0 = mix(z_A0, S_1, w_1),  S_1 = mix(z_A1, S_2, w_2), …   (A0 the nearest ancestor)
//
// kept to kMaxDepth ancestors: a longer chain loses the link whose share of the surface is
// least (that much pops). The length n is chosen per arrival from how far the surface may
// move on screen:
//
//   n = clamp(⌈Err_Scr(Err(A_i) + Err(P)), largest over the chain⌉ / px_per_frame, 1, max_frames)
//
// (Err_Scr with the patch's own ρ: an upper bound of the jump in pixels), so a small jump
// ends at once and a large one at most max_frames later. Only arrivals fade: a patch drawn
// because the selection now wants a finer level over an ancestor that was *selected* (an LOD
// change, not a streaming fallback) is the scheme's business (geomorph morphs it).
//
// The fade starts exactly on what was drawn where the ancestors are drawn as their full grids:
// schemes that draw patches coarser (tessellation factors, simplified chunks) draw stand-ins
// at their full grid (standsIn), which the shaders' interpolation reproduces (geomorph's own
// level is its grid; a stand-in morphing towards its parent starts off by that morph).
//
// Plain C++ (no GL): the renderer feeds it each streaming frame's selection and drawn cover,
// and puts the ancestors' slots and weights into the instance records; the shaders mix
// (terrain_common.glsl, arrivalFade).
#include "ridge/lod/patch_quadtree.h"

#include <array>
#include <functional>
#include <optional>
#include <vector>

namespace ridge::lod {

struct ArrivalBlendSettings {
    static constexpr int kMaxFrames = 10000;
    static constexpr ValueRange kPxPerFrameRange = ValueRange::openClosed(0.0, 1000.0);
    // Longest fade, frames; 0: arrivals replace their ancestor at once. 256 (about 4 s at
    // 60 Hz): after a teleport the chain's jumps reach about 100 px on the Sierra archive, so
    // 32 frames moved 2.9 px a frame and 128 frames 0.83 px; 256 keeps under 0.5 px
    // (docs/PERF.md). The fade ends sooner where the jump is smaller.
    int max_frames = 256;
    // How far a fading surface may move on screen in one frame, pixels (bound, not measure).
    double px_per_frame = 0.25;
    // Throws ridge::Error naming the field outside its range.
    void validate() const;
};

// A patch fading in: the surface drawn before it, as a chain of ancestors (see above).
struct ArrivalBlend {
    static constexpr int kMaxDepth = 4;
    struct Link {
        PatchId from;
        float weight = 0.f; // link 0: of S_0 in the patch's surface; link i: of S_i in S_(i−1)
    };
    std::array<Link, kMaxDepth> links{};
    int depth = 0; // links in use, 1 .. kMaxDepth
};

class ArrivalBlends {
  public:
    explicit ArrivalBlends(ArrivalBlendSettings settings = {});

    // One streaming frame. `wanted`: what the selection asked for; `drawn`: what is drawn
    // (the resident cover: wanted patches, and ancestors standing in for missing ones).
    // `resident(p)`: p's surface is on the GPU now. `jump_px(from, to)`: an upper bound of
    // the on-screen jump from from's surface to to's, pixels. Fades started earlier advance
    // a frame; a drawn patch that was not drawn last frame and lies under an ancestor that
    // stood in for it last frame starts one; a link whose ancestor left the GPU ends there.
    void advance(const std::vector<SelectedPatch>& wanted, const std::vector<SelectedPatch>& drawn,
                 const std::function<bool(PatchId)>& resident,
                 const std::function<double(PatchId from, PatchId to)>& jump_px);
    // The fade of drawn patch `p` this frame, if any.
    std::optional<ArrivalBlend> of(PatchId p) const;
    // Whether drawn patch `p` stands in for missing descendants this frame. A scheme that
    // draws patches coarser than their grid draws a stand-in at its full grid, so that what
    // arrives fades from the surface that was drawn.
    bool standsIn(PatchId p) const;
    size_t fading() const { return fades_.size(); }
    // Forgets everything (a teleport, a new archive): the next frame starts no fade.
    void reset();

  private:
    struct Link {
        PatchId from;
        int age = 0;    // frames since this link's fade began
        int frames = 0; // its n
        float weight() const;
    };
    struct Fade {
        PatchId patch;
        std::vector<Link> links; // 1 .. kMaxDepth
    };
    struct Drawn {
        PatchId id;
        bool stood_in = false; // drawn for missing descendants, not wanted itself
    };
    // Drops links beyond kMaxDepth, each time the one whose surface has the least share.
    static void shorten(std::vector<Link>& links);

    ArrivalBlendSettings settings_;
    std::vector<Fade> fades_; // sorted by patch
    std::vector<Drawn> last_; // last frame's drawn cover, sorted by id
    bool has_last_ = false;
};

} // namespace ridge::lod
