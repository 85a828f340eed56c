#include "ggg/osm/projection.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include <proj.h>

#include "ggg/error.hpp"

namespace ggg {

struct LocalProjection::Impl {
    PJ_CONTEXT* ctx = nullptr;
    PJ* pj = nullptr;
    ~Impl() {
        if (pj) proj_destroy(pj);
        if (ctx) proj_context_destroy(ctx);
    }
};

std::string local_crs(GeoOrigin origin) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "+proj=tmerc +lat_0=%.9f +lon_0=%.9f +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m",
                  origin.lat, origin.lon);
    return buffer;
}

std::string LocalProjection::proj_string() const { return local_crs(origin_); }

void reproject(GeometricGraph& g, GeoOrigin origin) {
    if (g.origin.lat == origin.lat && g.origin.lon == origin.lon) return;
    const LocalProjection from(g.origin);
    const LocalProjection to(origin);
    auto move = [&](std::span<Vec2> points) {
        from.inverse(points);
        to.forward(points);
    };
    move(std::span<Vec2>(g.positions));
    move(std::span<Vec2>(g.geometry));
    std::vector<Vec2> frame_origins;
    frame_origins.reserve(g.frames.size());
    for (const auto& f : g.frames) frame_origins.push_back(f.t);
    for (const auto& r : g.more_rewrites) frame_origins.push_back(r.frame.t);
    move(std::span<Vec2>(frame_origins));
    for (std::size_t v = 0; v < g.frames.size(); ++v) g.frames[v].t = frame_origins[v];
    for (std::size_t i = 0; i < g.more_rewrites.size(); ++i) g.more_rewrites[i].frame.t = frame_origins[g.frames.size() + i];
    g.origin = origin;
}

LocalProjection::LocalProjection(GeoOrigin origin) : origin_(origin), impl_(std::make_unique<Impl>()) {
    if (!std::isfinite(origin.lat) || !std::isfinite(origin.lon) || std::abs(origin.lat) > 90.0 ||
        std::abs(origin.lon) > 180.0) {
        throw InputError("projection origin out of range: lat " + std::to_string(origin.lat) + ", lon " +
                         std::to_string(origin.lon));
    }
    impl_->ctx = proj_context_create();
    proj_log_level(impl_->ctx, PJ_LOG_NONE);
    proj_context_set_enable_network(impl_->ctx, 0);
    const std::string definition =
        "+proj=pipeline +step +proj=unitconvert +xy_in=deg +xy_out=rad +step " + proj_string();
    impl_->pj = proj_create(impl_->ctx, definition.c_str());
    if (!impl_->pj) {
        throw Error("cannot create the map projection: " +
                    std::string(proj_context_errno_string(impl_->ctx, proj_context_errno(impl_->ctx))));
    }
}

LocalProjection::~LocalProjection() = default;

namespace {
// A point too far from the origin (the transverse Mercator diverges 90 degrees of longitude
// away) comes back as infinity or an error value: that is bad input, not a number to keep.
void transform(PJ* pj, PJ_DIRECTION direction, std::span<Vec2> xy) {
    if (xy.empty()) return;
    double* x = xy.data()->data();
    const std::size_t stride = sizeof(Vec2);
    proj_trans_generic(pj, direction, x, stride, xy.size(), x + 1, stride, xy.size(), nullptr, 0, 0,
                       nullptr, 0, 0);
    for (const Vec2& p : xy) {
        if (!p.allFinite() || std::abs(p.x()) > 1e8 || std::abs(p.y()) > 1e8) {
            throw InputError("coordinates cannot be projected into one local frame: the data spans too much of the "
                             "earth (a road graph covers a city or a region, not half the globe)");
        }
    }
}
} // namespace

void LocalProjection::forward(std::span<Vec2> xy) const { transform(impl_->pj, PJ_FWD, xy); }
void LocalProjection::inverse(std::span<Vec2> xy) const { transform(impl_->pj, PJ_INV, xy); }

Vec2 LocalProjection::forward(double lon, double lat) const {
    Vec2 p{lon, lat};
    forward(std::span<Vec2>(&p, 1));
    return p;
}

Vec2 LocalProjection::inverse(const Vec2& xy) const {
    Vec2 p = xy;
    inverse(std::span<Vec2>(&p, 1));
    return p;
}

double haversine_m(double lat1, double lon1, double lat2, double lon2) {
    constexpr double radius = 6371008.8; // IUGG mean earth radius
    constexpr double deg = M_PI / 180.0;
    const double dlat = (lat2 - lat1) * deg;
    const double dlon = (lon2 - lon1) * deg;
    const double h = std::sin(dlat / 2) * std::sin(dlat / 2) +
                     std::cos(lat1 * deg) * std::cos(lat2 * deg) * std::sin(dlon / 2) * std::sin(dlon / 2);
    return 2 * radius * std::asin(std::min(1.0, std::sqrt(h)));
}

} // namespace ggg
