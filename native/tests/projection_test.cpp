#include <gtest/gtest.h>

#include <cmath>

#include "ggg/error.hpp"
#include "ggg/osm/projection.hpp"

using namespace ggg;

namespace {
// Meridian arc length on WGS84 from the equator to latitude phi (Helmert's series; its error
// is far below a millimetre), an independent reference for north-south distances.
double meridian_arc(double lat_deg) {
    const double a = 6378137.0, f = 1 / 298.257223563;
    const double n = f / (2 - f);
    const double phi = lat_deg * M_PI / 180;
    const double A = a / (1 + n) * (1 + n * n / 4 + n * n * n * n / 64);
    return A * (phi - (3 * n / 2 - 9 * n * n * n / 16) * std::sin(2 * phi) + (15 * n * n / 16 - 15 * n * n * n * n / 32) * std::sin(4 * phi) -
                (35 * n * n * n / 48) * std::sin(6 * phi) + (315 * n * n * n * n / 512) * std::sin(8 * phi));
}
} // namespace

TEST(Projection, OriginMapsToZero) {
    LocalProjection p({48.8637785, 2.3661084});
    const Vec2 xy = p.forward(2.3661084, 48.8637785);
    EXPECT_NEAR(xy.x(), 0.0, 1e-9);
    EXPECT_NEAR(xy.y(), 0.0, 1e-9);
}

TEST(Projection, NorthSouthDistanceMatchesMeridianArc) {
    for (double lat : {-33.9, 0.5, 41.39, 60.17}) {
        LocalProjection p({lat, 10.0});
        const Vec2 a = p.forward(10.0, lat - 0.02);
        const Vec2 b = p.forward(10.0, lat + 0.02);
        const double expected = meridian_arc(lat + 0.02) - meridian_arc(lat - 0.02);
        EXPECT_NEAR((b - a).norm(), expected, 1e-3) << "latitude " << lat; // ~4.4 km, within a millimetre
    }
}

TEST(Projection, CityScaleDistancesAgreeWithGreatCircle) {
    // 20 km across a city: the sphere differs from the ellipsoid by < 0.5 %, the projection
    // must stay within that of the great-circle distance.
    LocalProjection p({41.19, -8.568});
    const double lat1 = 41.10, lon1 = -8.65, lat2 = 41.28, lon2 = -8.48;
    const double projected = (p.forward(lon2, lat2) - p.forward(lon1, lat1)).norm();
    const double great_circle = haversine_m(lat1, lon1, lat2, lon2);
    EXPECT_NEAR(projected / great_circle, 1.0, 5e-3);
    EXPECT_GT(great_circle, 20000.0);
}

TEST(Projection, InverseRoundTrip) {
    LocalProjection p({55.81, 37.61});
    for (double dx : {-20000.0, 0.0, 13000.0}) {
        for (double dy : {-15000.0, 500.0, 20000.0}) {
            const Vec2 ll = p.inverse(Vec2{dx, dy});
            const Vec2 back = p.forward(ll.x(), ll.y());
            EXPECT_NEAR(back.x(), dx, 1e-6);
            EXPECT_NEAR(back.y(), dy, 1e-6);
        }
    }
}

TEST(Projection, RejectsOriginOutOfRange) {
    EXPECT_THROW(LocalProjection({95.0, 0.0}), InputError);
    EXPECT_THROW(LocalProjection({0.0, NAN}), InputError);
}
