// The overlap graph of a set of occurrences: which of them share a vertex.
#include <algorithm>
#include <string>

#include "ggg/analysis/non_overlapping.hpp"
#include "ggg/error.hpp"
#include "independent_set.hpp"

namespace ggg {

using non_overlapping_detail::kNone;

namespace {

void check_occurrences(std::span<const VertexId> vertices, std::size_t k) {
    if (k == 0) throw UsageError("non-overlapping selection: occurrence size k must be positive");
    if (vertices.size() % k != 0) {
        throw UsageError("non-overlapping selection: " + std::to_string(vertices.size()) +
                         " vertex ids are not a whole number of occurrences of " + std::to_string(k));
    }
    if (vertices.size() / k >= kNone) {
        throw UsageError("non-overlapping selection: at most 2^32 - 1 occurrences are supported");
    }
}

} // namespace

OverlapGraph build_overlap_graph(std::span<const VertexId> vertices, std::size_t k) {
    check_occurrences(vertices, k);
    OverlapGraph graph;
    const std::size_t n = vertices.size() / k;
    if (n == 0) return graph;

    VertexId max_id = 0;
    for (const VertexId v : vertices) {
        if (v < 0) throw UsageError("non-overlapping selection: negative vertex id " + std::to_string(v));
        max_id = std::max(max_id, v);
    }
    // Bucket index per vertex id: the id itself when ids are reasonably dense, else its
    // rank among the distinct ids (sparse ids would make a direct table huge).
    std::vector<std::uint32_t> key(vertices.size());
    std::size_t keys = 0;
    if (static_cast<std::size_t>(max_id) < 4 * vertices.size() + 256) {
        for (std::size_t i = 0; i < vertices.size(); ++i) key[i] = static_cast<std::uint32_t>(vertices[i]);
        keys = static_cast<std::size_t>(max_id) + 1;
    } else {
        std::vector<VertexId> distinct(vertices.begin(), vertices.end());
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            key[i] = static_cast<std::uint32_t>(std::lower_bound(distinct.begin(), distinct.end(), vertices[i]) -
                                                distinct.begin());
        }
        keys = distinct.size();
    }

    // Occurrences through each vertex (counting sort; ascending within a bucket).
    std::vector<std::size_t> start(keys + 1, 0);
    for (const std::uint32_t key_v : key) ++start[key_v + 1];
    for (std::size_t v = 0; v < keys; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> through(vertices.size());
    {
        std::vector<std::size_t> fill(start.begin(), start.end() - 1);
        for (std::uint32_t i = 0; i < n; ++i) {
            for (std::size_t p = static_cast<std::size_t>(i) * k; p < static_cast<std::size_t>(i + 1) * k; ++p) {
                through[fill[key[p]]++] = i;
            }
        }
    }

    // Row i = union of the buckets of its vertices, deduplicated by a mark per
    // occurrence. Occurrences come in any order, so their buckets are scattered in
    // memory: ask for the bucket bounds a few occurrences ahead and for the buckets a
    // little nearer.
    constexpr std::size_t kAheadBounds = 8, kAheadBuckets = 4;
    std::vector<std::int64_t> offsets(n + 1, 0);
    std::vector<std::uint32_t> unsorted;
    {
        std::vector<std::uint32_t> mark(n, kNone);
        for (std::uint32_t i = 0; i < n; ++i) {
            if (i + kAheadBounds < n) {
                for (std::size_t p = (i + kAheadBounds) * k; p < (i + kAheadBounds + 1) * k; ++p) __builtin_prefetch(&start[key[p]]);
            }
            if (i + kAheadBuckets < n) {
                for (std::size_t p = (i + kAheadBuckets) * k; p < (i + kAheadBuckets + 1) * k; ++p) __builtin_prefetch(&through[start[key[p]]]);
            }
            for (std::size_t p = static_cast<std::size_t>(i) * k; p < static_cast<std::size_t>(i + 1) * k; ++p) {
                for (std::size_t q = start[key[p]]; q < start[key[p] + 1]; ++q) {
                    const std::uint32_t j = through[q];
                    if (j != i && mark[j] != i) {
                        mark[j] = i;
                        unsorted.push_back(j);
                    }
                }
            }
            offsets[i + 1] = static_cast<std::int64_t>(unsorted.size());
        }
    }
    // Sorted rows without sorting: the relation is symmetric, so its transpose is the
    // same graph, and filling the transpose row by row in order of i sorts every row.
    graph.neighbors.resize(unsorted.size());
    {
        std::vector<std::int64_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t i = 0; i < n; ++i) {
            for (std::int64_t p = offsets[i]; p < offsets[i + 1]; ++p) {
                graph.neighbors[static_cast<std::size_t>(fill[unsorted[static_cast<std::size_t>(p)]]++)] = i;
            }
        }
    }
    graph.offsets = std::move(offsets);
    return graph;
}

void non_overlapping_detail::check_graph(const OverlapGraph& graph) {
    if (graph.offsets.empty() || graph.offsets.front() != 0 ||
        graph.offsets.back() != static_cast<std::int64_t>(graph.neighbors.size())) {
        throw UsageError("overlap graph: offsets do not span the neighbour array");
    }
    const std::size_t n = graph.offsets.size() - 1;
    if (n >= kNone) throw UsageError("overlap graph: at most 2^32 - 1 occurrences are supported");
    for (std::size_t i = 0; i < n; ++i) {
        if (graph.offsets[i + 1] < graph.offsets[i]) throw UsageError("overlap graph: offsets decrease");
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        const auto row = graph.neighbours_of(i);
        for (std::size_t p = 0; p < row.size(); ++p) {
            const std::uint32_t j = row[p];
            if (j >= n || j == i || (p > 0 && row[p - 1] >= j)) {
                throw UsageError("overlap graph: row " + std::to_string(i) +
                                 " is not sorted, repeats, or holds itself or an id out of range");
            }
            const auto back = graph.neighbours_of(j);
            if (!std::binary_search(back.begin(), back.end(), i)) {
                throw UsageError("overlap graph: not symmetric at " + std::to_string(i) + "-" + std::to_string(j));
            }
        }
    }
}

} // namespace ggg
