#include "ridge/codecbench/anchor_codec.h"

namespace ridge::codecbench {

std::vector<std::unique_ptr<AnchorCodec>> makeAnchorCodecs()
{
    std::vector<std::unique_ptr<AnchorCodec>> anchors;
    anchors.push_back(makeLercAnchor());
    anchors.push_back(makeJpegLsAnchor());
    anchors.push_back(makeJpeg2000Anchor());
    // Both efforts: 7 is what cjxl users get, 9 the strongest lossless JPEG XL there is here
    // (the target ratio is measured against the best anchor).
    anchors.push_back(makeJpegXlAnchor(7));
    anchors.push_back(makeJpegXlAnchor(9));
    // JPEG XL's own progressive mode: what a coarse-to-fine stream costs the strongest anchor,
    // beside ridge's pyramid.
    anchors.push_back(makeJpegXlAnchor(9, /*progressive=*/true));
    anchors.push_back(makeMedZstdAnchor());
    anchors.push_back(makeZfpAnchor());
    return anchors;
}

} // namespace ridge::codecbench
