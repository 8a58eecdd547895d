#pragma once
// Base incremental (the fractal-rings paper, §8): a patch of a refinable codec (one decoded by
// steps, the fractal codec's iterations of T) is decoded with few steps when far and refined in
// place as the viewer approaches. The paper picks the count from the patch's level and
// distance; ridge picks the fewest steps whose added error keeps the patch within the
// selection's ε on screen, so the end-to-end bound still holds for what is drawn:
//     Err_Scr(P) + stepBound(k) · (Err_Scr(P) / Err(P)) ≤ ε
// (Err_Scr is linear in the error at a given distance: the second term is stepBound(k) in
// metres projected as Err(P) is). GL-free policy; the renderer executes it.
#include "ridge/codec/height_codec.h"

namespace ridge::stream {

// The steps to apply to a patch whose full decode has Err(P) = `err_metres`, seen with
// Err_Scr(P) = `screen_error_px` against ε = `epsilon_px`; `height_scale`: metres per code.
// The full count when nothing less fits, when the view gives no distance (Err or Err_Scr not
// positive and finite) or when the payload stores no bound for partial decodes.
int stepsForView(const RefinablePayload& payload, double height_scale, double err_metres,
                 double screen_error_px, double epsilon_px);

} // namespace ridge::stream
