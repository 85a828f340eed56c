#pragma once
// OSM XML and OPL are checked by the project before libosmium parses them: libosmium's
// coordinate parser overflows (undefined behaviour, then a wrong location) on values such as
// lat="1e300", and expat re-scans a token that spans its input chunks, so one huge attribute
// takes time that grows with the square of its length. A coordinate out of range or not a
// number is an error naming the node; an element longer than any OSM data needs is refused.
#include <cstddef>
#include <string>
#include <string_view>

namespace ggg::osm_detail {

// OSM tag values hold at most 255 characters; an element (from '<' to '>') or a run of text
// between elements this long is not OSM data.
inline constexpr std::size_t max_xml_token_bytes = std::size_t{1} << 20;

enum class TextFormat { xml, opl };

// The decompressed text of an OSM file (.osm, .opl, and their .gz and .bz2 forms), bounded
// by max_text_file_bytes (files.hpp) so that a small compressed file cannot expand without end.
// Throws InputError naming the file.
std::string read_osm_text(const std::string& path);

// Throws InputError ("<name>: node 42: latitude '1e300' is out of range (-90 to 90)", ...).
void check_osm_text(std::string_view text, TextFormat format, const std::string& name);

// A PBF file, read whole into memory (files.hpp bounds it), checked where libosmium does not
// check (undefined behaviour found by fuzzing): every blob header must name its type, which
// libosmium compares with a null pointer otherwise, and in every data block the deltas of ids
// and coordinates must add up within 64 bits and every coordinate must lie within the world.
// Throws InputError ("<name>: not a readable OSM file (PBF error: node 7: its latitude is out
// of range (-90 to 90))"). What libosmium reports itself (bad framing, bad protobuf) is left to it.
void check_pbf(std::string_view data, const std::string& name);

} // namespace ggg::osm_detail
