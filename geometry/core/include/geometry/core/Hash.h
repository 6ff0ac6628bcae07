// Internal to the geometry libraries (not part of their API): a 64-bit integer mixer shared by the welding grid (Topology.cpp) and
// the deterministic per-vertex noise (Primitives.cpp).
#pragma once

#include <cstdint>

namespace geometry {

// The splitmix64 finaliser: a cheap bijection whose output bits all depend on every input bit.
// Enough to scatter regular keys (grid cells) and to decorrelate per-vertex noise; no
// statistical quality beyond that is claimed.
inline std::uint64_t mix64(std::uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ull;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebull;
    x ^= x >> 31;
    return x;
}

} // namespace geometry
