#include "MethodUtil.h"

#include "../passes/VolumeStates.h"

namespace gpu {

void clearStencil(const Targets& t) {
    applyState(kVolumeState); // stencil write mask on for the clear
    const int zero = 0;
    glClearNamedFramebufferiv(t.visibilityFbo.id(), GL_STENCIL, 0, &zero);
}

std::vector<CasterRange> casterRuns(const CasterSet& casters,
                                    std::span<const std::uint32_t> subset) {
    std::vector<CasterRange> runs;
    std::uint32_t previous = 0;
    for (std::size_t k = 0; k < subset.size(); ++k) {
        const CasterRange& r = casters.range(subset[k]);
        if (k > 0 && subset[k] == previous + 1) {
            CasterRange& last = runs.back();
            last.triangleCount += r.triangleCount;
            last.edgeCount += r.edgeCount;
            last.groupCount += r.groupCount;
        } else {
            runs.push_back(r);
        }
        previous = subset[k];
    }
    return runs;
}

} // namespace gpu
