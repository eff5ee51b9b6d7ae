// Hostile input and faults (docs/hardening.md): every broken .qsp class is refused with a typed error
// that says what and where; declared sizes are checked before anything is allocated; memory is
// bounded by the declared content; output is atomic (kill, full disk, unwritable folder); nothing is
// clobbered; every shared mesh round-trips or is refused cleanly; fuzzer findings stay fixed.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "../fuzz/fuzz_check.h"
#include "../fuzz/qsp_craft.h"
#include "codec_encode.h"
#include "codec_sections.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/polymesh.h"
#include "support/cli.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/float32_text.h"
#include "support/load.h"
#include "support/mesh_gen.h"
#include "support/mesh_text.h"
#include "support/openmesh.h"
#include "support/polygon.h"

extern char** environ;

namespace qsp {
namespace {

namespace fs = std::filesystem;
namespace craft = qsp::craft;
using testing::quote;
using testing::run_qsp;

using testing::slurp;
using testing::spit;

std::string cube_qsp(bool keep_order = false) {
  EncodeOptions o;
  o.keep_order = keep_order;
  return encode(testing::load(fs::path(QSP_TESTDATA_DIR) / "cube_4.obj"), o);
}

struct Caught {
  bool thrown = false;
  ErrorCode code = ErrorCode::kInternal;
  std::string message;
};

Caught decode_error(std::string_view bytes, const DecodeLimits& limits = {}) {
  Caught c;
  try {
    (void)decode(bytes, limits);
  } catch (const Error& e) {
    c.thrown = true;
    c.code = e.code();
    c.message = e.what();
  }
  return c;
}

// Asserts `bytes` is refused with `code` and a message containing every one of `parts`.
void expect_refused(std::string_view bytes, ErrorCode code, std::initializer_list<std::string_view> parts,
                    const DecodeLimits& limits = {}) {
  const Caught c = decode_error(bytes, limits);
  ASSERT_TRUE(c.thrown) << "accepted";
  EXPECT_EQ(error_name(c.code), std::string(error_name(code))) << c.message;
  for (std::string_view p : parts)
    EXPECT_NE(c.message.find(p), std::string::npos) << "'" << p << "' not in: " << c.message;
  // inspect() parses the same container and must refuse it the same way.
  try {
    (void)inspect(bytes, limits);
    ADD_FAILURE() << "inspect accepted what decode refuses: " << c.message;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), c.code) << e.what();
  }
}

// Replaces the payload of the first section with `tag`.
std::string with_section(const std::string& file, std::uint8_t tag, const std::string& payload) {
  craft::Parts p;
  EXPECT_TRUE(craft::split(file, p));
  auto secs = craft::sections(p.body);
  for (auto& s : secs)
    if (s.tag == tag) {
      s.payload = payload;
      break;
    }
  return craft::seal(p.major, p.minor, p.encoder, craft::join(secs));
}

std::string section_payload(const std::string& file, std::uint8_t tag) {
  craft::Parts p;
  EXPECT_TRUE(craft::split(file, p));
  for (const auto& s : craft::sections(p.body))
    if (s.tag == tag) return s.payload;
  ADD_FAILURE() << "no section " << int(tag);
  return {};
}

// ---------------------------------------------------------------------------------------------
// Each class of broken container: typed error, what and where.

TEST(HostileQsp, TruncatedAtEveryLength) {
  for (bool keep : {false, true}) {
    const std::string bytes = cube_qsp(keep);
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      SCOPED_TRACE(n);
      expect_refused(std::string_view(bytes).substr(0, n), ErrorCode::kFormat, {"truncated", "byte offset"});
    }
  }
}

TEST(HostileQsp, BadMagic) {
  const std::string good = cube_qsp();
  expect_refused("ply\nformat ascii 1.0\n", ErrorCode::kFormat, {"not a .qsp file", "byte offset 0"});
  expect_refused(std::string("v 0 0 0\n"), ErrorCode::kFormat, {"bad magic"});
  std::string seven = good;
  seven[0] = static_cast<char>(0x09);  // high bit stripped
  expect_refused(seven, ErrorCode::kFormat, {"bad magic", "7-bit"});
  std::string crlf = good;
  crlf.erase(4, 1);  // "\r\n" -> "\n"
  expect_refused(crlf, ErrorCode::kFormat, {"bad magic", "line-ending"});
}

TEST(HostileQsp, NewerOrOlderMajorVersion) {
  craft::Parts p;
  ASSERT_TRUE(craft::split(cube_qsp(), p));
  expect_refused(craft::seal(4, 0, 0, p.body), ErrorCode::kVersion,
                 {"format 4.0", "reads format 3.x", "upgrade qsp", "byte offset 8"});
  expect_refused(craft::seal(255, 3, 0, p.body), ErrorCode::kVersion, {"format 255.3"});
  expect_refused(craft::seal(0, 9, 0, p.body), ErrorCode::kVersion, {"format 0.9"});
  // 1.x and 2.x were development versions: not read.
  expect_refused(craft::seal(2, 2, 0, p.body), ErrorCode::kVersion, {"format 2.2", "development version"});
  expect_refused(craft::seal(1, 3, 0, p.body), ErrorCode::kVersion, {"format 1.3", "development version"});
  // A newer minor of the same major is readable where it uses none of the required sections it may add.
  EXPECT_EQ(decode(craft::seal(kFormatMajor, 200, 0, p.body)).quads, decode(cube_qsp()).quads);
}

TEST(HostileQsp, ChecksumMismatch) {
  const std::string good = cube_qsp();
  for (std::size_t at : {std::size_t{16}, good.size() / 2, good.size() - 9, good.size() - 1}) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x04);
    SCOPED_TRACE(at);
    expect_refused(bad, ErrorCode::kChecksum,
                   {"checksum mismatch", "byte offset " + std::to_string(good.size() - 8)});
  }
}

TEST(HostileQsp, ReservedBitsSet) {
  craft::Parts p;
  ASSERT_TRUE(craft::split(cube_qsp(), p));
  // The encoder byte: bits 4-7 reserved, the level in bits 0-3 at most 9.
  for (int bit = 4; bit < 8; ++bit) {
    expect_refused(craft::seal(kFormatMajor, kFormatMinor, static_cast<std::uint8_t>(1u << bit), p.body),
                   ErrorCode::kFormat, {"reserved encoder byte bits", "byte offset 10"});
  }
  for (int level = 10; level < 16; ++level) {
    expect_refused(craft::seal(kFormatMajor, kFormatMinor, static_cast<std::uint8_t>(level), p.body),
                   ErrorCode::kFormat, {"compression level " + std::to_string(level), "byte offset 10"});
  }
  for (int level = 0; level <= 9; ++level)
    EXPECT_EQ(
        inspect(craft::seal(kFormatMajor, kFormatMinor, static_cast<std::uint8_t>(level), p.body)).level,
        level);
  // The geometry section's tools byte: bit 5 mirror prediction (3.17), which needs a symmetry section;
  // bits 6-7 reserved.
  const std::string file = cube_qsp();
  {
    std::string geometry = section_payload(file, craft::kTagGeometry);
    geometry[0] = static_cast<char>(geometry[0] | 0x20);
    expect_refused(with_section(file, craft::kTagGeometry, geometry), ErrorCode::kFormat,
                   {"geometry section: mirror prediction without a symmetry section", "byte offset"});
  }
  for (int bit = 6; bit < 8; ++bit) {
    std::string geometry = section_payload(file, craft::kTagGeometry);
    geometry[0] = static_cast<char>(geometry[0] | (1 << bit));
    expect_refused(with_section(file, craft::kTagGeometry, geometry), ErrorCode::kFormat,
                   {"geometry section: reserved tool bits", "byte offset"});
  }
  // The counts section's flag byte.
  const std::string good = cube_qsp();
  std::string counts = section_payload(good, craft::kTagCounts);
  counts.back() = static_cast<char>(0x80);
  expect_refused(with_section(good, craft::kTagCounts, counts), ErrorCode::kFormat,
                 {"reserved counts flag", "byte offset"});
}

