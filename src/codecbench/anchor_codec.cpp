#include "ridge/codecbench/anchor_codec.h"

namespace ridge::codecbench {

std::vector<std::unique_ptr<AnchorCodec>> makeAnchorCodecs()
{
    std::vector<std::unique_ptr<AnchorCodec>> anchors;
    anchors.push_back(makeLercAnchor());
    anchors.push_back(makeJpegLsAnchor());
    anchors.push_back(makeJpeg2000Anchor());
    anchors.push_back(makeJpegXlAnchor());
    anchors.push_back(makeMedZstdAnchor());
    anchors.push_back(makeZfpAnchor());
    return anchors;
}

} // namespace ridge::codecbench
