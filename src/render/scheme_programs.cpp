#include "scheme_programs.h"

namespace ridge::render {

std::array<const gpu::ShaderProgram*, 2> SchemePrograms::get(bool capture)
{
    const int c = capture ? 1 : 0;
    if (!compiled_[c]) {
        const std::vector<std::string> varyings =
            capture ? std::vector<std::string>{"Capture.tf_position", "Capture.tf_instance",
                                               "Capture.tf_skirt"}
                    : std::vector<std::string>{};
        for (int clip = 0; clip < 2; ++clip) {
            std::vector<gpu::ShaderStage> stages = surface_;
            if (clip)
                stages.push_back({GL_GEOMETRY_SHADER, "terrain_clip.geom"});
            if (!capture)
                stages.push_back({GL_FRAGMENT_SHADER, fragment_});
            programs_[c][clip] = gpu::ShaderProgram(stages, varyings);
        }
        compiled_[c] = true;
    }
    return {&programs_[c][0], &programs_[c][1]};
}

} // namespace ridge::render
