// Small helpers shared by the methods.
#pragma once

#include "../CasterSet.h"
#include "../Targets.h"

#include <cstdint>
#include <span>
#include <vector>

namespace gpu {

// Zeroes the stencil counts (with the write mask a volume pass would leave on).
void clearStencil(const Targets& t);

// The frame ranges of `subset` (ascending caster indices), adjacent casters merged into one
// range each so that the usual case, every caster, is one draw per volume part.
std::vector<CasterRange> casterRuns(const CasterSet& casters,
                                    std::span<const std::uint32_t> subset);

} // namespace gpu
