// The plane geometry that synthesis shares: what makes a region usable.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "ggg/graph/plane_geometry.hpp"

using namespace ggg;

namespace {

Vec2 unit_at(double angle) { return {std::cos(angle), std::sin(angle)}; }

} // namespace

TEST(RegionOutline, SidesThatCrossOrTouchAreFound) {
    EXPECT_FALSE(first_self_crossing({{0, 0}, {100, 0}, {100, 100}, {0, 100}}));
    EXPECT_FALSE(first_self_crossing({{0, 0}, {100, 0}, {100, 100}})); // a triangle
    EXPECT_EQ(first_self_crossing({{0, 0}, {100, 100}, {100, 0}, {0, 100}}), (std::pair<std::size_t, std::size_t>{0, 2}));
    // A corner on another side (the outline touches itself) counts as crossing.
    EXPECT_EQ(first_self_crossing({{0, 0}, {100, 0}, {100, 100}, {50, 0}, {0, 100}}), (std::pair<std::size_t, std::size_t>{0, 2}));
    // A five-pointed star drawn in one stroke.
    std::vector<Vec2> star;
    for (int k = 0; k < 5; ++k) star.push_back(100.0 * unit_at(k * 4 * M_PI / 5));
    EXPECT_TRUE(first_self_crossing(star));
    // A comb of 2,000 corners whose teeth come close but never meet, and the same comb with
    // one tooth bent over its neighbour.
    std::vector<Vec2> comb;
    for (int k = 0; k < 500; ++k) {
        comb.push_back({10.0 * k, 0});
        comb.push_back({10.0 * k, 100});
        comb.push_back({10.0 * k + 9, 100});
        comb.push_back({10.0 * k + 9, 0});
    }
    comb.push_back({5000, -50});
    comb.push_back({0, -50});
    EXPECT_FALSE(first_self_crossing(comb));
    comb[4 * 250 + 2] = {10.0 * 251 + 5, 100};
    const auto bent = first_self_crossing(comb);
    ASSERT_TRUE(bent);
    EXPECT_EQ(bent->first, 4u * 250 + 1);
}
