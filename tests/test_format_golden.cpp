// Pins the .qsp bytes (testdata/golden), the refusal of every damaged or crafted file
// (testdata/invalid/*.qsp + .expect), and the spec's own worked example.
// QSP_UPDATE_GOLDEN=1 rewrites the golden .qsp files and the crafted invalid files: only for a
// deliberate format change, which also needs a new version and a changes-log entry in the spec.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/corpus.h"
#include "support/quantized.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

const std::string kGolden = std::string(QSP_TESTDATA_DIR) + "/golden";
const std::string kInvalid = std::string(QSP_TESTDATA_DIR) + "/invalid";
// Only QSP_UPDATE_GOLDEN=1 rewrites: any other value (0 included) checks, as an unset variable does.
bool updating() {
  const char* v = std::getenv("QSP_UPDATE_GOLDEN");
  return v && std::string(v) == "1";
}

std::string slurp(const std::string& path) { return read_file_bytes(path); }
void dump(const std::string& path, std::string_view bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::string> golden_names() {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(kGolden)) {
    if (e.path().extension() == ".obj") out.push_back(e.path().stem().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

EncodeOptions options_for(const std::string& name) {
  EncodeOptions o;
  // The search is the level's, not the format's: these pin the files of the one that tries the most.
  o.level = kMaxLevel;
  o.keep_order = name.find("_keep_order") != std::string::npos;
  // The partition is an encoder choice, not the format: these pin the motorcycle graph's files (and
  // one greedy partition's), whichever the encoder would pick.
  o.partition =
      name.find("_greedy") != std::string::npos ? PartitionMode::kGreedy : PartitionMode::kMotorcycle;
  // "_q14": positions quantized to 14 bits (the other goldens are lossless).
  if (name.find("_q14") != std::string::npos) o.quantize_bits = 14;
  // "_no_shapes": geometry revision 4 or 5, as the encoder writes them above 32768 vertices (the other
  // goldens are revision 6, which is smaller on each of them).
  if (name.find("_no_shapes") != std::string::npos) o.geometry_shapes = false;
  // The encoder picks patch order for every other golden; this pins the layout-order bytes.
  if (name.find("_layout_order") != std::string::npos) o.geometry_order = CodingOrder::kLayout;
  return o;
}

// `decoded` is `mesh` renumbered, read without the encoder's order map: each vertex of `mesh` has its
// own decoded vertex within `bound` on every axis (bit for bit when 0), and the faces are the same
// quads of those vertices, each up to its first corner.
void expect_same_mesh(const QuadMesh& mesh, const QuadMesh& decoded, double bound) {
  ASSERT_EQ(decoded.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(decoded.face_count(), mesh.face_count());
  const std::size_t n = mesh.vertex_count();
  std::vector<std::uint32_t> to(n);
  std::vector<bool> taken(n);
  for (std::size_t v = 0; v < n; ++v) {
    double best = INFINITY;
    for (std::size_t u = 0; u < n; ++u) {
      double d = 0;
      for (int k = 0; k < 3; ++k)
        d = std::max(d, std::abs(double{decoded.positions[3 * u + k]} - double{mesh.positions[3 * v + k]}));
      if (d < best) best = d, to[v] = static_cast<std::uint32_t>(u);
    }
    ASSERT_LE(best, bound) << "vertex " << v << " has no decoded vertex near enough";
    ASSERT_FALSE(taken[to[v]]) << "vertex " << v << ": its nearest decoded vertex is another's";
    taken[to[v]] = true;
    if (bound == 0) {
      ASSERT_EQ(std::memcmp(&decoded.positions[3 * to[v]], &mesh.positions[3 * v], 12), 0) << "vertex " << v;
    }
  }
  // Each face as its corners from the smallest, so the canonical file's choice of first corner is free.
  const auto faces = [](const std::vector<std::uint32_t>& q, const std::vector<std::uint32_t>* map) {
    std::vector<std::array<std::uint32_t, 4>> out;
    for (std::size_t f = 0; f < q.size() / 4; ++f) {
      std::array<std::uint32_t, 4> c;
      for (int k = 0; k < 4; ++k) c[k] = map ? (*map)[q[4 * f + k]] : q[4 * f + k];
      std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
      out.push_back(c);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  EXPECT_EQ(faces(mesh.quads, &to), faces(decoded.quads, nullptr));
}

// Older format versions whose files must keep decoding: testdata/golden/vX.Y, and the version bytes.
struct OldVersion {
  std::string dir;
  char major, minor;
};
const std::vector<OldVersion> kOldVersions = {{"v1.0", 1, 0}, {"v1.1", 1, 1}, {"v1.2", 1, 2},
                                              {"v1.3", 1, 3}, {"v2.0", 2, 0}, {"v2.1", 2, 1}};

TEST(Golden, BytesArePinned) {
  auto names = golden_names();
  ASSERT_GE(names.size(), 5u);
  for (const auto& name : names) {
    SCOPED_TRACE(name);
    QuadMesh mesh = read_mesh_file(kGolden + "/" + name + ".obj");
    std::string bytes = encode(mesh, options_for(name));
    std::string path = kGolden + "/" + name + ".qsp";
    if (updating()) dump(path, bytes);
    ASSERT_TRUE(fs::exists(path));
    EXPECT_EQ(bytes, slurp(path)) << "the encoder's output changed: a format change needs a version bump";
    // The pinned file decodes to its .obj: exactly when lossless, within half a grid step when not.
    QuadMesh back = decode(slurp(path));
    const std::uint32_t bits = options_for(name).quantize_bits;
    expect_same_mesh(mesh, back, bits ? testing::quantization_bound(mesh.positions, bits) : 0.0);
    if (options_for(name).keep_order) {
      EXPECT_EQ(back.quads, mesh.quads);
      if (!bits) {
        EXPECT_EQ(std::memcmp(back.positions.data(), mesh.positions.data(), 4 * mesh.positions.size()), 0);
      }
    }
  }
}

// Files of formats 1.0 to 2.1 (testdata/golden/vX.Y: the same meshes, geometry coding revisions 1, 2,
// 3 (2 for l_shape_layout_order), 4 and 5; LZMA ends on the topology and order streams of 1.x) still
// decode, to exactly the mesh the current file of the same name gives.
TEST(Golden, OlderVersionFilesStillDecode) {
  for (const auto& [dir, major, minor] : kOldVersions) {
    int seen = 0;
    for (const auto& name : golden_names()) {
      const std::string path = kGolden + "/" + dir + "/" + name + ".qsp";
      if (!fs::exists(path)) continue;  // goldens added later
      SCOPED_TRACE(path);
      const std::string old = slurp(path);
      ASSERT_EQ(old[8], major) << "not a " << dir << " file";
      ASSERT_EQ(old[9], minor) << "not a " << dir << " file";
      const QuadMesh then = decode(old), now = decode(slurp(kGolden + "/" + name + ".qsp"));
      EXPECT_EQ(then.quads, now.quads);
      EXPECT_EQ(then.positions, now.positions);
      ++seen;
    }
    EXPECT_GE(seen, 5) << dir;
  }
}

// The current goldens are revision 6 where it is smaller (all but three), *_no_shapes revision 5
// (tilted_noise*, with normal chaining) or 4, and use both coding orders; the 1.2 goldens pin revision
// 3 (patch order) and 2 (layout order).
TEST(Golden, BothCodingOrdersArePinned) {
  std::map<CodingOrder, int> orders;
  std::map<int, int> revisions, revisions_1_2;
  for (const auto& name : golden_names()) {
    const FileInfo info = inspect(slurp(kGolden + "/" + name + ".qsp"));
    ++revisions[info.geometry_revision];
    if (name.find("_no_shapes") != std::string::npos) {
      EXPECT_EQ(info.geometry_revision, name.starts_with("tilted_noise") ? 5 : 4) << name;
    } else {
      EXPECT_TRUE(info.geometry_revision == 6 || info.geometry_revision == 4) << name;
    }
    ++orders[info.geometry_order];
    const std::string old = kGolden + "/v1.2/" + name + ".qsp";
    if (fs::exists(old)) ++revisions_1_2[inspect(slurp(old)).geometry_revision];
  }
  EXPECT_GE(orders[CodingOrder::kPatch], 5);
  EXPECT_GE(orders[CodingOrder::kLayout], 1);
  EXPECT_GE(revisions[6], 8);
  EXPECT_EQ(revisions[5], 2);
  EXPECT_GE(revisions[4], 1);
  EXPECT_GE(revisions_1_2[3], 5);
  EXPECT_GE(revisions_1_2[2], 1);
}

// Every strict prefix and every single-bit flip of every golden file (both versions) is refused with
// a typed error.
TEST(Golden, EveryPrefixAndBitFlipIsRefused) {
  std::vector<std::string> paths;
  for (const auto& name : golden_names()) {
    paths.push_back(kGolden + "/" + name + ".qsp");
    for (const auto& old : kOldVersions)
      if (fs::exists(kGolden + "/" + old.dir + "/" + name + ".qsp"))
        paths.push_back(kGolden + "/" + old.dir + "/" + name + ".qsp");
  }
  for (const auto& path : paths) {
    SCOPED_TRACE(path);
    const std::string good = slurp(path);
    for (std::size_t n = 0; n < good.size(); ++n) {
      try {
        decode(std::string_view(good).substr(0, n));
        ADD_FAILURE() << "prefix of " << n << " bytes accepted";
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kFormat) << n << ": " << e.what();
      }
    }
    for (std::size_t bit = 0; bit < 8 * good.size(); ++bit) {
      std::string bad = good;
      bad[bit / 8] = static_cast<char>(bad[bit / 8] ^ (1 << (bit % 8)));
      try {
        decode(bad);
        ADD_FAILURE() << "flip of bit " << bit << " accepted";
      } catch (const Error& e) {
        EXPECT_TRUE(e.code() == ErrorCode::kFormat || e.code() == ErrorCode::kVersion ||
                    e.code() == ErrorCode::kChecksum)
            << bit << ": " << error_name(e.code()) << ": " << e.what();
      }
    }
  }
}

// ---- Crafted files ----

void put_varint(std::string& out, std::uint64_t v) {
  while (v >= 0x80) {
    out.push_back(static_cast<char>((v & 0x7F) | 0x80));
    v >>= 7;
  }
  out.push_back(static_cast<char>(v));
}

// magic + version + flags, then the size field and checksum computed as an encoder would.
std::string seal(std::string_view head11, std::string_view sections) {
  std::string out(head11);
  std::uint64_t total = head11.size() + sections.size() + 8 + 1;
  for (;;) {
    std::string v;
    put_varint(v, total);
    if (head11.size() + v.size() + sections.size() + 8 == total) {
      out += v;
      break;
    }
    ++total;
  }
  out += sections;
  std::uint64_t sum = XXH64(out.data(), out.size(), 0);
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>(sum >> (8 * i)));
  return out;
}

std::string section(std::uint8_t tag, std::string_view payload) {
  std::string s(1, static_cast<char>(tag));
  put_varint(s, payload.size());
  s += payload;
  return s;
}

struct Parts {
  std::string head11, counts, topology, geometry;  // section payloads
};

// Splits a file the encoder wrote for a small mesh (1-byte size field, sections in order).
Parts split(const std::string& f) {
  Parts p;
  p.head11 = f.substr(0, 11);
  std::size_t pos = 12;
  std::string* dst[] = {&p.counts, &p.topology, &p.geometry};
  for (std::string* d : dst) {
    ++pos;  // tag
    std::size_t len = static_cast<std::uint8_t>(f[pos++]);
    *d = f.substr(pos, len);
    pos += len;
  }
  return p;
}

std::string assemble(const Parts& p) {
  return seal(p.head11, section(1, p.counts) + section(2, p.topology) + section(3, p.geometry));
}

// The crafted invalid files: name -> (bytes, expected code, expected message substring).
struct Crafted {
  std::string bytes, code, message;
};

std::map<std::string, Crafted> crafted() {
  const std::string good = slurp(kGolden + "/quad.qsp");
  const Parts p = split(good);
  std::map<std::string, Crafted> out;
  out["qsp_empty"] = {"", "format", "truncated"};
  out["qsp_truncated"] = {
      good.substr(0, 40), "format",
      "truncated: header declares " + std::to_string(good.size()) + " bytes, file has 40"};
  std::string bad_magic = good;
  bad_magic[1] = 'X';
  out["qsp_bad_magic"] = {bad_magic, "format", "bad magic number"};
  std::string crlf = good;
  crlf.erase(4, 1);  // CR LF -> LF, as a text-mode transfer would
  out["qsp_line_endings_converted"] = {crlf, "format", "line-ending bytes were changed"};
  std::string seven = good;
  seven[0] = static_cast<char>(0x09);
  out["qsp_high_bit_stripped"] = {seven, "format", "7-bit transfer"};
  Parts newer = p;
  newer.head11[8] = kFormatMajor + 1;
  out["qsp_newer_major"] = {assemble(newer), "version",
                            "file is .qsp format " + std::to_string(kFormatMajor + 1) + "." +
                                std::to_string(kFormatMinor) + "; this qsp reads formats 1.x to " +
                                std::to_string(kFormatMajor) + ".x (upgrade qsp)"};
  std::string flipped = good;
  flipped[40] = static_cast<char>(flipped[40] ^ 0x04);
  out["qsp_checksum_mismatch"] = {flipped, "checksum", "checksum mismatch"};
  Parts reserved = p;
  reserved.head11[10] = 0x01;
  out["qsp_reserved_header_bit"] = {assemble(reserved), "format", "reserved header flag bits are set"};
  Parts reserved2 = p;
  reserved2.counts.back() = 0x40;
  out["qsp_reserved_counts_bit"] = {assemble(reserved2), "format", "reserved counts flag bits are set"};
  out["qsp_trailing_bytes"] = {good + std::string("\0\0\0", 3), "format", "3 trailing bytes"};
  {
    std::string sec = section(1, p.counts) + section(2, p.topology);
    sec += std::string(1, '\x03') + std::string(1, '\x7f') + p.geometry;  // geometry claims 127 bytes
    out["qsp_section_longer_than_file"] = {
        seal(p.head11, sec), "format",
        "section declares 127 bytes but only " + std::to_string(p.geometry.size()) + " remain"};
  }
  {
    std::string counts;
    put_varint(counts, 1000000000);
    put_varint(counts, 1000000000);
    counts += std::string("\x01\x00\x00", 3);
    Parts huge = p;
    huge.counts = counts;
    out["qsp_huge_counts"] = {assemble(huge), "limit", "vertex count 1000000000 exceeds the limit 67108864"};
    counts.clear();
    put_varint(counts, 5000);
    put_varint(counts, 5000);
    counts += std::string("\x01\x00\x00", 3);
    huge.counts = counts;
    out["qsp_counts_larger_than_content"] = {
        assemble(huge), "format",
        "topology describes 1 faces and 4 referenced vertices, the counts section 5000 and 5000"};
  }
  {
    Parts more = p;
    more.counts[0] = 5;  // 5 vertices, but the topology has 4 and no unreferenced vertex
    out["qsp_counts_mismatch"] = {
        assemble(more), "format",
        "topology describes 1 faces and 4 referenced vertices, the counts section 1 and 5"};
  }
  out["qsp_unknown_required_section"] = {seal(p.head11, section(1, p.counts) + section(2, p.topology) +
                                                            section(5, "x") + section(3, p.geometry)),
                                         "format", "unknown or out-of-order required section tag 0x05"};
  out["qsp_missing_geometry"] = {seal(p.head11, section(1, p.counts) + section(2, p.topology)), "format",
                                 "required section 3 is missing"};
  {
    Parts overlong = p;
    overlong.counts = std::string("\x84\x00", 2) + p.counts.substr(1);
    out["qsp_overlong_varint"] = {assemble(overlong), "format", "vertex count is not minimally encoded"};
  }
  {
    // A geometry coding revision newer than this build's: what a 2.1 decoder says to a revision-6
    // section of a 2.2 file.
    Parts future = p;
    future.geometry[0] = 7;
    out["qsp_unknown_geometry_revision"] = {assemble(future), "format",
                                            "geometry: unknown geometry coding revision"};
  }
  {
    // Flag bit 2 (normal chaining) exists in revision 6 only, and bit 3 in none.
    Parts r4 = p, r6 = p;
    r4.geometry[0] = 4;
    r4.geometry[2] = static_cast<char>(r4.geometry[2] | 0x04);
    out["qsp_chain_flag_in_revision_4"] = {assemble(r4), "format",
                                           "geometry: reserved geometry flag bits are set"};
    Parts r5 = r4;  // revision 5 always chains: its flag bit 2 is reserved too
    r5.geometry[0] = 5;
    out["qsp_chain_flag_in_revision_5"] = {assemble(r5), "format",
                                           "geometry: reserved geometry flag bits are set"};
    r6.geometry[0] = 6;
    r6.geometry[2] = static_cast<char>(r6.geometry[2] | 0x08);
    out["qsp_reserved_flag_in_revision_6"] = {assemble(r6), "format",
                                              "geometry: reserved geometry flag bits are set"};
  }
  {
    Parts junk = p;
    junk.topology += '\0';
    out["qsp_topology_trailing_byte"] = {assemble(junk), "format",
                                         "topology section does not end as the encoder ends it"};
  }
  return out;
}

TEST(Invalid, CraftedFilesArePinnedAndRefused) {
  for (const auto& [name, c] : crafted()) {
    SCOPED_TRACE(name);
    std::string path = kInvalid + "/" + name + ".qsp";
    if (updating()) {
      dump(path, c.bytes);
      dump(kInvalid + "/" + name + ".expect", "code=" + c.code + "\nmessage=" + c.message + "\n");
    }
    EXPECT_EQ(slurp(path), c.bytes);
  }
}

TEST(Invalid, EveryQspIsRefusedWithItsExpectedError) {
  int seen = 0;
  for (const auto& e : fs::directory_iterator(kInvalid)) {
    if (e.path().extension() != ".qsp") continue;
    ++seen;
    SCOPED_TRACE(e.path().string());
    auto expect = testing::read_expect(fs::path(e.path()).replace_extension(".expect"));
    ASSERT_TRUE(expect.count("code") && expect.count("message"));
    try {
      decode(slurp(e.path().string()));
      ADD_FAILURE() << "accepted";
    } catch (const Error& err) {
      EXPECT_EQ(error_name(err.code()), expect["code"]) << err.what();
      EXPECT_NE(std::string(err.what()).find(expect["message"]), std::string::npos) << err.what();
    }
  }
  EXPECT_GE(seen, 15);
}

TEST(Invalid, UnknownOptionalSectionsAreSkipped) {
  const Parts p = split(slurp(kGolden + "/quad.qsp"));
  std::string with_extra =
      seal(p.head11, section(1, p.counts) + section(0x81, "future data") + section(2, p.topology) +
                         section(3, p.geometry) + section(0xA0, ""));
  QuadMesh m = decode(with_extra);
  EXPECT_EQ(m.face_count(), 1u);
  FileInfo info = inspect(with_extra);
  EXPECT_EQ(info.other_bytes, 2u + 11u + 2u);
}

TEST(Invalid, NewerMinorVersionIsRead) {
  Parts p = split(slurp(kGolden + "/quad.qsp"));
  p.head11[9] = 7;
  EXPECT_EQ(decode(assemble(p)).face_count(), 1u);
}

// ---- The spec's worked example ----

// The hex dump between "<!-- example: NAME -->" and the closing fence of the next code block.
std::string spec_example(const std::string& name) {
  std::string md = slurp(std::string(QSP_TESTDATA_DIR) + "/../format-spec/qsp_format.md");
  auto at = md.find("<!-- example: " + name + " -->");
  if (at == std::string::npos) return {};
  auto open = md.find("```", at);
  auto body = md.find('\n', open) + 1;
  auto close = md.find("```", body);
  std::string out;
  std::istringstream in(md.substr(body, close - body));
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));  // comments after '#'
    std::istringstream words(line);
    std::string w;
    while (words >> w) out.push_back(static_cast<char>(std::stoi(w, nullptr, 16)));
  }
  return out;
}

TEST(Spec, WorkedExampleDecodes) {
  std::string bytes = spec_example("quad.qsp");
  ASSERT_FALSE(bytes.empty()) << "format-spec/qsp_format.md lost its worked example";
  EXPECT_EQ(bytes, slurp(kGolden + "/quad.qsp"));
  QuadMesh m = decode(bytes);
  EXPECT_EQ(m.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(m.quads, (std::vector<std::uint32_t>{0, 1, 2, 3}));
  EncodeOptions best;
  best.level = kMaxLevel;
  EXPECT_EQ(encode(m, best), bytes);
}

}  // namespace
}  // namespace qsp
