#pragma once
// WGS84 longitude/latitude <-> metres in a local transverse Mercator frame centred on an
// origin (PROJ's exact tmerc). Centring on the data keeps the scale error of a city-sized
// extract far below a millimetre per metre, so lengths in the graph are real lengths.
#include <memory>
#include <span>

#include "ggg/graph/geometric_graph.hpp"

namespace ggg {

class LocalProjection {
public:
    explicit LocalProjection(GeoOrigin origin);
    ~LocalProjection();
    LocalProjection(const LocalProjection&) = delete;
    LocalProjection& operator=(const LocalProjection&) = delete;

    const GeoOrigin& origin() const noexcept { return origin_; }

    // In place: xy holds (lon, lat) pairs in degrees on entry and (x, y) metres on return.
    void forward(std::span<Vec2> xy) const;
    // In place: (x, y) metres to (lon, lat) degrees.
    void inverse(std::span<Vec2> xy) const;

    Vec2 forward(double lon, double lat) const;
    Vec2 inverse(const Vec2& xy) const;

    // The PROJ string of the frame, written into files so that other tools can reproject.
    std::string proj_string() const;

private:
    struct Impl;
    GeoOrigin origin_;
    std::unique_ptr<Impl> impl_;
};

// The PROJ string of the local frame centred on `origin`.
std::string local_crs(GeoOrigin origin);

// Moves a graph into the local frame of another origin (positions, polylines and frame
// origins), e.g. to put a second city into the frame of a scene that holds the first.
void reproject(GeometricGraph& graph, GeoOrigin origin);

// Great-circle (haversine) distance in metres on the mean earth sphere; an independent
// check of projected lengths.
double haversine_m(double lat1, double lon1, double lat2, double lon2);

} // namespace ggg
