// The .qsp container (format-spec/qsp_format.md, "File structure", "Sections"): magic number,
// version, encoder byte, file size, tagged sections and the XXH64 checksum. The one place that reads
// and writes them: decode, inspect, the fingerprint of a .qsp and encode go through it, and so do the
// fuzzers (fuzz/qsp_craft.h) and the format tests that build files by hand.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/codec.h"

namespace qsp::container {

inline constexpr unsigned char kMagic[8] = {0x89, 'Q', 'S', 'P', 0x0D, 0x0A, 0x1A, 0x0A};
inline constexpr std::size_t kFixedHeader = 11;  // magic, major, minor, encoder byte
inline constexpr std::size_t kChecksumBytes = 8;

// Section tags. Bit 7 set: optional (a decoder that does not know it skips it).
inline constexpr std::uint8_t kTagCounts = 0x01, kTagTopology = 0x02, kTagGeometry = 0x03, kTagOrder = 0x04;
// Format 3.1: required where the mesh is not a manifold, consistently oriented all-quad one.
inline constexpr std::uint8_t kTagPolygons = 0x05;
// Format 3.2: required where the mesh has texture coordinates.
inline constexpr std::uint8_t kTagTexcoords = 0x06;
// Format 3.3: required where the mesh has face labels (o, g, usemtl, s) or material libraries.
inline constexpr std::uint8_t kTagLabels = 0x07;
// Format 3.4: required where the mesh has OpenSubdiv tags.
inline constexpr std::uint8_t kTagTags = 0x08;
// Format 3.5: required where the mesh has normals.
inline constexpr std::uint8_t kTagNormals = 0x09;
inline constexpr std::uint8_t kTagExact = 0x0a;   // exact positions, from 3.6
inline constexpr std::uint8_t kTagColors = 0x0b;  // vertex and face colours, from 3.8
// Format 3.12: the geometry section codes the polygons section's interior positions.
inline constexpr std::uint8_t kTagInterior = 0x0c;
// Format 3.13: texture coordinates, normals and colours binary32 does not hold.
inline constexpr std::uint8_t kTagExactValues = 0x0d;
// Format 3.14: PLY vertex and face properties and the OBJ vertex weight.
inline constexpr std::uint8_t kTagProperties = 0x0e;
// Format 3.17: the mirror symmetry the geometry section predicts positions by (its tool bit 0x20).
inline constexpr std::uint8_t kTagSymmetry = 0x0f;
inline constexpr std::uint8_t kOptionalBit = 0x80;
inline constexpr std::uint8_t kTagComments = 0x81;       // optional, from 3.1
inline constexpr std::uint8_t kTagKeptLines = 0x82;      // optional, from 3.7
inline constexpr std::uint8_t kTagStatements = 0x83;     // optional, from 3.11
inline constexpr std::uint8_t kTagPlyInfo = 0x84;        // optional, from 3.15: PLY obj_info lines
inline constexpr std::uint8_t kTagCodedComments = 0x85;  // optional, from 3.16: comments range-coded

// A section tag, the format minor version that defines it, and its name in messages.
struct SectionKind {
  std::uint8_t tag;
  std::uint8_t minor;
  std::string_view name;
};
// Every section this qsp knows, in tag order (a new section is a row here, beside its coder). parse()
// refuses a required tag not in it and a required section in a file of a lower minor version than its
// row's; decode() refuses, and holds_polygons() looks for, the required ones added after 3.0
// (added_required), which only decode_polygons() reads.
inline constexpr SectionKind kSections[] = {
    {kTagCounts, kFormatMinorQuads, "counts"},
    {kTagTopology, kFormatMinorQuads, "topology"},
    {kTagGeometry, kFormatMinorQuads, "geometry"},
    {kTagOrder, kFormatMinorQuads, "order"},
    {kTagPolygons, kFormatMinorPolygons, "polygons"},
    {kTagTexcoords, kFormatMinorTexcoords, "texture coordinates"},
    {kTagLabels, kFormatMinorLabels, "face labels"},
    {kTagTags, kFormatMinorTags, "subdivision tags"},
    {kTagNormals, kFormatMinorNormals, "normals"},
    {kTagExact, kFormatMinorExact, "exact positions"},
    {kTagColors, kFormatMinorColors, "colours"},
    {kTagInterior, kFormatMinorInterior, "interior positions"},
    {kTagExactValues, kFormatMinorExactValues, "exact values"},
    {kTagProperties, kFormatMinorProperties, "properties"},
    {kTagSymmetry, kFormatMinorMirror, "symmetry"},
    {kTagComments, kFormatMinorPolygons, "comments"},
    {kTagKeptLines, kFormatMinorKeptLines, "kept lines"},
    {kTagStatements, kFormatMinorStatements, "statement order"},
    {kTagPlyInfo, kFormatMinorPlyInfo, "PLY obj_info lines"},
    {kTagCodedComments, kFormatMinorCodedComments, "coded comments"},
};

// Whether the section is a required one added after 3.0 (a file holding it is not a 3.0 quad file).
constexpr bool added_required(const SectionKind& k) {
  return k.minor > kFormatMinorQuads && !(k.tag & kOptionalBit);
}

// Whether the section holds data a quad mesh (QuadMesh) has no place for: every required one added after
// 3.0 but the symmetry section, which says only how the positions are coded.
constexpr bool holds_more_than_quads(const SectionKind& k) {
  return added_required(k) && k.tag != kTagSymmetry;
}

// Whether parse() refuses the section in a file of a lower minor version than its row's: every required
// one added after 3.0, and the optional ones from 3.16 on (earlier ones were never held to it, and files
// that hold them in a lower minor stay readable).
constexpr bool held_to_minor(const SectionKind& k) {
  return added_required(k) || k.minor >= kFormatMinorCodedComments;
}

// The tag as the messages write it: "0x05".
std::string tag_name(std::uint8_t tag);

// The encoder byte: the compression level in bits 0-3 (0 = not said, 1-9), bits 4-7 reserved.
inline constexpr std::uint8_t kLevelMask = 0x0F, kMaxLevelValue = 9;

struct Section {
  std::uint8_t tag = 0;
  std::uint64_t offset = 0;                                                        // of the tag byte
  std::uint64_t payload_offset = 0;                                                // of the payload
  std::string_view payload;                                                        // into the parsed file
  std::uint64_t size() const { return payload_offset + payload.size() - offset; }  // tag + length + payload
};

struct File {
  std::uint8_t major = 0, minor = 0, level = 0;
  std::vector<Section> sections;  // in file order (increasing tags), optional ones included
  // The section with `tag`, or null.
  const Section* find(std::uint8_t tag) const;
};

// Checks a whole file's container, in the spec's order (magic, version, size, checksum, encoder
// byte, then the sections' framing: tags in increasing order, counts, topology and geometry
// present, no unknown required tag, no section in a file of a lower minor version than its row's where
// held_to_minor, not both comments sections) and returns its sections, which point into `file`. Throws
// Error(kFormat) naming what and the byte offset, kVersion for another major version (or an unknown
// required section in a file of a newer minor), kChecksum. Safe on untrusted input.
File parse(std::string_view file);

// XXH64 with seed 0, as the checksum field holds it.
std::uint64_t checksum(std::string_view bytes);

// Appends a section: tag, varint length, payload.
void put_section(std::string& out, std::uint8_t tag, std::string_view payload);

// A whole file around `sections` (put_section's output, in order): magic, version, encoder byte, the
// size field (which counts itself) and the checksum. Writes whatever it is given (tests craft invalid
// files with it).
std::string seal(std::uint8_t major, std::uint8_t minor, std::uint8_t encoder, std::string_view sections);

// `file` (a whole .qsp) with the section `tag` holding `payload`, in its place among the others
// (replacing one with that tag), and a minor version of at least `minor`. Throws what parse() throws.
std::string with_section(std::string_view file, std::uint8_t tag, std::string_view payload,
                         std::uint8_t minor);

}  // namespace qsp::container
