#pragma once
// Whole files read and written safely. Reads are bounded, so a path that is a link to
// /dev/zero, a pipe or a runaway file cannot exhaust memory. Writes go to a temporary file
// created exclusively beside the target and renamed over it: concurrent writers to one path
// all succeed and leave one whole file, and a failure (a full disk, a cancelled run) leaves
// the previous file untouched and no temporary file behind.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace ggg {

// Largest text file (JSON graph, GeoJSON, grammar, uncompressed OSM XML or OPL) read into
// memory. The largest city extracts the project reads are a few hundred megabytes as XML.
inline constexpr std::size_t max_text_file_bytes = std::size_t{2} << 30; // 2 GiB
// A pipe or a device says nothing of its length: this much is read from one at most.
inline constexpr std::size_t max_stream_bytes = std::size_t{256} << 20; // 256 MiB

// The whole file. Throws InputError naming the file when it is missing, a folder, unreadable,
// or longer than `limit` bytes (for a device or a pipe: when more than `limit` bytes come).
std::string read_text_file(const std::string& path, std::size_t limit = max_text_file_bytes);

// Checks, before any work is done, that `path` can be written: UsageError when it exists and
// is not a regular file (a folder, a device, a symbolic link: those are never replaced), and
// InputError when its folder does not exist or cannot be written to. Commands check every
// output this way before they write the first, so a bad second output replaces nothing.
void check_output_path(const std::string& path);
void check_output_paths(const std::vector<std::string>& paths);

// Writes `text` to `path` through a unique temporary file beside it (created exclusively,
// flushed to disk, renamed over `path`). Throws InputError on any failure (disk full, file
// size limit, no permission), after removing the temporary file.
void write_text_file(const std::string& path, std::string_view text);

} // namespace ggg