TEST(HostileQsp, TrailingBytes) {
  const std::string good = cube_qsp();
  expect_refused(good + std::string(1, '\0'), ErrorCode::kFormat,
                 {"1 trailing bytes", "byte offset " + std::to_string(good.size())});
  expect_refused(good + good, ErrorCode::kFormat, {std::to_string(good.size()) + " trailing bytes"});
  // Inside a section: the entropy-coded stream must end exactly where its symbols end.
  std::string topo = section_payload(good, craft::kTagTopology) + std::string(3, '\0');
  expect_refused(with_section(good, craft::kTagTopology, topo), ErrorCode::kFormat,
                 {"topology", "byte offset"});
  std::string counts = section_payload(good, craft::kTagCounts) + "x";
  expect_refused(with_section(good, craft::kTagCounts, counts), ErrorCode::kFormat,
                 {"counts section has 1 unexpected bytes"});
}

TEST(HostileQsp, CountsLargerThanTheFile) {
  const std::string good = cube_qsp();
  craft::Parts p;
  ASSERT_TRUE(craft::split(good, p));
  // The size field claims more than there is (the file was cut).
  std::string longer = good;
  ASSERT_NE(static_cast<std::uint8_t>(longer[11]) & 0x7F, 0x7F);
  longer[11] = static_cast<char>(static_cast<std::uint8_t>(longer[11]) + 1);
  expect_refused(longer, ErrorCode::kFormat,
                 {"truncated: header declares " + std::to_string(good.size() + 1) + " bytes, file has " +
                  std::to_string(good.size())});
  // A section length beyond the end of the body.
  auto secs = craft::sections(p.body);
  std::string body =
      p.body.substr(0, secs.back().offset) + std::string(1, static_cast<char>(secs.back().tag));
  craft::put_varint(body, secs.back().payload.size() + 10);
  body += secs.back().payload;
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, body), ErrorCode::kFormat,
                 {"declares " + std::to_string(secs.back().payload.size() + 10) + " bytes but only", "remain",
                  "byte offset"});
  std::string huge_len = std::string(1, static_cast<char>(craft::kTagGeometry)) + "\xff\xff\xff\xff\x0f";
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, p.body.substr(0, secs.back().offset) + huge_len),
                 ErrorCode::kFormat, {"declares 4294967295 bytes but only 0 remain"});
  // Counts beyond the format, beyond the limits, or inconsistent with each other.
  auto with_counts = [&](std::uint64_t v, std::uint64_t f, std::uint64_t c, std::uint64_t u) {
    return with_section(good, craft::kTagCounts, craft::counts_payload(v, f, c, u));
  };
  expect_refused(with_counts(kMaxVertices + 1, 96, 1, 0), ErrorCode::kFormat,
                 {"vertex count exceeds the format's 2^31 - 1"});
  expect_refused(with_counts(98, kMaxFaces + 1, 1, 0), ErrorCode::kFormat,
                 {"face count exceeds the format's 2^29 - 1"});
  expect_refused(with_counts(DecodeLimits{}.max_vertices + 1, 96, 1, 0), ErrorCode::kLimit,
                 {"vertex count " + std::to_string(DecodeLimits{}.max_vertices + 1) + " exceeds the limit",
                  "byte offset"});
  expect_refused(with_counts(98, DecodeLimits{}.max_faces + 1, 1, 0), ErrorCode::kLimit,
                 {"face count", "exceeds the limit"});
  expect_refused(with_counts(98, 96, 97, 0), ErrorCode::kFormat, {"more components than faces"});
  expect_refused(with_counts(98, 96, 1, 99), ErrorCode::kFormat,
                 {"more unreferenced vertices than vertices"});
  expect_refused(with_counts(99, 96, 1, 0), ErrorCode::kFormat, {"topology describes", "byte offset"});
  expect_refused(with_counts(98, 97, 1, 0), ErrorCode::kFormat, {"byte offset"});
  expect_refused(with_counts(98, 96, 2, 0), ErrorCode::kFormat, {"byte offset"});
  DecodeLimits tight;
  tight.max_vertices = 97;
  expect_refused(good, ErrorCode::kLimit, {"vertex count 98 exceeds the limit 97"}, tight);
}

TEST(HostileQsp, UnknownAndMissingSections) {
  const std::string good = cube_qsp();
  craft::Parts p;
  ASSERT_TRUE(craft::split(good, p));
  auto secs = craft::sections(p.body);
  ASSERT_EQ(secs.size(), 3u);
  // Optional sections (tag bit 7) this decoder does not know are skipped; they come after the required
  // ones (sections are in tag order), and before them they are refused.
  auto more = secs;
  more.push_back(craft::SectionView{0x85, 0, 0, "future data"});
  more.push_back(craft::SectionView{0xF0, 0, 0, ""});
  EXPECT_EQ(decode(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(more))).quads, decode(good).quads);
  for (std::size_t at = 0; at < secs.size(); ++at) {
    auto early = secs;
    early.insert(early.begin() + static_cast<std::ptrdiff_t>(at),
                 craft::SectionView{0x85, 0, 0, "future data"});
    expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(early)), ErrorCode::kFormat,
                   {"is missing", "byte offset"});
  }
  // An unknown required section is refused: "upgrade qsp" in a file of a newer minor version, a format
  // error in one of this version. So are missing, repeated and reordered ones.
  auto unknown = secs;
  unknown.push_back({0x10, 0, 0, "x"});
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(unknown)), ErrorCode::kFormat,
                 {"section 0x10 is required but unknown", "byte offset"});
  expect_refused(craft::seal(kFormatMajor, kFormatMinor + 1, 0, craft::join(unknown)), ErrorCode::kVersion,
                 {"section 0x10 is required but unknown", "upgrade qsp", "byte offset"});
  for (std::size_t drop = 0; drop < secs.size(); ++drop) {
    auto fewer = secs;
    fewer.erase(fewer.begin() + static_cast<std::ptrdiff_t>(drop));
    expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(fewer)), ErrorCode::kFormat,
                   {"byte offset"});
  }
  auto twice = secs;
  twice.insert(twice.begin() + 1, secs[0]);
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(twice)), ErrorCode::kFormat,
                 {"byte offset"});
  auto swapped = secs;
  std::swap(swapped[1], swapped[2]);
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, craft::join(swapped)), ErrorCode::kFormat,
                 {"byte offset"});
  expect_refused(craft::seal(kFormatMajor, kFormatMinor, 0, ""), ErrorCode::kFormat,
                 {"required section 1 (counts) is missing"});
}

