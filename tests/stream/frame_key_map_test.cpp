#include "ridge/stream/frame_key_map.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

using namespace ridge::stream;

TEST(FrameKeyMap, MatchesAMapAcrossClearsAndGrowth)
{
    FrameKeyMap<int> map;
    std::mt19937 rng(5);
    for (int round = 0; round < 20; ++round) {
        map.clear();
        std::map<int64_t, int> expected;
        const int n = 1 + int(rng() % 3000);
        for (int k = 0; k < n; ++k) {
            const int64_t key = int64_t(rng() % 5000) * (round % 2 ? 1 : 1024);
            EXPECT_EQ(map.insert(key, k), expected.emplace(key, k).second);
        }
        EXPECT_EQ(map.size(), expected.size());
        for (int64_t key = 0; key < 5000; ++key) {
            const int64_t probe = key * (round % 2 ? 1 : 1024);
            const int* v = map.find(probe);
            auto it = expected.find(probe);
            ASSERT_EQ(v != nullptr, it != expected.end());
            if (v) {
                EXPECT_EQ(*v, it->second);
            }
        }
    }
}
