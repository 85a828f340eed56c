// Occurrences de-duplicated by vertex set, within a group and across the groups of an order
// (detection_stages.hpp).
#include "detection_stages.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace ggg::detection_detail {

namespace {

// Sorted vertex set of an occurrence, for de-duplication.
struct VertexSetKey {
    std::uint64_t hash;
    std::uint32_t index;
};

std::uint64_t mix(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

} // namespace

void deduplicate(Isogroup& group) {
    const std::size_t k = group.order();
    const std::size_t n = group.frequency();
    std::vector<VertexId> sorted(group.vertices);
    std::vector<VertexSetKey> keys(n);
    for (std::size_t i = 0; i < n; ++i) {
        auto first = sorted.begin() + static_cast<std::ptrdiff_t>(i * k);
        std::sort(first, first + static_cast<std::ptrdiff_t>(k));
        std::uint64_t h = 0x5eed;
        for (std::size_t j = 0; j < k; ++j) h = mix(h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(sorted[i * k + j])));
        keys[i] = {h, static_cast<std::uint32_t>(i)};
    }
    std::sort(keys.begin(), keys.end(), [](const VertexSetKey& a, const VertexSetKey& b) {
        return a.hash < b.hash || (a.hash == b.hash && a.index < b.index);
    });
    std::vector<char> drop(n, 0);
    bool any = false;
    for (std::size_t a = 0; a < n;) {
        std::size_t b = a + 1;
        while (b < n && keys[b].hash == keys[a].hash) ++b;
        for (std::size_t x = a; x < b; ++x) {
            if (drop[keys[x].index]) continue;
            for (std::size_t y = x + 1; y < b; ++y) {
                if (drop[keys[y].index]) continue;
                if (std::equal(sorted.begin() + static_cast<std::ptrdiff_t>(keys[x].index * k),
                               sorted.begin() + static_cast<std::ptrdiff_t>((keys[x].index + 1) * k),
                               sorted.begin() + static_cast<std::ptrdiff_t>(keys[y].index * k))) {
                    drop[keys[y].index] = 1;
                    any = true;
                }
            }
        }
        a = b;
    }
    if (!any) return;
    std::size_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (drop[i]) continue;
        if (out != i) {
            std::copy_n(group.vertices.begin() + static_cast<std::ptrdiff_t>(i * k), k,
                        group.vertices.begin() + static_cast<std::ptrdiff_t>(out * k));
            group.transforms[out] = group.transforms[i];
        }
        ++out;
    }
    group.vertices.resize(out * k);
    group.transforms.resize(out);
}

void assign_to_one_group(std::vector<Found>& found, const GeometricGraph& g) {
    struct Entry {
        std::uint64_t hash;
        std::uint32_t rank; // of the group, most frequent first
        std::uint32_t occurrence;
    };
    std::vector<std::size_t> by_frequency(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) by_frequency[i] = i;
    std::stable_sort(by_frequency.begin(), by_frequency.end(), [&](std::size_t a, std::size_t b) {
        return found[a].group.frequency() > found[b].group.frequency();
    });
    std::vector<std::size_t> offset(found.size() + 1, 0);
    for (std::size_t r = 0; r < found.size(); ++r) offset[r + 1] = offset[r] + found[by_frequency[r]].group.frequency();
    std::vector<Entry> entries(offset.back());
    std::vector<std::vector<VertexId>> sorted_sets(found.size());
    tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t r) {
        const Isogroup& group = found[by_frequency[r]].group;
        const std::size_t k = group.order();
        std::vector<VertexId>& sorted = sorted_sets[r];
        sorted = group.vertices;
        for (std::size_t i = 0; i < group.frequency(); ++i) {
            auto first = sorted.begin() + static_cast<std::ptrdiff_t>(i * k);
            std::sort(first, first + static_cast<std::ptrdiff_t>(k));
            std::uint64_t h = 0x5eed;
            for (std::size_t j = 0; j < k; ++j) h = mix(h ^ static_cast<std::uint32_t>(sorted[i * k + j]));
            entries[offset[r] + i] = {h, static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(i)};
        }
    });
    tbb::parallel_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        if (a.hash != b.hash) return a.hash < b.hash;
        if (a.rank != b.rank) return a.rank < b.rank;
        return a.occurrence < b.occurrence;
    });
    std::vector<std::vector<char>> drop(found.size());
    for (std::size_t r = 0; r < found.size(); ++r) drop[r].assign(found[by_frequency[r]].group.frequency(), 0);
    std::vector<char> touched(found.size(), 0);
    auto set_of = [&](const Entry& e) {
        const std::size_t k = found[by_frequency[e.rank]].group.order();
        return sorted_sets[e.rank].data() + static_cast<std::size_t>(e.occurrence) * k;
    };
    for (std::size_t a = 0; a < entries.size();) {
        std::size_t b = a + 1;
        while (b < entries.size() && entries[b].hash == entries[a].hash) ++b;
        for (std::size_t x = a; x < b; ++x) {
            if (drop[entries[x].rank][entries[x].occurrence]) continue;
            const std::size_t k = found[by_frequency[entries[x].rank]].group.order();
            for (std::size_t y = x + 1; y < b; ++y) {
                if (drop[entries[y].rank][entries[y].occurrence]) continue;
                if (found[by_frequency[entries[y].rank]].group.order() != k) continue;
                if (std::equal(set_of(entries[x]), set_of(entries[x]) + k, set_of(entries[y]))) {
                    drop[entries[y].rank][entries[y].occurrence] = 1;
                    touched[entries[y].rank] = 1;
                }
            }
        }
        a = b;
    }
    tbb::parallel_for(std::size_t{0}, found.size(), [&](std::size_t r) {
        if (!touched[r]) return;
        Isogroup& group = found[by_frequency[r]].group;
        const std::size_t k = group.order();
        std::size_t out = 0;
        for (std::size_t i = 0; i < group.frequency(); ++i) {
            if (drop[r][i]) continue;
            if (out != i) {
                std::copy_n(group.vertices.begin() + static_cast<std::ptrdiff_t>(i * k), k,
                            group.vertices.begin() + static_cast<std::ptrdiff_t>(out * k));
                group.transforms[out] = group.transforms[i];
            }
            ++out;
        }
        group.vertices.resize(out * k);
        group.transforms.resize(out);
        if (out > 0) refine(group, g);
    });
}

} // namespace ggg::detection_detail