// Small files of every component kind and mode, for the exhaustive corruption sweeps.
std::vector<std::pair<std::string, std::string>> sweep_files() {
  std::vector<std::pair<std::string, std::string>> out;
  QuadMesh grid = testing::grid(3, 2);
  grid.positions.insert(grid.positions.end(), {0.5f, 7.25f, -1e-3f});  // an unreferenced vertex
  QuadMesh mixed = testing::periodic(5, 2, false, 0);
  testing::append(mixed, testing::periodic(4, 3, true, 1), 10);
  testing::append(mixed, testing::polyomino(std::vector<std::string>{"##.", ".##"}), 20);
  EncodeOptions keep, quant;
  keep.keep_order = true;
  quant.quantize_bits = 9;
  out.emplace_back("grid", encode(grid));
  out.emplace_back("grid keep-order", encode(grid, keep));
  out.emplace_back("mixed", encode(mixed));
  out.emplace_back("mixed quantized", encode(mixed, quant));
  // Every current golden: the geometry tools (normal chaining, logistic mixing, cell shapes, repeats),
  // both coding orders, quantized and keep-order files, every component kind.
  for (const auto& e : fs::directory_iterator(fs::path(QSP_TESTDATA_DIR) / "golden"))
    if (e.path().extension() == ".qsp")
      out.emplace_back("golden " + e.path().filename().string(), read_file_bytes(e.path().string()));
  std::sort(out.begin(), out.end());
  return out;
}

// A file that decodes must give a valid mesh that round-trips; one that does not, a typed error.
void expect_clean(const std::string& bytes, const std::string& what) {
  QuadMesh m;
  try {
    m = decode(bytes);
  } catch (const Error& e) {
    EXPECT_NE(e.code(), ErrorCode::kInternal) << what << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << what << ": " << e.what();
    return;
  }
  try {
    (void)build_adjacency(m);
  } catch (const Error& e) {
    ADD_FAILURE() << what << ": decoded an invalid mesh: " << e.what();
    return;
  }
  fuzz::check_round_trip(m, what.c_str());
}

