// GeoJSON region reader: ggg::geojson_region_centre, then ggg::read_geojson_region around
// that centre and around a fixed origin (they take a path: the input goes to a temporary
// .geojson file). An InputError is a correct outcome.
#include <cmath>
#include <cstdint>

#include "fuzz_common.hpp"
#include "ggg/error.hpp"
#include "ggg/io/geojson.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const ggg_fuzz::TempFile file(data, size, ".geojson");
    try {
        const ggg::GeoOrigin centre = ggg::geojson_region_centre(file.path());
        if (!std::isfinite(centre.lat) || !std::isfinite(centre.lon)) ggg_fuzz::fail("region centre is not finite");
        (void)ggg::read_geojson_region(file.path(), centre);
    } catch (const ggg::Error&) {
    }
    try {
        (void)ggg::read_geojson_region(file.path(), ggg::GeoOrigin{46.0, 8.95});
    } catch (const ggg::Error&) {
    }
    return 0;
}
