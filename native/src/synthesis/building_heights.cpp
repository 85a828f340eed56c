// The heights and tints of the city layout's buildings (city_stages.hpp).
#include "city_stages.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "ggg/random.hpp"

namespace ggg::city_detail {

void building_heights(const GeometricGraph& g, const CityLayoutOptions& o, CityLayout& out) {
    const std::size_t count = out.buildings.size();
    out.building_height_m.resize(count);
    out.building_tint.resize(count);
    if (count == 0) return;
    std::vector<double> xs, ys;
    for (const Vec2& p : g.positions) {
        xs.push_back(p.x());
        ys.push_back(p.y());
    }
    auto middle = [](std::vector<double>& v) {
        std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    const auto [x_low, x_high] = std::minmax_element(xs.begin(), xs.end());
    const auto [y_low, y_high] = std::minmax_element(ys.begin(), ys.end());
    const double radius = std::max(1.0, 0.5 * std::hypot(*x_high - *x_low, *y_high - *y_low));
    const Vec2 centre(middle(xs), middle(ys));
    Random random{o.seed * 0x2545F4914F6CDD1Dull + 0x5851F42D4C957F2Dull};
    auto base_floors = [](double area_m2) { // 4 floors in blocks under 0.3 ha, down to 1.5 over 25 ha
        const double x = std::log10(std::max(area_m2, 1.0));
        const std::array<double, 4> at{3.5, 4.2, 4.8, 5.4}, floors{4.0, 3.0, 2.0, 1.5};
        if (x <= at.front()) return floors.front();
        for (std::size_t i = 1; i < at.size(); ++i) {
            if (x <= at[i]) return floors[i - 1] + (floors[i] - floors[i - 1]) * (x - at[i - 1]) / (at[i] - at[i - 1]);
        }
        return floors.back();
    };
    for (std::size_t b = 0; b < count; ++b) {
        const Vec2 first = out.buildings.points[static_cast<std::size_t>(out.buildings.offsets[b])];
        const double area = out.faces.face_area[static_cast<std::size_t>(out.buildings.owner[b])];
        const double base = base_floors(area);
        const double distance = (first - centre).norm() / radius;
        const double near_middle = std::clamp(1.0 - 1.5 * distance, 0.0, 1.0);
        const double central = 1.0 + 0.6 * near_middle * near_middle;
        // Log-normal noise (sigma 0.25), from two uniforms (Box-Muller).
        const double u1 = 1.0 - random.uniform(0.0, 1.0), u2 = random.uniform(0.0, 1.0);
        double floors = base * central * std::exp(0.25 * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2));
        const bool tower = random.uniform(0.0, 1.0) < 0.01 && base * central >= 5.0;
        if (tower) floors *= random.uniform(1.8, 3.0);
        floors = std::clamp(std::rint(floors), 1.0, 60.0);
        out.building_height_m[b] = floors * o.floor_height_m + random.uniform(0.3, 1.2);
        out.building_tint[b] = random.uniform(0.0, 1.0);
    }
}

} // namespace ggg::city_detail