// Every single-bit flip and every cut of the body, re-sealed so the checksum does not hide it: the
// section parsers, entropy decoders and partition checks see it all.
TEST(HostileQsp, EveryResealedBitFlipAndCutIsCleanOrValid) {
  for (const auto& [name, file] : sweep_files()) {
    craft::Parts p;
    ASSERT_TRUE(craft::split(file, p));
    for (std::size_t i = 0; i < p.body.size(); ++i) {
      for (int b = 0; b < 8; ++b) {
        std::string body = p.body;
        body[i] = static_cast<char>(body[i] ^ (1 << b));
        expect_clean(craft::seal(p.major, p.minor, 0, body),
                     name + " flip " + std::to_string(i) + "." + std::to_string(b));
      }
      expect_clean(craft::seal(p.major, p.minor, 0, p.body.substr(0, i)), name + " cut " + std::to_string(i));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Limits.

struct ChildRun {
  int exit_code = -1;  // -signal if killed
};

// Runs qsp with `args` (stdout to `out`, stderr to /dev/null) as its own process.
ChildRun run_child(const std::vector<std::string>& args, const std::string& out = "/dev/null") {
  std::vector<char*> argv;
  std::string exe = QSP_CLI_PATH;
  argv.push_back(exe.data());
  std::vector<std::string> copy = args;
  for (auto& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  ChildRun r;
  if (posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ) != 0) return r;
  posix_spawn_file_actions_destroy(&fa);
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  return r;
}

// Each test's own folder (support/files.h), which others (a dropped-privilege run) may enter; folders
// a test made unwritable are made writable again before it goes.
class OpenDirTest : public testing::TempDirTest {
 protected:
  void SetUp() override { fs::permissions(dir_, fs::perms::all); }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    for (const auto& e : fs::recursive_directory_iterator(dir_, ec)) {
      if (e.is_directory()) fs::permissions(e.path(), fs::perms::owner_all, fs::perm_options::add, ec);
    }
  }
  // Names in a folder, sorted (to show leftovers).
  static std::vector<std::string> listing(const fs::path& d) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(d)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

using Limits = OpenDirTest;

// Files of a few dozen bytes that declare a huge mesh: refused at once, with no large allocation.
TEST_F(Limits, TinyFileDeclaringAHugeMeshIsRefusedBeforeAllocating) {
  const std::string good = cube_qsp();
  const std::string empty_topology = encode_topology({});
  TopologyCode torus;
  torus.kind = ComponentKind::kTorus;
  torus.a = 8192, torus.b = 8192;  // 2^26 faces, all in a few bytes of topology
  const std::string torus_topology = encode_topology(std::vector<TopologyCode>{torus});
  const std::uint64_t big = DecodeLimits{}.max_faces;  // at the limit: accepted by the counts check
  auto file = [](const std::string& counts, const std::string& topo, const std::string& geo) {
    return craft::seal(kFormatMajor, kFormatMinor, 0,
                       craft::section(craft::kTagCounts, counts) + craft::section(craft::kTagTopology, topo) +
                           craft::section(craft::kTagGeometry, geo));
  };
  const std::string small_geometry = section_payload(good, craft::kTagGeometry);
  struct Case {
    const char* what;
    std::string bytes;
    ErrorCode code;
  };
  const std::vector<Case> cases = {
      {"2^40 faces", file(craft::counts_payload(4, std::uint64_t{1} << 40, 1, 0), "", ""),
       ErrorCode::kFormat},
      {"vertices past the limit", file(craft::counts_payload(big + 1, 1, 1, 0), "", ""), ErrorCode::kLimit},
      {"2^26 components",
       file(craft::counts_payload(big, big, big, 0), std::string(12, '\0'), small_geometry),
       ErrorCode::kFormat},
      {"2^26 unreferenced vertices",
       file(craft::counts_payload(big, 0, 0, big), empty_topology, small_geometry), ErrorCode::kFormat},
      {"8192 x 8192 torus", file(craft::counts_payload(big, big, 1, 0), torus_topology, small_geometry),
       ErrorCode::kFormat},
  };
  const std::string reference = p("small.qsp");
  spit(reference, good);
  const ChildRun base = run_child({"decompress", reference, "-"});
  ASSERT_EQ(base.exit_code, 0);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    EXPECT_LT(c.bytes.size(), 200u);
    const Caught e = decode_error(c.bytes);
    ASSERT_TRUE(e.thrown);
    EXPECT_EQ(error_name(e.code), std::string(error_name(c.code))) << e.message;
    EXPECT_NE(e.message.find("byte offset"), std::string::npos) << e.message;
    spit(p("bomb.qsp"), c.bytes);
    for (const std::string command : {"decompress", "stats"}) {
      std::vector<std::string> args = {command, p("bomb.qsp")};
      if (command == "decompress") args.push_back("-");
      // Its memory and time are measured in tools/bench/bench_limits.py, never here.
      EXPECT_EQ(run_child(args).exit_code, 1) << command;
    }
  }
}

// The decoder's working memory against the spec's bound (format-spec/qsp_format.md, "Limits and
// memory") is measured by tools/bench/bench_limits.py, never in a unit test.

// The decoder refuses a file whose geometry section is too short for its vertex count (src/codec.cpp:
// at most 1536 vertices per byte; the coder's floor is ~853). The cheapest geometry there is (every
// coordinate a repeat of rank 0) must stay well inside that, or valid files would be refused: if the
// geometry coder ever codes a vertex in fewer than 6 adaptive decisions, this fails and the bound must move.
TEST(LimitsBound, CheapestGeometryFitsTheContentBound) {
  QuadMesh flat = testing::grid(300, 200);
  QuadMesh zero = flat;
  std::fill(zero.positions.begin(), zero.positions.end(), 0.0f);
  EncodeOptions quant;
  quant.quantize_bits = 1;
  // The costly tools (forced: the encoder would not choose them above 32768 vertices): logistic
  // decisions are clamped to the bit models' most skewed probability, so they cost no less.
  const EncodeTuning costly{geometry_tool::kCellShapes | geometry_tool::kLogisticMixing |
                            geometry_tool::kValueRepeats};
  for (const auto& [name, bytes] : {std::pair<std::string, std::string>{"flat grid", encode(flat)},
                                    {"all zero", encode(zero)},
                                    {"all zero, 1 bit", encode(zero, quant)},
                                    {"flat grid, costly tools", encode_tuned(flat, {}, costly)},
                                    {"all zero, costly tools", encode_tuned(zero, {}, costly)},
                                    {"all zero, 1 bit, costly tools", encode_tuned(zero, quant, costly)}}) {
    const std::string geometry = section_payload(bytes, craft::kTagGeometry);
    const double per_byte = double(flat.vertex_count()) / double(geometry.size());
    std::printf("%s: %.0f vertices per geometry byte\n", name.c_str(), per_byte);
    EXPECT_LT(per_byte, 2048.0 / 1.5) << name;  // kMaxVerticesPerGeometryByte in src/codec.cpp
    EXPECT_EQ(decode(bytes).vertex_count(), flat.vertex_count()) << name;
  }
}

TEST_F(Limits, CliLimitFlagsOverrideTheDefaults) {
  spit(p("c.qsp"), cube_qsp());
  auto r = run_qsp("decompress --max-faces 95 " + quote(p("c.qsp")) + " " + quote(p("c.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("face count 96 exceeds the limit 95"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(p("c.qsp")), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("c.obj")));
  r = run_qsp("decompress --max-vertices 10 " + quote(p("c.qsp")) + " " + quote(p("c.obj")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("vertex count 98 exceeds the limit 10"), std::string::npos) << r.err;
  r = run_qsp("decompress --max-faces 96 --max-vertices 98 " + quote(p("c.qsp")) + " " + quote(p("c.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run_qsp("decompress --help");
  EXPECT_NE(r.out.find("--max-faces"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// CLI failures: exit code and a message that says what and where; nothing written.

using CliFailures = OpenDirTest;

TEST_F(CliFailures, EveryInvalidMeshIsRefusedByCompress) {
  int n = 0, stored = 0;
  for (const fs::path& mesh : testing::invalid_meshes()) {
    SCOPED_TRACE(mesh.string());
    auto expect = testing::read_expect(fs::path(mesh).replace_extension(".expect"));
    const std::string out = p(mesh.filename().string() + ".qsp");
    const auto r = run_qsp("compress --positions-only " + quote(mesh.string()) + " " + quote(out));
    // Polygon meshes (format 3.1): what the quad readers refuse as not quads, non-manifold or mis-oriented
    // compress stores; a face of two corners is still not a mesh.
    const std::string code = expect.at("code");
    if (code == "not-quad" || code == "non-manifold" || code == "orientation") {
      if (mesh.filename() == "obj_not_quad.obj") {
        expect["message"] =
            "obj_not_quad.obj:12: face has 2 vertices; a face needs at least 3 distinct vertices";
      } else {
        EXPECT_EQ(r.exit_code, 0) << r.err;
        const std::string text = testing::slurp(mesh);
        const auto ext = mesh.extension();
        const testing::TextMesh in = ext == ".ply"   ? testing::parse_ply_bytes(text)
                                     : ext == ".off" ? testing::parse_off_text(text)
                                                     : testing::parse_obj_text(text);
        EXPECT_EQ(decode_polygons(testing::slurp(out)).face_count(), in.faces.size());
        fs::remove(out);
        ++stored;
        continue;
      }
    }
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err.rfind("qsp: error: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(expect.at("message")), std::string::npos)
        << r.err << "\nexpected: " << expect.at("message");
    EXPECT_EQ(listing(dir_), std::vector<std::string>{}) << "output left behind";
    ++n;
  }
  EXPECT_GE(n, 45);
  EXPECT_EQ(stored, 6);  // off_not_quad, ply_triangle and the four of topology/
}

TEST_F(CliFailures, CorruptQspNamesTheFileAndTheOffset) {
  const std::string good = cube_qsp();
  craft::Parts parts;
  ASSERT_TRUE(craft::split(good, parts));
  std::string flipped = good;
  flipped[good.size() / 2] ^= 1;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {good.substr(0, 30), "truncated"},
      {"PK\x03\x04 not a qsp", "bad magic"},
      {craft::seal(4, 1, 0, parts.body), "format 4.1"},
      {flipped, "checksum mismatch"},
      {craft::seal(kFormatMajor, kFormatMinor, 0x40, parts.body), "reserved encoder byte"},
      {good + "xyz", "3 trailing bytes"},
      {with_section(good, craft::kTagCounts, craft::counts_payload(99, 96, 1, 0)), "topology describes"},
  };
  for (const auto& [bytes, what] : cases) {
    SCOPED_TRACE(what);
    spit(p("in.qsp"), bytes);
    const auto r = run_qsp("decompress " + quote(p("in.qsp")) + " " + quote(p("out.obj")));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(r.err.rfind("qsp: error: " + p("in.qsp") + ": ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("byte offset"), std::string::npos) << r.err;
    EXPECT_EQ(listing(dir_), std::vector<std::string>{"in.qsp"});
  }
}

// Exit codes are derived from the error type in one place (tools/qsp/main.cpp, README):
// 0 ok, 1 bad input or refused, 2 usage, 3 I/O, 4 internal.
TEST_F(CliFailures, ExitCodesFollowTheErrorType) {
  spit(p("c.qsp"), cube_qsp());
  EXPECT_EQ(run_qsp("decompress " + quote(p("missing.qsp")) + " " + quote(p("x.obj"))).exit_code, 3);
  EXPECT_EQ(run_qsp("compress " + quote(p("missing.obj")) + " " + quote(p("x.qsp"))).exit_code, 3);
  fs::create_directory(p("d.obj"));
  EXPECT_EQ(run_qsp("compress " + quote(p("d.obj")) + " " + quote(p("x.qsp"))).exit_code, 3);
  EXPECT_EQ(run_qsp("decompress " + quote(p("c.qsp")) + " -o " + quote(p("x.stl"))).exit_code, 1);
  EXPECT_EQ(run_qsp("compress " + quote(p("c.qsp")) + " " + quote(p("x.qsp"))).exit_code, 1);
  EXPECT_EQ(run_qsp("decompress").exit_code, 2);
  EXPECT_EQ(run_qsp("decompress --no-such-flag " + quote(p("c.qsp"))).exit_code, 2);
  EXPECT_EQ(run_qsp("frobnicate").exit_code, 2);
  const auto r = run_qsp("decompress " + quote(p("missing.qsp")) + " " + quote(p("x.obj")));
  EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(p("missing.qsp")), std::string::npos) << r.err;
}

// ---------------------------------------------------------------------------------------------
// Atomic output.

using AtomicOutput = OpenDirTest;

// A compressed mesh big enough that decoding and writing its OBJ (7 MB) take a while.
std::string big_qsp() {
  static const std::string bytes = encode(testing::grid(500, 400));
  return bytes;
}

// The CLI's test seam (QSP_TEST_STOP_BEFORE_RENAME=1) stops the process with the output complete in
// its temporary file, just before it gets its name: a kill there is known to land inside the window.
// It must leave nothing (or, with -f, the old file untouched); continued instead, the run finishes.
// With and without --sync (which only adds the flushes before the name).
TEST_F(AtomicOutput, KilledBeforeTheRenameLeavesNoPartialOrTemporaryFile) {
  spit(p("big.qsp"), big_qsp());
  fs::create_directory(p("ref"));
  ASSERT_EQ(run_child({"decompress", p("big.qsp"), p("ref/out.obj")}).exit_code, 0);
  const std::string expected = slurp(p("ref/out.obj"));
  fs::remove_all(p("ref"));
  for (const bool sync : {false, true})  // flushed to disk before the name, or not: atomic either way
    for (const bool force : {false, true}) {
      for (const bool kill : {true, false}) {
        SCOPED_TRACE(std::string(force ? "-f" : "no -f") + (sync ? " --sync" : "") +
                     (kill ? ", killed" : ", continued"));
        if (force) spit(p("out.obj"), "old");
        std::string exe = QSP_CLI_PATH, a1 = "decompress", a2 = p("big.qsp"), a3 = p("out.obj"), f = "-f",
                    s = "--sync";
        std::vector<char*> argv = {exe.data(), a1.data()};
        if (force) argv.push_back(f.data());
        if (sync) argv.push_back(s.data());
        argv.insert(argv.end(), {a2.data(), a3.data(), nullptr});
        std::vector<std::string> env_text = {"QSP_TEST_STOP_BEFORE_RENAME=1"};
        for (char** e = environ; *e; ++e) env_text.emplace_back(*e);
        std::vector<char*> env;
        for (auto& e : env_text) env.push_back(e.data());
        env.push_back(nullptr);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), env.data()), 0);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, WUNTRACED), pid);
        ASSERT_TRUE(WIFSTOPPED(status)) << "the seam did not stop qsp (status " << status << ")";
        // Stopped inside the window: the temporary is open (unnamed, or hidden), the output not there yet.
        bool temporary_open = false;
        for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd")) {
          std::error_code ec;
          const std::string target = fs::read_symlink(e.path(), ec).string();
          temporary_open |=
              target.rfind(dir_.string() + "/", 0) == 0 && target.find("big.qsp") == std::string::npos;
        }
        EXPECT_TRUE(temporary_open) << "no temporary file open in " << dir_;
        const std::vector<std::string> before =
            force ? std::vector<std::string>{"big.qsp", "out.obj"} : std::vector<std::string>{"big.qsp"};
        EXPECT_EQ(listing(dir_), before);
        ::kill(pid, kill ? SIGKILL : SIGCONT);
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        if (kill) {
          EXPECT_TRUE(WIFSIGNALED(status)) << status;
          EXPECT_EQ(listing(dir_), before) << "a kill before the rename left something behind";
          if (force) {
            EXPECT_EQ(slurp(p("out.obj")), "old");
          }
        } else {
          EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
          EXPECT_EQ(listing(dir_), (std::vector<std::string>{"big.qsp", "out.obj"}));
          EXPECT_TRUE(slurp(p("out.obj")) == expected) << "complete output differs";
        }
        fs::remove(p("out.obj"));
      }
    }
}

// A write that fails part-way (file size limit: EFBIG, as a full disk gives ENOSPC) is reported, the
// temporary file is removed, nothing appears; a process killed by SIGXFSZ leaves nothing either.
TEST_F(AtomicOutput, WriteErrorRemovesTheTemporaryFile) {
  spit(p("big.qsp"), big_qsp());
  const std::string cmd = std::string("prlimit --fsize=65536 ") + quote(QSP_CLI_PATH) + " decompress " +
                          quote(p("big.qsp")) + " " + quote(p("out.obj"));
  auto r = run_qsp("--version");  // make sure the binary runs at all
  ASSERT_EQ(r.exit_code, 0);
  const std::string err = p("err.txt");
  int status = std::system(("sh -c " + quote("trap '' XFSZ; exec " + cmd) + " 2>" + quote(err)).c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << status;
  const std::string message = slurp(err);
  fs::remove(err);
  EXPECT_NE(message.find(p("out.obj") + ": cannot write: File too large"), std::string::npos) << message;
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"big.qsp"});
  status = std::system(("sh -c " + quote("exec " + cmd) + " 2>/dev/null").c_str());
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(listing(dir_), std::vector<std::string>{"big.qsp"}) << "killed by SIGXFSZ";
}

TEST_F(AtomicOutput, FullDeviceGivesAClearError) {
  spit(p("c.qsp"), cube_qsp());
  // Standard output on a full device.
  int status = std::system(
      (quote(QSP_CLI_PATH) + " decompress " + quote(p("c.qsp")) + " - >/dev/full 2>" + quote(p("err.txt")))
          .c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3);
  EXPECT_NE(slurp(p("err.txt")).find("No space left on device"), std::string::npos) << slurp(p("err.txt"));
  fs::remove(p("err.txt"));
  // A full device named as OUT with -f is written in place (never replaced by a regular file).
  if (::geteuid() != 0) GTEST_SKIP() << "mknod of a private /dev/full needs root";
  ASSERT_EQ(::mknod(p("full").c_str(), S_IFCHR | 0666, makedev(1, 7)), 0) << std::strerror(errno);
  auto r = run_qsp("decompress -f " + quote(p("c.qsp")) + " -o " + quote(p("full")) + " ");
  EXPECT_EQ(r.exit_code, 1);  // "full" has no .obj/.off extension
  ASSERT_EQ(::rename(p("full").c_str(), p("full.obj").c_str()), 0);
  r = run_qsp("decompress -f " + quote(p("c.qsp")) + " -o " + quote(p("full.obj")));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  struct stat st {};
  ASSERT_EQ(::lstat(p("full.obj").c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device node was replaced";
  EXPECT_EQ(listing(dir_), (std::vector<std::string>{"c.qsp", "full.obj"}));
  // Without -f an existing device is refused like any existing file.
  r = run_qsp("decompress " + quote(p("c.qsp")) + " -o " + quote(p("full.obj")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
}

TEST_F(AtomicOutput, UnwritableOrMissingFolderGivesAClearError) {
  spit(p("c.qsp"), cube_qsp());
  fs::permissions(p("c.qsp"), fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  auto r = run_qsp("decompress " + quote(p("c.qsp")) + " " + quote(p("no/such/dir/out.obj")));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("No such file or directory"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(p("no/such/dir")), std::string::npos) << r.err;
  fs::create_directory(p("ro"));
  fs::permissions(p("ro"), fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                               fs::perms::group_exec | fs::perms::others_read | fs::perms::others_exec);
  // root ignores folder permissions: drop to nobody for this run.
  const std::string as_user = ::geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
  const int status = std::system((as_user + quote(QSP_CLI_PATH) + " decompress " + quote(p("c.qsp")) + " " +
                                  quote(p("ro/out.obj")) + " 2>" + quote(p("err.txt")))
                                     .c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << status;
  const std::string message = slurp(p("err.txt"));
  EXPECT_NE(message.find(p("ro/out.obj")), std::string::npos) << message;
  EXPECT_NE(message.find("Permission denied"), std::string::npos) << message;
  EXPECT_TRUE(fs::is_empty(p("ro")));
}

TEST_F(AtomicOutput, ExistingFilesAreNeverClobberedWithoutForce) {
  spit(p("c.qsp"), cube_qsp());
  fs::copy_file(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj", p("cube.obj"));
  spit(p("out.obj"), "precious\n");
  spit(p("out.qsp"), "precious\n");
  fs::create_symlink(p("elsewhere.txt"), p("dangling.obj"));
  for (const std::string& cmd : {"decompress " + quote(p("c.qsp")) + " " + quote(p("out.obj")),
                                 "decompress " + quote(p("c.qsp")) + " -o " + quote(p("dangling.obj")),
                                 "compress " + quote(p("cube.obj")) + " " + quote(p("out.qsp"))}) {
    SCOPED_TRACE(cmd);
    const auto r = run_qsp(cmd);
    EXPECT_EQ(r.exit_code, 3);
    EXPECT_NE(r.err.find("already exists"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(p("out.obj")), "precious\n");
  EXPECT_EQ(slurp(p("out.qsp")), "precious\n");
  EXPECT_FALSE(fs::exists(p("elsewhere.txt")));
  EXPECT_EQ(run_qsp("decompress -f " + quote(p("c.qsp")) + " " + quote(p("out.obj"))).exit_code, 0);
  EXPECT_EQ(encode(read_mesh_file(p("out.obj"))), slurp(p("c.qsp")));
  EXPECT_EQ(listing(dir_),
            (std::vector<std::string>{"c.qsp", "cube.obj", "dangling.obj", "out.obj", "out.qsp"}));
}

TEST_F(AtomicOutput, TheInputIsNeverOverwrittenEvenWithForce) {
  fs::copy_file(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj", p("cube.obj"));
  const std::string before = slurp(p("cube.obj"));
  spit(p("c.qsp"), cube_qsp());
  fs::create_directory(p("sub"));
  fs::create_hard_link(p("cube.obj"), p("hard.obj"));
  fs::create_symlink(p("cube.obj"), p("soft.obj"));
  fs::create_hard_link(p("c.qsp"), p("c_link.obj"));
  for (const std::string& cmd : {"compress -f " + quote(p("cube.obj")) + " " + quote(p("cube.obj")),
                                 "compress -f " + quote(p("cube.obj")) + " -o " + quote(p("sub/../cube.obj")),
                                 "compress -f " + quote(p("cube.obj")) + " -o " + quote(p("hard.obj")),
                                 "compress -f " + quote(p("cube.obj")) + " -o " + quote(p("soft.obj")),
                                 "compress -f " + quote(p("soft.obj")) + " -o " + quote(p("cube.obj")),
                                 "decompress -f " + quote(p("c.qsp")) + " " + quote(p("c_link.obj"))}) {
    SCOPED_TRACE(cmd);
    const auto r = run_qsp(cmd);
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
  }
  EXPECT_EQ(slurp(p("cube.obj")), before);
  EXPECT_EQ(slurp(p("c.qsp")), cube_qsp());
  EXPECT_TRUE(fs::is_symlink(p("soft.obj")));
}

// ---------------------------------------------------------------------------------------------
// Coordinates float32 cannot keep: kept as float64 by compress, never rounded without a word.

using Float32Cli = OpenDirTest;

TEST_F(Float32Cli, CompressKeepsThemExactlyRoundsOnRequestAndRefusesBeyondFloat64) {
  const std::string in = p("digits.obj"), q = p("digits.qsp"), out = p("out.obj");
  testing::spit(in, "v 0 0 0\nv 1 0 0\nv 1 0.1234567891234 0\nv 0 1 0\nf 1 2 3 4\n");
  auto r = run_qsp("compress " + quote(in) + " " + quote(q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  ASSERT_EQ(run_qsp("decompress -f " + quote(q) + " " + quote(out)).exit_code, 0);
  EXPECT_NE(testing::slurp(out).find(" 0.1234567891234 "), std::string::npos) << testing::slurp(out);
  r = run_qsp("compress -f --float32 " + quote(in) + " " + quote(q));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rounded 1 coordinate to float32 (--float32)"), std::string::npos) << r.err;
  r = run_qsp("compress -q --float32 -f " + quote(in) + " " + quote(q));
  EXPECT_EQ(r.err, "");  // -q: no note
  ASSERT_EQ(run_qsp("decompress -f " + quote(q) + " " + quote(out)).exit_code, 0);
  EXPECT_NE(testing::slurp(out).find(" 0.12345679 "), std::string::npos);
  // More digits than float64 holds: refused, naming the vertex and the value, until rounded on request.
  const std::string wide = p("wide.obj");
  testing::spit(wide, "v 0 0 0\nv 1 0 0\nv 1 0.12345678901234567891 0\nv 0 1 0\nf 1 2 3 4\n");
  r = run_qsp("compress " + quote(wide) + " " + quote(p("wide.qsp")));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(wide + ": vertex 2 has 1.2345678901234567891e-1, more digits than float64 holds"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--float32"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("wide.qsp")));
  EXPECT_EQ(run_qsp("compress --float32 " + quote(wide) + " " + quote(p("wide.qsp"))).exit_code, 0);
  // Quantizing changes positions by request: no refusal.
  EXPECT_EQ(run_qsp("compress -f --quantize 12 " + quote(in) + " " + quote(q)).exit_code, 0);
  // reorder writes IN's positions: the same rule (kept as float64, rounded on request, refused beyond).
  fs::remove(out);
  r = run_qsp("reorder --like " + quote(in) + " " + quote(in) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing::slurp(out).find(" 0.1234567891234 "), std::string::npos) << testing::slurp(out);
  r = run_qsp("reorder -f --float32 --like " + quote(in) + " " + quote(in) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("rounded 1 coordinate to float32 (--float32)"), std::string::npos) << r.err;
  EXPECT_NE(testing::slurp(out).find(" 0.12345679 "), std::string::npos);
  r = run_qsp("reorder -f --like " + quote(wide) + " " + quote(wide) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(wide + ": vertex 2 has 1.2345678901234567891e-1, more digits than float64 holds"),
            std::string::npos)
      << r.err;
  // layout's outputs are exports for other tools: a warning, not a refusal.
  r = run_qsp("layout " + quote(in) + " -o " + quote(p("layout.obj")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: " + in + ":3: vertex 2 has 0.1234567891234"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("layout writes float32 positions"), std::string::npos) << r.err;
  // A float32's own shortest text (8 digits here), or 17 digits printing the float64 whose shortest text that
  // is, are kept.
  testing::spit(in, "v 0.1 0.12345679 0\nv 1 0 0.10000000000000001\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
  r = run_qsp("compress -f " + quote(in) + " " + quote(q));
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// ---------------------------------------------------------------------------------------------
// Real meshes through the CLI: exact round trip or a clear refusal, never a crash.

using SharedMeshesCli = OpenDirTest;

// The --drop list a mesh file needs, found from its text by the rules README states (not by qsp's reader):
// OBJ by statement (vt, v/vt: uv; vn, v//vn: normal; v x y z r g b [a]: color; o, g: group; usemtl,
// mtllib: material; s: smoothing; t with as many arguments as it declares: tag; v x y z w, a malformed t
// and, unless `lines_kept` (compress keeps them), every other statement: extra; comments never), OFF by its
// header's ST, C and N and by face colours.
std::string expected_drop(const fs::path& f, unsigned kept = 0, bool lines_kept = false) {
  const std::string text = slurp(f);
  unsigned kinds = 0;
  if (f.extension() == ".off") {
    const testing::TextMesh m = testing::parse_off_text(text);
    const std::string key = testing::split_words(testing::logical_lines(text).front().second).at(0);
    const std::string prefix = key.substr(0, key.find("OFF"));
    if (prefix.find("ST") != std::string::npos) kinds |= kCategoryUv;
    if (prefix.find('C') != std::string::npos) kinds |= kCategoryColor;
    if (prefix.find('N') != std::string::npos) kinds |= kCategoryNormal;
    for (const auto& extra : m.face_extra)
      if (!extra.empty()) kinds |= kCategoryColor;
    return category_list(kinds & ~kept);
  }
  for (const auto& [number, raw] : testing::logical_lines(text)) {
    const std::vector<std::string> w = testing::split_words(raw.substr(0, raw.find('#')));
    if (w.empty()) continue;
    const std::string& k = w[0];
    if (k == "v") {
      kinds |= w.size() == 5 ? kCategoryExtra : w.size() > 5 ? kCategoryColor : 0u;
    } else if (k == "vt" || k == "vn") {
      kinds |= k == "vt" ? kCategoryUv : kCategoryNormal;
    } else if (k == "f") {
      for (std::size_t i = 1; i < w.size(); ++i) {
        const std::size_t slash = w[i].find('/');
        if (slash == std::string::npos) continue;
        const std::size_t second = w[i].find('/', slash + 1);
        if (second != slash + 1) kinds |= kCategoryUv;
        if (second != std::string::npos) kinds |= kCategoryNormal;
      }
    } else if (k == "o" || k == "g") {
      kinds |= kCategoryGroup;
    } else if (k == "usemtl" || k == "mtllib") {
      kinds |= kCategoryMaterial;
    } else if (k == "s") {
      kinds |= kCategorySmoothing;
    } else if (k == "t") {
      long n[3] = {};
      const bool counts = w.size() >= 3 && std::sscanf(w[2].c_str(), "%ld/%ld/%ld", &n[0], &n[1], &n[2]) == 3;
      kinds |= counts && static_cast<std::size_t>(n[0] + n[1] + n[2]) + 3 == w.size() ? kCategoryTag
                                                                                      : kCategoryExtra;
    } else if (!lines_kept) {  // a line kept as text (compress keeps them: format 3.7)
      kinds |= kCategoryExtra;
    }
  }
  return category_list(kinds & ~kept);
}

// An OBJ file's face labels, read here rather than by qsp: per face its o, g, usemtl and s (the words
// after the keyword joined by single spaces; "-" before the first statement of a kind), then one entry
// per mtllib statement and one per subdivision tag (its floats by value: "5.0" is written back "5"); each
// face also lists its corners' normals by value (positive `vn` indices). What
// decompress must give back, face for face under --keep-order.
std::vector<std::string> obj_face_labels(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> out, libraries, normals;
  std::string current[4] = {"-", "-", "-", "-"};
  const char* keywords[4] = {"o", "g", "usemtl", "s"};
  for (std::string raw; std::getline(in, raw);) {
    const std::vector<std::string> w = testing::split_words(raw.substr(0, raw.find('#')));
    if (w.empty()) continue;
    std::string rest;
    for (std::size_t i = 1; i < w.size(); ++i) rest += (i > 1 ? " " : "") + w[i];
    if (w[0] == "vn") {  // as float32 values: the exact reader's and the writer's shortest text differ
      std::string n;
      for (std::size_t i = 1; i < w.size(); ++i) {
        n += ' ';
        n += std::to_string(std::strtof(w[i].c_str(), nullptr));
      }
      normals.push_back(n);
    }
    if (w[0] == "f") {
      std::string face = current[0] + "|" + current[1] + "|" + current[2] + "|" + current[3];
      for (std::size_t i = 1; i < w.size(); ++i) {  // each corner's normal (v//vn or v/vt/vn), by value
        const std::size_t first = w[i].find('/'), at = w[i].rfind('/');
        if (first == std::string::npos || first == at) continue;
        const long k = std::strtol(w[i].c_str() + at + 1, nullptr, 10);
        face += " n";  // appended apart: GCC 12 at -O3 warns of a false overlap in " n" + string
        face += k > 0 && static_cast<std::size_t>(k) <= normals.size() ? normals[k - 1] : std::string("?");
      }
      out.push_back(face);
    }
    if (w[0] == "mtllib") libraries.push_back("mtllib " + rest);
    if (w[0] == "t") {  // the name, the counts, the integers and strings as written, the floats' values
      std::string tag = "t";
      long n[3] = {};
      const bool counts = w.size() >= 3 && std::sscanf(w[2].c_str(), "%ld/%ld/%ld", &n[0], &n[1], &n[2]) == 3;
      for (std::size_t i = 1; i < w.size(); ++i) {
        const bool is_float = counts && i >= 3 + static_cast<std::size_t>(n[0]) &&
                              i < 3 + static_cast<std::size_t>(n[0] + n[1]);
        char value[40];
        std::snprintf(value, sizeof value, "%.17g", std::strtod(w[i].c_str(), nullptr));
        tag += " " + (is_float ? std::string(value) : w[i]);
      }
      libraries.push_back(tag);
    }
    for (int k = 0; k < 4; ++k)
      if (w[0] == keywords[k]) current[k] = rest;
  }
  out.insert(out.end(), libraries.begin(), libraries.end());
  return out;
}

// An OBJ file's leading '#' lines, text after the '#' and trimmed of a trailing CR, read here rather
// than by qsp: what decompress must give back.
std::vector<std::string> leading_hash_lines(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t at = line.find_first_not_of(" \t");
    if (at == std::string::npos) continue;
    if (line[at] != '#') break;
    out.push_back(line.substr(at + 1));
  }
  return out;
}

// The output is read back by OpenMesh, not by qsp's reader (SharedMeshes.OpenMeshReadsEveryValidFileAlike
// checks qsp's reading of the inputs against OpenMesh's). A file with coordinates float32 does not keep
// (found by testing::count_rounded_coordinates, not by qsp) gives them back as the values its text
// denotes; none is rounded.
TEST_F(SharedMeshesCli, EachRoundTripsExactlyOrIsRefusedClearly) {
  QSP_NEEDS_SHARED();
  const std::vector<fs::path> files = testing::shared_meshes();
  int round_tripped = 0, refused = 0, exact = 0, polygon_meshes = 0, labelled = 0;
  for (const fs::path& f : files) {
    SCOPED_TRACE(f.string());
    const std::string q = p("m.qsp"), back = p("back.obj");
    const testing::RoundedCount want = testing::count_rounded_coordinates(f);
    std::string flags = "--keep-order ";
    auto r = run_qsp("compress " + flags + quote(f.string()) + " " + quote(q));
    // compress keeps texture coordinates, normals, face labels and tags
    const std::string drop = expected_drop(f,
                                           kCategoryUv | kCategoryNormal | kCategoryGroup |
                                               kCategoryMaterial | kCategorySmoothing | kCategoryTag,
                                           true);
    if (const auto at = r.err.find("pass --drop "); r.exit_code == 1 && at != std::string::npos) {
      // The refusal names exactly the kinds the file has, and dropping them is enough.
      const std::string list = r.err.substr(at + 12, r.err.find(' ', at + 12) - at - 12);
      EXPECT_EQ(list, drop) << r.err;
      EXPECT_FALSE(fs::exists(q));
      flags += "--drop " + list + " ";
      r = run_qsp("compress " + flags + quote(f.string()) + " " + quote(q));
      if (r.exit_code == 0) {  // the note comes once the output is written
        EXPECT_NE(r.err.find(": dropped "), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("(--drop " + list + ")"), std::string::npos) << r.err;
      }
    } else if (r.exit_code == 0) {
      EXPECT_EQ(drop, "") << "compressed without refusing what it does not keep";
    }
    // Every shared file's coordinates have at most 17 significant digits: float64 holds them all.
    EXPECT_EQ(r.err.find("--float32"), std::string::npos) << "refused for digits: " << r.err;
    if (r.exit_code == 0 && want.count) ++exact;
    if (r.exit_code != 0) {
      ++refused;
      EXPECT_FALSE(testing::expected_mesh(f)) << "a valid mesh was refused: " << r.err;
      EXPECT_EQ(r.exit_code, 1) << r.err;
      EXPECT_NE(r.err.find("qsp: error: " + f.string() + ":"), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("internal"), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(q));
      continue;
    }
    r = run_qsp("decompress " + quote(q) + " " + quote(back));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(testing::expected_mesh(f)) << "accepted, but its manifest row says it is not a mesh";
    if (testing::expected_valid(f)) {
      const QuadMesh a = read_mesh_file(f.string()), b = testing::read_with_openmesh(back);
      EXPECT_EQ(a.quads, b.quads);
      EXPECT_TRUE(fuzz::same_bits(a.positions, b.positions));
    } else {
      // A polygon mesh (format 3.1), which OpenMesh would not read as it is: the faces index for index
      // (--keep-order) and the positions as floats, by the tests' own reader.
      const testing::Poly a = testing::read_faces(f), b = testing::read_faces(back);
      EXPECT_EQ(a.offsets, b.offsets);
      EXPECT_EQ(a.corners, b.corners);
      EXPECT_TRUE(fuzz::same_bits(a.positions, b.positions));
      ++polygon_meshes;
    }
    if (want.count) {
      // Coordinates float32 does not hold: the values the texts denote, vertex for vertex (--keep-order),
      // by the tests' own parser.
      const std::string text = slurp(f);
      const testing::TextMesh a = f.extension() == ".off" ? testing::parse_off_text(text)
                                                          : testing::parse_obj_text(text),
                              b = testing::parse_obj_text(slurp(back));
      ASSERT_EQ(a.vertices.size(), b.vertices.size());
      for (std::size_t v = 0; v < a.vertices.size(); ++v)
        for (std::size_t k = 0; k < 3; ++k)
          ASSERT_EQ(b.vertices[v].at(k), a.vertices[v].at(k)) << "vertex " << v << " axis " << k;
    }
    if (f.extension() == ".obj") {
      EXPECT_EQ(leading_hash_lines(back), leading_hash_lines(f)) << "licence lines";
      EXPECT_EQ(obj_face_labels(back), obj_face_labels(f)) << "face labels";
      labelled += obj_face_labels(f).size() > 0 && obj_face_labels(f)[0] != "-|-|-|-";
    }
    ++round_tripped;
    fs::remove(q);
    fs::remove(back);
  }
  std::printf(
      "%d meshes round-tripped exactly (%d of them with coordinates float32 does not hold), %d refused "
      "with a message\n",
      round_tripped, exact, refused);
  EXPECT_GT(exact, 0);  // pmp_hole_capsule.off has ten significant digits
  EXPECT_EQ(round_tripped, std::count_if(files.begin(), files.end(), testing::expected_mesh));
  EXPECT_GT(polygon_meshes, 20);
  EXPECT_GT(labelled, 20);  // MakeHuman's groups, OpenSubdiv's smoothing groups
  EXPECT_EQ(round_tripped + refused, static_cast<int>(files.size()));
}

// ---------------------------------------------------------------------------------------------
// Fuzzer findings (testdata/invalid/fuzz/, see testdata/README.md): each input with its NAME.expect.
// code=ok means the input must now round-trip (a valid mesh that once crashed the codec).

TEST(FuzzRegressions, EachFindingStaysFixed) {
  const fs::path dir = fs::path(QSP_TESTDATA_DIR) / "invalid" / "fuzz";
  if (!fs::is_directory(dir)) GTEST_SKIP() << "no findings recorded yet";
  int checked = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    const fs::path f = e.path();
    const std::string ext = f.extension().string();
    if (ext == ".expect" || ext == ".md") continue;
    SCOPED_TRACE(f.filename().string());
    fs::path sidecar = f;
    sidecar.replace_extension(".expect");
    ASSERT_TRUE(fs::exists(sidecar)) << "missing sidecar " << sidecar;
    auto expect = testing::read_expect(sidecar);
    ASSERT_TRUE(expect.count("code")) << sidecar;
    const std::string bytes = slurp(f);
    Caught c;
    bool round_tripped = false;  // check_round_trip returns false when encode refuses the mesh
    try {
      if (ext == ".qsp") {
        QuadMesh m = decode(bytes);
        (void)build_adjacency(m);
        round_tripped = fuzz::check_round_trip(m, "decoded finding");
      } else {
        const std::string name = f.filename().string();
        QuadMesh m = ext == ".off"   ? read_off(bytes, name)
                     : ext == ".ply" ? read_ply_file(f.string())
                                     : read_obj(bytes, name);
        round_tripped = fuzz::check_round_trip(m, "finding");
        if (expect["code"] != "ok") (void)build_adjacency(m);
      }
    } catch (const Error& err) {
      c = {true, err.code(), err.what()};
    }
    if (expect["code"] == "ok") {
      EXPECT_FALSE(c.thrown) << c.message;
      EXPECT_TRUE(round_tripped) << "a code=ok finding must round-trip, not be refused";
    } else {
      ASSERT_TRUE(c.thrown) << "accepted";
      EXPECT_EQ(error_name(c.code), expect["code"]) << c.message;
      EXPECT_NE(c.message.find(expect["message"]), std::string::npos)
          << c.message << "\nexpected: " << expect["message"];
    }
    ++checked;
  }
  std::printf("%d fuzzer findings checked\n", checked);
}

}  // namespace
}  // namespace qsp
