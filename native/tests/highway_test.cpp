#include <gtest/gtest.h>

#include "ggg/error.hpp"
#include "ggg/graph/road_class.hpp"
#include "ggg/osm/highway_filter.hpp"

using namespace ggg;

TEST(HighwayFilter, DrivableKeepsCarRoadsAndLinks) {
    const auto f = HighwayFilter::drivable();
    for (const char* v : {"motorway", "primary_link", "residential", "living_street", "unclassified"}) EXPECT_TRUE(f.accepts(v)) << v;
    for (const char* v : {"footway", "service", "track", "path", "construction", ""}) EXPECT_FALSE(f.accepts(v)) << v;
}

TEST(HighwayFilter, AllKeepsAnyValue) {
    const auto f = HighwayFilter::parse("all");
    EXPECT_TRUE(f.accepts("footway"));
    EXPECT_TRUE(f.accepts("proposed"));
    EXPECT_FALSE(f.accepts(""));
}

TEST(HighwayFilter, ExplicitList) {
    const auto f = HighwayFilter::parse("primary, secondary");
    EXPECT_TRUE(f.accepts("primary"));
    EXPECT_TRUE(f.accepts("secondary"));
    EXPECT_FALSE(f.accepts("residential"));
    EXPECT_THROW(HighwayFilter::parse("primary;secondary"), UsageError);
    EXPECT_THROW(HighwayFilter::parse("primary,primay"), UsageError); // a typo is not silently nothing
    const auto other = HighwayFilter::parse("residential,other");
    EXPECT_TRUE(other.accepts("construction"));
    EXPECT_TRUE(other.accepts("residential"));
    EXPECT_FALSE(other.accepts("primary"));
    EXPECT_THROW(HighwayFilter::parse(" , "), UsageError);
}

TEST(HighwayClass, NamesRoundTripAndRanksOrderImportance) {
    for (int c = 0; c < highway_class_count; ++c) {
        const auto cls = static_cast<HighwayClass>(c);
        EXPECT_EQ(highway_from_name(highway_name(cls)), cls);
        EXPECT_GT(highway_default_width(cls), 0.0);
    }
    EXPECT_EQ(highway_from_name("proposed"), HighwayClass::other);
    EXPECT_LT(highway_rank(HighwayClass::motorway), highway_rank(HighwayClass::primary));
    EXPECT_LT(highway_rank(HighwayClass::primary), highway_rank(HighwayClass::residential));
    EXPECT_LT(highway_rank(HighwayClass::residential), highway_rank(HighwayClass::footway));
}
