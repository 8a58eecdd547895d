#pragma once
// The terrain as its level-0 patch shows it: ground heights, clip planes and a camera that
// frames the whole terrain, cheap enough to call per frame and GL-free, for whoever places
// cameras (TerrainRenderer's groundHeight / clipPlanesFor / defaultCamera, the benchmark's
// camera paths, headless renders, the viewer's ground clamp).
#include "ridge/core/height_grid.h"
#include "ridge/lod/camera.h"
#include "ridge/lod/terrain_frame.h"

#include <cstdint>
#include <vector>

namespace ridge::lod {

class CoarseTerrain {
  public:
    // `root_codes`: the decoded level-0 patch, n×n codes row-major (n = the frame's patch
    // size); `root_box`: that patch's box in the terrain frame (the whole terrain's heights);
    // `quantization`: metres = offset + scale·code. Throws ridge::Error when the codes are not
    // n×n or the frame's spacings are not finite and positive.
    CoarseTerrain(TerrainFrame frame, Box root_box, std::vector<uint16_t> root_codes,
                  HeightQuantization quantization);
    // The same with the root's box made by the frame (TerrainFrame::patchBox) from the whole
    // terrain's height range: what a globe frame needs, whose boxes are not a height range.
    CoarseTerrain(TerrainFrame frame, double min_height, double max_height,
                  std::vector<uint16_t> root_codes, HeightQuantization quantization);

    const TerrainFrame& frame() const { return frame_; }
    const Box& box() const { return box_; }

    // The same terrain with every height multiplied by `exaggeration` (render-time vertical
    // exaggeration, RenderSettings::exaggeration): its ground, clip planes and default camera
    // are those of the drawn, exaggerated surface. Throws ridge::Error outside
    // SelectionSettings::kExaggerationRange.
    CoarseTerrain exaggerated(double exaggeration) const;

    // Terrain-frame height (metres) of the level-0 patch's surface under (x, y), bilinear
    // between its samples. Points off the terrain take the nearest border point, however far
    // (huge finite coordinates clamp); the read never leaves the patch. Throws ridge::Error
    // when x or y is NaN or infinite.
    double groundHeight(double x, double y) const;
    // The same at finest-grid (column, row), and under a world point of the frame (on a globe
    // along the ellipsoid's normal through it). Throws ridge::Error for non-finite input.
    double groundAt(double column, double row) const;
    double groundUnder(glm::dvec3 world) const;

    // near/far planes (metres) that suit a camera at `position`: near a quarter of the height
    // above the ground or of the distance to the terrain's box, in [0.05, 1e5] m (it shrinks
    // as the camera descends); far 1.5 times the farthest box corner. Throws ridge::Error for a
    // position outside kCameraCoordinateRange (NaN and infinities included).
    void clipPlanesFor(glm::dvec3 position, double& near_m, double& far_m) const;

    // An oblique view from the south-south-west, 35° above the horizon, as close as lets
    // every surface sample (surfaceSamples) project inside the picture with a 4% margin, the
    // surface centred: the terrain fills the frame on its tighter axis. Directions are local
    // to the terrain's centre (east, north, up); a globe frame spanning more than 60° is seen
    // from straight above its centre, north up, the whole of it in the picture. Throws
    // ridge::Error for a viewport or field of view lod::Camera refuses.
    Camera defaultCamera(Viewport viewport, double fov_y_degrees = 60.0) const;

    // The level-0 patch's surface over the terrain's extent, terrain-frame world points: its
    // samples inside the extent, and the extent's last column and row (bilinear there).
    std::vector<glm::dvec3> surfaceSamples() const;

  private:
    TerrainFrame frame_;
    Box box_;
    std::vector<uint16_t> codes_;
    HeightQuantization quantization_;
    int n_ = 0;                                  // samples per patch side
    double min_height_ = 0.0, max_height_ = 0.0; // the root's range (the box's on a plane)
};

} // namespace ridge::lod
