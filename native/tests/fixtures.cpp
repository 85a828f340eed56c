#include "fixtures.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <fstream>
#include <numeric>
#include <sstream>

#include "../src/io/grammar_packing.hpp" // the packed form's column names, in place order
#include "ggg/graph/plane_geometry.hpp"

namespace ggg::test {

namespace fs = std::filesystem;

namespace {

// A new folder for each test process, never one left by an earlier process with the same pid
// (a test that counts the files of its folder would count theirs too). Removed when the
// process ends; GGG_KEEP_TEST_FILES=1 keeps it, to look at. (Kept in storage that is never
// destroyed, so that it is still there when the removal runs at exit.)
const fs::path& temp_folder() {
    static const fs::path* dir = [] {
        std::string name = (fs::temp_directory_path() / ("ggg_tests_" + std::to_string(getpid()) + "_XXXXXX")).string();
        if (!::mkdtemp(name.data())) throw std::runtime_error("cannot make a temporary folder: " + name);
        return new fs::path(name);
    }();
    return *dir;
}

void remove_temp_folder() {
    std::error_code ignored;
    fs::remove_all(temp_folder(), ignored);
}

} // namespace

std::string temp_path(const std::string& suffix) {
    static int counter = 0;
    static const bool cleaned_at_exit = [] { return std::getenv("GGG_KEEP_TEST_FILES") == nullptr && std::atexit(remove_temp_folder) == 0; }();
    (void)cleaned_at_exit;
    return (temp_folder() / ("f" + std::to_string(counter++) + suffix)).string();
}

std::string temp_file(const std::string& content, const std::string& suffix) {
    const std::string path = temp_path(suffix);
    std::ofstream(path, std::ios::binary) << content;
    return path;
}

std::string shared_osm_dir() {
    const fs::path dir(GGG_SHARED_OSM_DIR);
    return fs::is_directory(dir) ? fs::canonical(dir).string() : std::string{};
}

std::vector<std::string> corpus_files() {
    std::vector<std::string> files;
    const std::string dir = shared_osm_dir();
    if (dir.empty()) return files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const std::string name = entry.path().filename().string();
        if (name.find(".osm") != std::string::npos) files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::size_t component_count(const GeometricGraph& g) {
    std::vector<std::int32_t> parent(g.vertex_count());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](std::int32_t x) {
        while (parent[static_cast<std::size_t>(x)] != x) x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
        return x;
    };
    std::size_t components = g.vertex_count();
    for (const auto& [u, v] : g.edges) {
        const auto a = find(u), b = find(v);
        if (a != b) {
            parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
            --components;
        }
    }
    return components;
}

CliResult run_cli(const std::string& arguments) {
    const std::string err_path = temp_path(".err");
    const std::string command = std::string("'") + GGG_CLI_PATH + "' " + arguments + " 2>'" + err_path + "'";
    FILE* pipe = popen(command.c_str(), "r");
    std::string out;
    std::array<char, 4096> buffer{};
    while (pipe && fgets(buffer.data(), buffer.size(), pipe)) out += buffer.data();
    const int status = pipe ? pclose(pipe) : -1;
    std::ifstream err_in(err_path);
    std::stringstream err;
    err << err_in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out, err.str()};
}

std::size_t polyline_crossings(const GeometricGraph& g, std::size_t from_edge) {
    std::size_t n = 0;
    for (std::size_t e = from_edge; e < g.edge_count(); ++e) {
        const Vec2* p = g.geometry_begin(static_cast<EdgeId>(e));
        const std::size_t np = g.geometry_size(static_cast<EdgeId>(e));
        for (std::size_t f = 0; f < g.edge_count(); ++f) {
            if (f == e || (f >= from_edge && f < e)) continue;
            const Vec2* q = g.geometry_begin(static_cast<EdgeId>(f));
            const std::size_t nq = g.geometry_size(static_cast<EdgeId>(f));
            bool crossed = false;
            for (std::size_t i = 0; i + 1 < np && !crossed; ++i) {
                for (std::size_t k = 0; k + 1 < nq && !crossed; ++k) {
                    // Pieces that meet at a shared end (two streets at one junction, nearly in
                    // line) meet there, which the rounding of t and u must not take for a crossing.
                    if (p[i] == q[k] || p[i] == q[k + 1] || p[i + 1] == q[k] || p[i + 1] == q[k + 1]) continue;
                    const Vec2 r = p[i + 1] - p[i], s = q[k + 1] - q[k];
                    const double d = cross(r, s);
                    if (std::abs(d) < 1e-12) continue;
                    const double t = cross(q[k] - p[i], s) / d, u = cross(q[k] - p[i], r) / d;
                    crossed = t > 1e-6 && t < 1 - 1e-6 && u > 1e-6 && u < 1 - 1e-6;
                }
            }
            n += crossed;
        }
    }
    return n;
}


std::size_t shared_places(const GeometricGraph& g, double quantum) {
    std::vector<std::pair<long long, long long>> cells;
    cells.reserve(g.vertex_count());
    for (const Vec2& p : g.positions) cells.emplace_back(std::llround(p.x() / quantum), std::llround(p.y() / quantum));
    std::sort(cells.begin(), cells.end());
    return cells.size() - static_cast<std::size_t>(std::unique(cells.begin(), cells.end()) - cells.begin());
}

nlohmann::json& packed_column(nlohmann::json& doc, const std::string& section, const std::string& name) {
    const auto at = io_detail::column_place(section, name);
    if (!at || section == "graph") throw std::invalid_argument("no packed column " + section + "." + name);
    nlohmann::json& placed = doc.at(section);
    while (placed.size() <= *at) placed.push_back(nlohmann::json::array());
    return placed[*at];
}

} // namespace ggg::test
