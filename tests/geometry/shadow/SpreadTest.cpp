// The work groups' spread order (shaders/shared/Spread.h, the shaders' source compiled as C++):
// a bijection of the items for every count, and, dealt out in contiguous blocks as llvmpipe
// deals a dispatch's groups to its threads, every block's items spread over the whole list: a
// costly stretch of it (a penumbra's tiles, one caster's slots) falls to every thread alike.
#include <glm/glm.hpp>
#include <shared/Spread.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using shader::spreadIndex;
using shader::spreadStride;

TEST(Spread, EveryItemTakenOnce) {
    for (unsigned n = 1; n <= 3000; ++n) {
        const unsigned k = spreadStride(n);
        ASSERT_EQ(shader::spreadGcd(k, n), 1u) << n;
        std::vector<int> taken(n, 0);
        for (unsigned g = 0; g < n; ++g) {
            const unsigned item = spreadIndex(g, n, k);
            ASSERT_LT(item, n) << n << " " << g;
            ++taken[item];
        }
        ASSERT_TRUE(std::all_of(taken.begin(), taken.end(), [](int t) { return t == 1; })) << n;
    }
    // Exact where g k passes 32 bits: 4K's 129 600 tiles, and more.
    for (const unsigned n : {129600u, 1u << 20, (1u << 25) + 7u}) {
        const unsigned k = spreadStride(n);
        for (const unsigned g : {0u, 1u, n / 2, n - 2, n - 1})
            EXPECT_EQ(spreadIndex(g, n, k),
                      static_cast<unsigned>((static_cast<unsigned long long>(g) * k) % n))
                << n << " " << g;
    }
}

// A costly stretch: the items of one contiguous tenth of the list. Dealt to T threads in
// contiguous blocks of groups (llvmpipe), each thread takes its fair share of the stretch (its
// share of the groups times the stretch's length) to within 2 items and 1 % (measured: at most
// 1.44 items where the fair share is 26, 2 of 4 320); in list order one thread would take all
// of it (409 items of 4 096 where the fair share is 26 to 205).
TEST(Spread, ContiguousBlocksShareACostlyStretch) {
    double worst = 0.0;
    for (const unsigned n : {64u, 691u, 1006u, 4096u, 129600u})
        for (const unsigned threads : {2u, 3u, 4u, 8u, 16u}) {
            const unsigned k = spreadStride(n);
            const unsigned first = n / 3, last = first + n / 10; // the stretch [first, last)
            const unsigned block = (n + threads - 1) / threads;
            if (double(last - first) / threads < 4.0) continue; // too few to share
            for (unsigned t = 0; t < threads; ++t) {
                unsigned inStretch = 0, groups = 0;
                for (unsigned g = t * block; g < std::min(n, (t + 1) * block); ++g, ++groups) {
                    const unsigned item = spreadIndex(g, n, k);
                    inStretch += item >= first && item < last ? 1 : 0;
                }
                const double fair = double(groups) * double(last - first) / double(n);
                const double off = std::abs(double(inStretch) - fair);
                worst = std::max(worst, off / (2.0 + 0.01 * fair));
                EXPECT_LE(off, 2.0 + 0.01 * fair) << "n " << n << ", " << threads << " threads, block " << t;
            }
        }
    std::printf("  the worst block's items of the stretch off its fair share: %.2f of the bound\n",
                worst);
}

} // namespace
