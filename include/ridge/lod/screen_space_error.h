#pragma once
// Screen-space error of a patch ("Coarse Level of Detail Selection", Yusov & Shevtsov 2011, §5):
//
//   Err_Scr(P) = γ · Err(P) / ρ(c, V),   γ = ½ · max(R_h · ctg(φ_h / 2), R_v · ctg(φ_v / 2))
//
// with Err(P) the patch's guaranteed geometric error in metres, ρ(c, V) the distance from the
// camera position c to the closest point of the patch's bounding box V. The formula is the
// standard conservative bound for a vertical error seen face-on at the screen centre.
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"

namespace ridge::lod {

// γ of `camera`, pixels per (metre of error per metre of distance).
double screenSpaceErrorFactor(const Camera& camera);

// ρ(c, V): 0 when c is inside the box.
double distanceToBox(glm::dvec3 c, const Box& box);

// The paper's ρ assumes the error is seen face-on at the screen centre. Off-axis, a vertical
// error e at distance r and view depth w projects to at most γ·e·r/w² pixels (its image is
// γ·e/w times the sine of its angle to the view ray, over the cosine of the ray's angle θ to
// the axis: up to 1/cos θ more than γ·e/w when looking steeply down). Every visible point of
// the box has r >= ρ, w >= r·cos θ_max (θ_max: view axis to frustum corner) and w >= the
// box's nearest depth w_n, so r/w² <= 1/(cos θ_max · max(ρ·cos θ_max, w_n)): this bound in
// place of ρ keeps Err_Scr an upper bound anywhere on screen. It refines at most
// 1/cos² θ_max (2.4 for 60° at 16:9) further than ρ; measured, it barely moves the triangle
// count (the finest patches' blocks dominate it).
// `side_on` false leaves out the extra cos θ_max for errors seen side-on (the bound before
// issue 12: cheaper, measured up to 1.09 ε; kept for comparisons with earlier figures).
double visibleDepthBound(const Camera& camera, const Box& box, double rho, bool side_on = true);

// Err_Scr in pixels; +inf when the camera is inside the box and err > 0.
double screen_space_error(double gamma, double err_metres, double rho);
// The texture-detail criterion beside Err_Scr: the projected sample spacing of a patch's level,
// γ · spacing / ρ pixels, with the same conservative ρ (a horizontal length seen face-on
// projects at most as a vertical one does). A patch whose samples are further apart than a
// pixel target on screen shows its height and normal maps magnified — a blur however small
// Err_Scr is (a whole globe is one patch at ε = 2 px). +inf inside the box.
double projectedSampleSpacing(double gamma, double spacing_metres, double rho);

} // namespace ridge::lod
