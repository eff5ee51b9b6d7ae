// The .qsp codec: entropy coder, topology streams, round trips, canonical bytes, keep-order, CLI.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/entropy.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/partition.h"
#include "qsp/smaller.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"
#include "support/quantized.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

// ---- Entropy coder ----

TEST(Entropy, BitsAndIntegersRoundTrip) {
  std::mt19937 rng(7);
  std::vector<unsigned> bits;
  std::vector<std::uint32_t> ints;
  for (int i = 0; i < 20000; ++i) {
    bits.push_back(rng() % 10 == 0);
    std::uint32_t mag = rng() % 33;
    ints.push_back(mag == 32 ? 0xFFFFFFFEu : static_cast<std::uint32_t>(rng() & ((1ull << mag) - 1)));
  }
  std::string out;
  RangeEncoder enc(out);
  BitModel bm[3];
  IntModel im;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    enc.encode_bit(bm[i % 3], bits[i]);
    im.encode(enc, ints[i]);
    enc.encode_raw(ints[i] & 0xFFFF, 16);
  }
  enc.finish();
  RangeDecoder dec(out, 0, "test stream");
  BitModel dm[3];
  IntModel di;
  for (std::size_t i = 0; i < bits.size(); ++i) {
    ASSERT_EQ(dec.decode_bit(dm[i % 3]), bits[i]);
    ASSERT_EQ(di.decode(dec), ints[i]);
    ASSERT_EQ(dec.decode_raw(16), ints[i] & 0xFFFF);
  }
  EXPECT_NO_THROW(dec.finish());
}

TEST(Entropy, SkewedBitsCostLittle) {
  std::string out;
  RangeEncoder enc(out);
  BitModel m;
  for (int i = 0; i < 100000; ++i) enc.encode_bit(m, 0);
  enc.finish();
  EXPECT_LT(out.size(), 60u);  // ~0.003 bits each once learnt
}

// A mixed decision round-trips and leans on whichever model has seen more: a fresh specific model
// (one per symbol here) coded alone pays ~1 bit each time, mixed with a trained general one far less.
TEST(Entropy, MixedDecisionsLeanOnTheExperiencedModel) {
  std::mt19937 rng(3);
  std::vector<unsigned> bits(4000);
  for (unsigned& b : bits) b = rng() % 8 == 0;
  auto code = [&](bool mix) {
    std::string out;
    RangeEncoder enc(out);
    BitModel general;
    std::vector<BitModel> specific(bits.size());
    for (std::size_t i = 0; i < bits.size(); ++i)
      mix ? enc.encode_bit(specific[i], general, bits[i]) : enc.encode_bit(specific[i], bits[i]);
    enc.finish();
    return out;
  };
  const std::string alone = code(false), mixed = code(true);
  EXPECT_GT(alone.size(), bits.size() / 8 * 9 / 10);  // ~1 bit per decision
  EXPECT_LT(mixed.size(), bits.size() / 8 * 7 / 10);  // entropy of 1/8 is 0.54 bits
  RangeDecoder dec(mixed, 0, "test stream");
  BitModel general;
  std::vector<BitModel> specific(bits.size());
  for (std::size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(dec.decode_bit(specific[i], general), bits[i]) << i;
  EXPECT_NO_THROW(dec.finish());
}

// Once the specific model has seen 64 bits it codes alone: the same bytes as a single-model stream,
// and the general model is left as it was.
TEST(Entropy, MatureModelsCodeAlone) {
  BitModel trained;
  {
    std::string scratch;
    RangeEncoder warm(scratch);
    for (int i = 0; i < 64; ++i) warm.encode_bit(trained, i % 5 == 0);
  }
  std::mt19937 rng(5);
  std::vector<unsigned> bits(500);
  for (unsigned& b : bits) b = rng() % 3 == 0;
  std::string single, mixed;
  RangeEncoder one(single), two(mixed);
  BitModel a = trained, b = trained, general;
  for (unsigned bit : bits) {
    one.encode_bit(a, bit);
    two.encode_bit(b, general, bit);
  }
  one.finish();
  two.finish();
  EXPECT_EQ(single, mixed);
  EXPECT_EQ(general.seen, 0);
}

TEST(Entropy, DecoderRefusesShortAndLongStreams) {
  std::string out;
  RangeEncoder enc(out);
  BitModel m;
  for (int i = 0; i < 1000; ++i) enc.encode_bit(m, i % 3 == 0);
  enc.finish();
  auto run = [](std::string_view s) {
    RangeDecoder dec(s, 100, "test stream");
    BitModel dm;
    for (int i = 0; i < 1000; ++i) dec.decode_bit(dm);
    dec.finish();
  };
  EXPECT_NO_THROW(run(out));
  for (std::size_t n = 0; n < out.size(); ++n) {
    EXPECT_THROW(run(std::string_view(out).substr(0, n)), Error) << n;
  }
  EXPECT_THROW(run(out + std::string(1, '\0')), Error);
}

// Every single-byte change, cut or append of a stream either decodes other symbols or is refused,
// for both ends: the encoder's bytes are the only ones that give its symbols. (Before the decoder
// checked code < range, `00 ff ff ff f8 00` passed for the one raw byte 0xFF whose stream is
// `00 fe ff ff f8 00`, and compact `ff ff ff f9 16` for a stream written as `ff ff ff f8 16`.)
TEST(Entropy, OnlyTheEncodersBytesGiveItsSymbols) {
  struct Symbol {
    int model;  // 0, 1: a decision through that model; -n: n raw bits
    std::uint32_t value;
  };
  std::vector<std::vector<Symbol>> cases = {
      {{-8, 0xFF}},
      {{1, 1}, {-6, 63}, {0, 1}, {0, 1}, {-6, 63}, {1, 1}, {-4, 15}, {-8, 255}, {-5, 31}, {0, 1}}};
  std::mt19937 rng(17);
  for (int c = 0; c < 40; ++c) {
    std::vector<Symbol> sy(1 + rng() % 24);
    for (Symbol& x : sy) {
      const int kind = static_cast<int>(rng() % 3);
      const int n = 1 + static_cast<int>(rng() % 12);
      x = kind < 2 ? Symbol{kind, rng() % 5 == 0 ? 1u : 0u}
                   : Symbol{-n, static_cast<std::uint32_t>(rng()) & ((1u << n) - 1)};
    }
    cases.push_back(sy);
  }
  for (StreamEnds ends : {StreamEnds::kLzma, StreamEnds::kCompact}) {
    for (const auto& sy : cases) {
      std::string out;
      RangeEncoder enc(out, ends);
      BitModel m[2];
      for (const Symbol& x : sy)
        x.model >= 0 ? enc.encode_bit(m[x.model], x.value) : enc.encode_raw(x.value, -x.model);
      enc.finish();
      auto same = [&](std::string_view bytes) {
        try {
          RangeDecoder dec(bytes, 0, "test stream", ends);
          BitModel d[2];
          for (const Symbol& x : sy)
            if ((x.model >= 0 ? dec.decode_bit(d[x.model]) : dec.decode_raw(-x.model)) != x.value)
              return false;
          dec.finish();
          return true;
        } catch (const Error&) {
          return false;
        }
      };
      ASSERT_TRUE(same(out));
      for (std::size_t i = 0; i < out.size(); ++i)
        for (int b = 0; b < 256; ++b) {
          std::string bad = out;
          if (bad[i] == static_cast<char>(b)) continue;
          bad[i] = static_cast<char>(b);
          EXPECT_FALSE(same(bad)) << "byte " << i << " = " << b;
        }
      for (int b = 0; b < 256; ++b) EXPECT_FALSE(same(out + static_cast<char>(b))) << "appended " << b;
      if (!out.empty()) {
        EXPECT_FALSE(same(std::string_view(out).substr(0, out.size() - 1)));
      }
    }
  }
}

// Compact ends (geometry revision 4): the same symbols in 4 bytes less than LZMA's ends (no leading
// zero, 3 or 4 zero bytes left out of the flush), for any number of symbols, the empty stream
// included; the decoder reads the left-out zeros back, accepts only the encoder's own ending for the
// symbols it decoded, and refuses a stream that needs more than 4 zeros.
TEST(Entropy, CompactEndsSaveFourBytesAndStayStrict) {
  std::mt19937 rng(13);
  for (int count : {0, 1, 2, 5, 17, 100, 1000, 5000}) {
    SCOPED_TRACE(count);
    std::vector<unsigned> bits(static_cast<std::size_t>(count));
    std::vector<std::uint32_t> raw(bits.size());
    for (std::size_t i = 0; i < bits.size(); ++i) bits[i] = rng() % 4 == 0, raw[i] = rng() & 0x3FF;
    auto code = [&](StreamEnds ends) {
      std::string out;
      RangeEncoder enc(out, ends);
      BitModel m;
      for (std::size_t i = 0; i < bits.size(); ++i) {
        enc.encode_bit(m, bits[i]);
        if (i % 7 == 0) enc.encode_raw(raw[i], 10);
      }
      enc.finish();
      return out;
    };
    auto run = [&](std::string_view s) {
      RangeDecoder dec(s, 0, "test stream", StreamEnds::kCompact);
      BitModel m;
      for (std::size_t i = 0; i < bits.size(); ++i) {
        if (dec.decode_bit(m) != bits[i]) return false;
        if (i % 7 == 0 && dec.decode_raw(10) != raw[i]) return false;
      }
      dec.finish();
      return true;
    };
    const std::string lzma = code(StreamEnds::kLzma), compact = code(StreamEnds::kCompact);
    EXPECT_LE(compact.size() + 4, lzma.size());
    EXPECT_GE(compact.size() + 5, lzma.size());
    EXPECT_TRUE(run(compact));
    // A zero appended, the last byte cut or changed: not these symbols, or refused.
    auto same = [&](std::string_view s) {
      try {
        return run(s);
      } catch (const Error&) {
        return false;
      }
    };
    EXPECT_THROW(run(compact + std::string(1, '\0')), Error);
    EXPECT_FALSE(same(compact + std::string(1, '\x5A')));
    if (!compact.empty()) {
      EXPECT_FALSE(same(compact.substr(0, compact.size() - 1)));
      std::string changed = compact;
      changed.back() = static_cast<char>(changed.back() ^ 1);
      EXPECT_FALSE(same(changed));
    }
  }
  // A stream whose symbols need more than the 4 zeros: ends too early.
  std::string out;
  RangeEncoder enc(out, StreamEnds::kCompact);
  enc.encode_raw(0x2A5u, 10);
  enc.encode_raw(0x3FFFFFu, 22);
  enc.finish();
  RangeDecoder dec(std::string_view(out).substr(0, out.size() - 2), 0, "test stream", StreamEnds::kCompact);
  EXPECT_THROW(
      {
        dec.decode_raw(10);
        dec.decode_raw(22);
        dec.decode_raw(32);
        dec.decode_raw(32);
      },
      Error);
}

// ---- Topology streams ----

// A single quad: one patch and one hole, four darts each (worked out in qsp_format.md).
TopologyCode single_quad_code() {
  TopologyCode c;
  c.kind = ComponentKind::kDisk;
  c.next_ref = {0, 0, 0, 2, 4, 1, 2, 1};
  c.edge_length = {1, 1, 1, 1};
  c.corner = {1, 0, 1, 0, 0, 1, 1, 0};
  return c;
}

TEST(Topology, HandBuiltCodesRoundTrip) {
  TopologyCode torus;
  torus.kind = ComponentKind::kTorus;
  torus.a = 9, torus.b = 6, torus.twist = 2;
  TopologyCode annulus;
  annulus.kind = ComponentKind::kAnnulus;
  annulus.a = 12, annulus.b = 3;
  TopologyCode big = single_quad_code();
  big.edge_length = {70000, 3, 3, 70000};  // edges 0 and 3 are opposite, so are 1 and 2
  std::vector<TopologyCode> codes = {single_quad_code(), torus, annulus, big};
  std::string bytes = encode_topology(codes);
  std::vector<TopologyCode> back =
      decode_topology(bytes, 0, codes.size(), 1000, 100000, StreamEnds::kCompact);
  ASSERT_EQ(back.size(), codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) EXPECT_TRUE(back[i] == codes[i]) << i;
  // The code is a valid partition: a 1x1 grid.
  ComponentPartition p = partition_from_code(back[0]);
  EXPECT_EQ(grid_layout(p).quads.size(), 4u);
  // Limits are enforced while decoding.
  EXPECT_THROW(decode_topology(bytes, 0, codes.size(), 7, 100000, StreamEnds::kCompact),
               Error);  // 8 schematic edges
  EXPECT_THROW(decode_topology(bytes, 0, codes.size(), 1000, 69999, StreamEnds::kCompact), Error);
}

TEST(Topology, LengthsImpliedByOppositeSidesAreNotStored) {
  // A 5x7 patch: only two of the four lengths are coded, and a code whose opposite sides disagree
  // is refused by the encoder as a bug.
  TopologyCode c = single_quad_code();
  c.edge_length = {5, 7, 7, 5};
  std::vector<TopologyCode> one{c};
  auto back = decode_topology(encode_topology(one), 0, 1, 100, 100, StreamEnds::kCompact);
  EXPECT_TRUE(back[0] == c);
  c.edge_length = {5, 7, 6, 5};
  EXPECT_THROW(encode_topology(std::vector<TopologyCode>{c}), Error);
}

// ---- Meshes ----

QuadMesh load(const std::string& path) {
  ReadReport report;
  return read_mesh_file(path, &report);
}

std::vector<std::string> mesh_files(const std::string& dir) {
  std::vector<std::string> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir)) {
    MeshFormat f = format_from_path(e.path().string());
    if (f == MeshFormat::kObj || f == MeshFormat::kOff || f == MeshFormat::kPly)
      out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool same_float_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// decoded is `mesh` renumbered by `order` (original -> canonical), every face rotated by its rotation.
void expect_isomorphic(const QuadMesh& mesh, const QuadMesh& decoded, const OrderMap& order,
                       bool exact_positions) {
  ASSERT_EQ(decoded.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(decoded.face_count(), mesh.face_count());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    std::uint32_t cf = order.face[f], r = order.rotation[f];
    for (std::uint32_t c = 0; c < 4; ++c) {
      ASSERT_EQ(decoded.quads[4 * cf + c], order.vertex[mesh.quads[4 * f + (c + r) % 4]]) << "face " << f;
    }
  }
  if (!exact_positions) return;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(same_float_bits(decoded.positions[3 * order.vertex[v] + k], mesh.positions[3 * v + k]))
          << "vertex " << v;
    }
  }
}

// Returns false (after checking the refusal is a typed input error) when `path` is not a valid mesh.
bool round_trip(const std::string& path) {
  SCOPED_TRACE(path);
  QuadMesh mesh;
  try {
    mesh = load(path);
    build_adjacency(mesh);
  } catch (const Error& e) {
    EXPECT_NE(e.code(), ErrorCode::kInternal) << e.what();
    return false;
  }
  OrderMap order;
  std::string bytes = encode(mesh, {}, &order);
  QuadMesh decoded = decode(bytes);
  expect_isomorphic(mesh, decoded, order, true);
  // Decoding then encoding again gives the same bytes (the canonical form is a fixed point).
  EXPECT_EQ(encode(decoded), bytes);

  EncodeOptions keep;
  keep.keep_order = true;
  QuadMesh restored = decode(encode(mesh, keep));
  EXPECT_EQ(restored.quads, mesh.quads);
  EXPECT_TRUE(restored.positions.size() == mesh.positions.size() &&
              std::memcmp(restored.positions.data(), mesh.positions.data(), 4 * mesh.positions.size()) == 0);
  // Either coding order, forced, gives the same mesh back (the encoder picks one per file; a
  // decoder must read both). Large meshes only get patch order, which the default already covers.
  if (mesh.vertex_count() <= kSearchVertexLimit) {
    EncodeOptions best_options;
    best_options.level = kMaxLevel;
    const std::string best = encode(mesh, best_options);
    // Where the default's header sample covers the whole mesh, --best tries a superset of its choices.
    if (mesh.vertex_count() <= level_effort(kDefaultLevel, 0).header_sample) {
      EXPECT_LE(best.size(), bytes.size()) << "--best is larger than the default";
    }
    for (CodingOrder o : {CodingOrder::kLayout, CodingOrder::kPatch}) {
      EncodeOptions forced;
      forced.level = kMaxLevel;
      forced.geometry_order = o;
      OrderMap forced_order;
      const std::string fb = encode(mesh, forced, &forced_order);
      const FileInfo fi = inspect(fb);
      EXPECT_TRUE(fi.geometry_revision >= 4 && fi.geometry_revision <= 6) << int{fi.geometry_revision};
      EXPECT_EQ(fi.geometry_order, o);
      expect_isomorphic(mesh, decode(fb), forced_order, true);
      EXPECT_LE(best.size(), fb.size());  // the highest level keeps the smaller
    }
  }
  FileInfo info = inspect(bytes);
  EXPECT_EQ(info.vertices, mesh.vertex_count());
  EXPECT_EQ(info.faces, mesh.face_count());
  EXPECT_EQ(info.total_bytes, bytes.size());
  return true;
}

TEST(Codec, RoundTripTestdata) {
  auto files = mesh_files(QSP_TESTDATA_DIR);
  ASSERT_FALSE(files.empty());
  for (const auto& f : files) EXPECT_TRUE(round_trip(f)) << f;
}

// Every shared mesh the manifest calls valid round-trips, every other one is refused cleanly: a
// reader or codec that refuses valid meshes fails here, not only one that corrupts them.
void round_trip_shared(const fs::path& dir) {
  QSP_NEEDS_SHARED();
  const auto files = testing::mesh_files_in(dir);
  const auto manifest = testing::read_manifest(dir / "MANIFEST.tsv");
  EXPECT_EQ(files.size(), manifest.size()) << "files in " << dir << " against rows in its MANIFEST.tsv";
  int ok = 0;
  for (const auto& f : files) {
    const bool valid = round_trip(f.string());
    EXPECT_EQ(valid, testing::expected_valid(f)) << f;
    ok += valid;
  }
  EXPECT_EQ(ok, testing::expected_valid_count(files));
}

TEST(Codec, RoundTripSharedMeshes) { round_trip_shared(testing::shared_dir() / "meshes"); }

TEST(Codec, RoundTripOpenSubdivShapes) { round_trip_shared(testing::shared_dir() / "meshes" / "osd_shapes"); }

// Patch order predicts every point from mesh neighbours one edge away; on coarse meshes with small
// patches it beats layout order, which predicts schematic vertices from others a patch side away.
TEST(Codec, PatchOrderPaysOnSmallPatches) {
  QSP_NEEDS_SHARED();
  for (const char* name :
       {"igl_horse_quad.obj", "quadriflow_gargoyle.obj", "igl_inspired_mesh_quads_conjugate.off"}) {
    const std::string p = (testing::shared_dir() / "meshes" / name).string();
    SCOPED_TRACE(name);
    const QuadMesh mesh = load(p);
    for (std::uint32_t bits : {0u, 14u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      o.geometry_order = CodingOrder::kLayout;
      const std::size_t layout = encode(mesh, o).size();
      o.geometry_order = CodingOrder::kPatch;
      const std::size_t patch = encode(mesh, o).size();
      std::printf("%s %u bits: patch order %zu bytes, layout order %zu\n", name, bits, patch, layout);
      // Lossless gains less: the low bits of decimal residuals are noise in either order.
      EXPECT_LT(static_cast<double>(patch), (bits ? 0.97 : 0.99) * static_cast<double>(layout)) << bits;
    }
  }
}

QuadMesh shuffled(const QuadMesh& m, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::uint32_t> vperm(m.vertex_count()), fperm(m.face_count());
  std::iota(vperm.begin(), vperm.end(), 0);
  std::iota(fperm.begin(), fperm.end(), 0);
  std::shuffle(vperm.begin(), vperm.end(), rng);
  std::shuffle(fperm.begin(), fperm.end(), rng);
  QuadMesh out;
  out.positions.resize(m.positions.size());
  for (std::size_t v = 0; v < vperm.size(); ++v)
    std::copy_n(&m.positions[3 * v], 3, &out.positions[3 * vperm[v]]);
  for (std::size_t i = 0; i < fperm.size(); ++i) {
    std::uint32_t f = fperm[i], r = rng() % 4;
    for (std::uint32_t c = 0; c < 4; ++c) out.quads.push_back(vperm[m.quads[4 * f + (c + r) % 4]]);
  }
  return out;
}

TEST(Codec, ShuffledCopiesGiveIdenticalBytes) {
  std::vector<std::string> files = mesh_files(QSP_TESTDATA_DIR);
  for (const char* name :
       {"igl_horse_quad.obj", "mh_base.obj", "osd_catmark_car.obj", "pmp_hole_capsule.off"}) {
    const fs::path p = testing::shared_dir() / "meshes" / name;
    if (testing::shared_present()) files.push_back(p.string());
  }
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    QuadMesh mesh = load(f);
    std::string bytes = encode(mesh);
    for (std::uint32_t seed = 1; seed <= 3; ++seed) EXPECT_EQ(encode(shuffled(mesh, seed)), bytes) << seed;
  }
}

// Each partition mode on its own gives one file per mesh, whatever its numbering: on symmetric meshes
// (the cubes) greedy and merge must pick among equivalent partitions by position, as the codec does.
TEST(Codec, EveryPartitionModeIsCanonical) {
  std::vector<std::string> files = mesh_files(QSP_TESTDATA_DIR);
  for (const auto& f : testing::mesh_files_in(testing::shared_dir() / "meshes" / "osd_shapes"))
    files.push_back(f.string());
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    QuadMesh mesh;
    if (!testing::read_valid(f, mesh)) continue;
    for (PartitionMode mode : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
      EncodeOptions o;
      o.partition = mode;
      const std::string bytes = encode(mesh, o);
      for (std::uint32_t seed = 1; seed <= 2; ++seed)
        EXPECT_EQ(encode(shuffled(mesh, seed), o), bytes) << partition_mode_name(mode) << " seed " << seed;
    }
  }
}

// By default a mesh of up to 32768 vertices is stored with whichever partition gives the smallest
// file, the first of motorcycle, greedy, merge on a tie.
// The levels that search partitions keep the smallest of the three (levels 8 and 9).
TEST(Codec, BestKeepsTheSmallestPartition) {
  std::vector<std::string> files = mesh_files(QSP_TESTDATA_DIR);
  for (const char* name : {"igl_horse_quad.obj", "quadriflow_gargoyle.obj", "mh_fedora.obj"}) {
    const fs::path p = testing::shared_dir() / "meshes" / name;
    if (testing::shared_present()) files.push_back(p.string());
  }
  int smaller = 0;
  for (const auto& f : files) {
    SCOPED_TRACE(f);
    const QuadMesh mesh = load(f);
    for (std::uint32_t bits : {0u, 14u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      o.level = kMaxLevel;
      const std::string chosen = encode(mesh, o);
      std::string best;
      for (PartitionMode mode : {PartitionMode::kMotorcycle, PartitionMode::kGreedy, PartitionMode::kMerge}) {
        o.partition = mode;
        std::string bytes = encode(mesh, o);
        if (mode == PartitionMode::kMotorcycle && bytes.size() > chosen.size()) ++smaller;
        if (best.empty() || bytes.size() < best.size()) best = std::move(bytes);
      }
      EXPECT_EQ(chosen, best) << bits << " bits";
    }
  }
  EXPECT_GT(smaller, 0) << "no mesh is smaller with another partition than the motorcycle graph";
}

// The codec's threads on both sides of their thresholds (src/codec.cpp): the greedy partition tried on a
// second thread from 1024 vertices, the decoder's mesh check beside the geometry decoder from 4096
// faces. Each gives the mesh back exactly; tools/hardening.sh runs this under ThreadSanitizer.
TEST(Codec, ThreadedPathsGiveTheMeshBack) {
  for (const auto& [a, b] : {std::pair{20, 20}, std::pair{40, 30}, std::pair{80, 60}}) {
    SCOPED_TRACE(std::to_string(a) + "x" + std::to_string(b));
    const QuadMesh m = testing::grid(a, b);
    OrderMap order;
    const std::string bytes = encode(m, {}, &order);
    expect_isomorphic(m, decode(bytes), order, true);
  }
}

// Geometry revision 6 (format 2.2) over every mesh of the corpus, lossless and at 14 bits: forced on, it
// decodes to exactly the mesh revisions 4 and 5 give; by default (meshes of up to 32768 vertices) the
// encoder keeps whichever is smaller, so no file grows against 2.1's coding, nor against forcing it.
// Forced off, every section is revision 4 or 5, which 2.1 decoders read. The partition is fixed to keep
// this affordable under the sanitizers; both coding orders are still tried.
TEST(Codec, RevisionSixRoundTripsAndNeverGrowsAFile) {
  int tried = 0, smaller = 0, pawn_ratio_checked = 0;
  for (const auto& path : qsp::testing::corpus()) {
    QuadMesh mesh;
    if (!testing::read_valid(path, mesh)) continue;
    if (mesh.vertex_count() > 32768 || mesh.face_count() == 0) continue;
    SCOPED_TRACE(path.string());
    for (std::uint32_t bits : {0u, 14u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      o.level = kMaxLevel;  // the levels that try revision 6
      o.partition = PartitionMode::kMotorcycle;
      const std::string chosen = encode(mesh, o);
      o.geometry_shapes = false;
      const std::string old = encode(mesh, o);
      o.geometry_shapes = true;
      const std::string forced = encode(mesh, o);
      EXPECT_LE(chosen.size(), old.size()) << bits << " bits";
      EXPECT_LE(chosen.size(), forced.size()) << bits << " bits";
      EXPECT_LE(inspect(old).geometry_revision, 5);
      EXPECT_EQ(inspect(forced).geometry_revision, 6);
      const QuadMesh a = decode(old), b = decode(forced);
      EXPECT_EQ(a.quads, b.quads);
      ASSERT_EQ(a.positions.size(), b.positions.size());
      EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), 4 * a.positions.size()), 0)
          << bits << " bits";
      const QuadMesh c = decode(chosen);
      EXPECT_EQ(c.quads, a.quads);
      EXPECT_EQ(std::memcmp(c.positions.data(), a.positions.data(), 4 * a.positions.size()), 0);
      smaller += chosen.size() < old.size();
      if (bits == 14 && path.filename() == "osd_catmark_pawn.obj") {  // a surface of revolution
        EXPECT_LT(10 * forced.size(), 7 * old.size())
            << "shape transfers: pawn " << forced.size() << " vs " << old.size();
        ++pawn_ratio_checked;
      }
      ++tried;
    }
  }
  EXPECT_GE(tried, 20);
  EXPECT_GE(smaller, tried / 2) << "revision 6 is smaller on too few meshes";
  if (testing::shared_present()) {
    EXPECT_EQ(pawn_ratio_checked, 1);
  }
}

TEST(Codec, EmptyAndVertexOnlyMeshes) {
  QuadMesh empty;
  QuadMesh back = decode(encode(empty));
  EXPECT_EQ(back.vertex_count(), 0u);
  QuadMesh points;
  points.positions = {1, 2, 3, -0.0f, 5, 6};
  EncodeOptions keep;
  keep.keep_order = true;
  back = decode(encode(points, keep));
  EXPECT_EQ(std::memcmp(back.positions.data(), points.positions.data(), 24), 0);
}

TEST(Codec, UnreferencedVerticesKeepTheirPositions) {
  QuadMesh m = load(std::string(QSP_TESTDATA_DIR) + "/grid_5x3.obj");
  m.positions.insert(m.positions.begin(), {7.5f, -1.0f, 2.0f});  // new vertex 0, in no face
  for (auto& v : m.quads) ++v;
  m.positions.insert(m.positions.end(), {1e-30f, 3.0f, 4.0f});
  OrderMap order;
  std::string bytes = encode(m, {}, &order);
  expect_isomorphic(m, decode(bytes), order, true);
  EXPECT_EQ(inspect(bytes).unreferenced, 2u);
}

// Quantized decodes against their input, on every corpus mesh at several depths: each coordinate within
// half a grid step of the original, plus float rounding (testing::quantization_bound).
TEST(Codec, QuantizedStaysWithinTheGrid) {
  int checked = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh m;
    if (!testing::read_valid(path, m)) continue;
    SCOPED_TRACE(path.string());
    for (std::uint32_t bits : {4u, 11u, 14u, 20u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      o.partition = PartitionMode::kMotorcycle;  // the grid does not depend on it; the search is costly
      OrderMap order;
      const std::string bytes = encode(m, o, &order);
      const QuadMesh d = decode(bytes);
      expect_isomorphic(m, d, order, false);
      const double bound = testing::quantization_bound(m.positions, bits);
      double worst = 0;
      for (std::size_t v = 0; v < m.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k)
          worst = std::max(
              worst, std::abs(double{d.positions[3 * order.vertex[v] + k]} - double{m.positions[3 * v + k]}));
      EXPECT_LE(worst, bound) << bits << " bits: worst error " << worst << ", bound " << bound;
    }
    ++checked;
  }
  EXPECT_EQ(checked, testing::expected_valid_count(testing::corpus()));
}

TEST(Codec, LimitsRefuseBeforeDecoding) {
  QuadMesh m = load(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj");
  std::string bytes = encode(m);
  DecodeLimits tight;
  tight.max_faces = m.face_count() - 1;
  try {
    decode(bytes, tight);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kLimit);
    EXPECT_NE(std::string(e.what()).find("face count"), std::string::npos);
  }
}

TEST(Codec, InspectCountsTable1Row) {
  QuadMesh m = load(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj");
  FileInfo info = inspect(encode(m));
  Adjacency adj = build_adjacency(m);
  EXPECT_EQ(info.edges, adj.halfedge_count() / 2);
  EXPECT_EQ(info.extraordinary, 8u);
  EXPECT_EQ(info.components.size(), 1u);
  EXPECT_GT(info.schematic_edges, 0u);
  EXPECT_EQ(
      info.header_bytes + info.connectivity_bytes + info.geometry_bytes + info.order_bytes + info.other_bytes,
      info.total_bytes);
}

// ---- CLI ----

struct CliRun {
  int status;
  std::string err;
};

CliRun run_cli(const std::string& args) {
  std::string errfile = (fs::temp_directory_path() / ("qsp_cli_err_" + std::to_string(::getpid()))).string();
  std::string cmd = std::string(QSP_CLI_PATH) + " " + args + " 2>" + errfile;
  int rc = std::system(cmd.c_str());
  std::ifstream in(errfile);
  std::string err((std::istreambuf_iterator<char>(in)), {});
  fs::remove(errfile);
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, err};
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("qsp_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(QSP_TESTDATA_DIR) + "/cube_4.obj", dir_ / "cube.obj");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string p(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(CliTest, CompressDecompressRoundTrip) {
  ASSERT_EQ(run_cli("compress " + p("cube.obj")).status, 0);
  ASSERT_TRUE(fs::exists(p("cube.obj.qsp")));
  // Default output would be cube.obj again: the input exists, so it is refused without -f.
  CliRun r = run_cli("decompress " + p("cube.obj.qsp"));
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("exists"), std::string::npos) << r.err;
  ASSERT_EQ(run_cli("decompress " + p("cube.obj.qsp") + " -o " + p("back.obj")).status, 0);
  QuadMesh a = load(p("cube.obj")), b = load(p("back.obj"));
  EXPECT_EQ(a.vertex_count(), b.vertex_count());
  EXPECT_EQ(encode(a), encode(b));
  // compress -> decompress -> compress gives the same bytes.
  ASSERT_EQ(run_cli("compress " + p("back.obj") + " " + p("again.qsp")).status, 0);
  EXPECT_EQ(read_file_bytes(p("again.qsp")), read_file_bytes(p("cube.obj.qsp")));
  // OFF output by extension, keep-order restores the file's own order.
  ASSERT_EQ(run_cli("compress --keep-order " + p("cube.obj") + " " + p("k.qsp")).status, 0);
  ASSERT_EQ(run_cli("decompress " + p("k.qsp") + " " + p("k.off")).status, 0);
  QuadMesh k = load(p("k.off"));
  EXPECT_EQ(k.quads, a.quads);
  EXPECT_EQ(k.positions, a.positions);
}

// --compat 2.1 writes what 2.1 readers decode: no geometry revision 6, the same mesh back.
TEST_F(CliTest, CompatWritesNoRevisionSix) {
  const std::string golden = std::string(QSP_TESTDATA_DIR) + "/golden/tilted_noise_q14.obj";
  ASSERT_EQ(run_cli("compress --best --quantize 14 " + golden + " " + p("new.qsp")).status, 0);
  ASSERT_EQ(run_cli("compress --best --compat 2.1 --quantize 14 " + golden + " " + p("old.qsp")).status, 0);
  const std::string now = read_file_bytes(p("new.qsp")), old = read_file_bytes(p("old.qsp"));
  EXPECT_EQ(inspect(now).geometry_revision, 6);
  EXPECT_EQ(inspect(old).geometry_revision, 5);
  EXPECT_EQ(old, read_file_bytes(std::string(QSP_TESTDATA_DIR) + "/golden/tilted_noise_q14_no_shapes.qsp"));
  EXPECT_EQ(decode(old).positions, decode(now).positions);
  EXPECT_EQ(run_cli("compress --compat 2.0 " + golden + " " + p("x.qsp")).status, 2);
}

TEST_F(CliTest, RefusesToOverwrite) {
  ASSERT_EQ(run_cli("compress " + p("cube.obj") + " " + p("x.qsp")).status, 0);
  CliRun r = run_cli("compress " + p("cube.obj") + " " + p("x.qsp"));
  EXPECT_EQ(r.status, 3);
  EXPECT_EQ(run_cli("compress -f " + p("cube.obj") + " " + p("x.qsp")).status, 0);
  // Never the input, not even with -f, not even through a link.
  std::string before = read_file_bytes(p("cube.obj"));
  r = run_cli("compress -f " + p("cube.obj") + " " + p("cube.obj"));
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
  fs::create_hard_link(p("cube.obj"), p("link.obj"));
  r = run_cli("compress -f " + p("cube.obj") + " -o " + p("link.obj"));
  EXPECT_EQ(r.status, 3);
  EXPECT_EQ(read_file_bytes(p("cube.obj")), before);
  // Usage errors exit 2.
  EXPECT_EQ(run_cli("compress " + p("cube.obj") + " " + p("a.qsp") + " -o " + p("b.qsp")).status, 2);
  EXPECT_EQ(run_cli("compress --quantize 31 " + p("cube.obj")).status, 2);
}

TEST_F(CliTest, ExtraDataIsRefusedUnlessDropped) {
  {
    std::ofstream o(p("uv.obj"));
    o << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\ng quad\nf 1/1 2/2 3/3 4/4\n";
  }
  CliRun r = run_cli("compress " + p("uv.obj"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--positions-only"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("texture"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("uv.obj.qsp")));
  r = run_cli("compress --positions-only " + p("uv.obj"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("dropped"), std::string::npos) << r.err;
}

TEST_F(CliTest, StdinAndStdout) {
  ASSERT_EQ(
      std::system(
          (std::string(QSP_CLI_PATH) + " compress - - < " + p("cube.obj") + " > " + p("s.qsp")).c_str()),
      0);
  ASSERT_EQ(
      std::system((std::string(QSP_CLI_PATH) + " decompress - < " + p("s.qsp") + " > " + p("s.obj")).c_str()),
      0);
  EXPECT_EQ(encode(load(p("s.obj"))), encode(load(p("cube.obj"))));
}

TEST_F(CliTest, CorruptFileGivesTypedError) {
  ASSERT_EQ(run_cli("compress " + p("cube.obj") + " " + p("c.qsp")).status, 0);
  std::string bytes = read_file_bytes(p("c.qsp"));
  bytes[bytes.size() / 2] ^= 0x10;
  write_file_atomic(p("bad.qsp"), bytes, false);
  CliRun r = run_cli("decompress " + p("bad.qsp") + " " + p("bad.obj"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(p("bad.obj")));
}

}  // namespace
}  // namespace qsp

namespace qsp {
namespace {

// Not a check: prints bytes and bits per vertex (connectivity and geometry apart) for the shared
// meshes. Run: qsp_tests --gtest_also_run_disabled_tests --gtest_filter='*SizeTable*'
TEST(Measure, DISABLED_SizeTable) {
  std::printf("%-40s %8s %8s %7s %9s %7s %9s %7s\n", "mesh", "V", "F", "conn.B", "conn.bpv", "geom.B",
              "geom.bpv", "q14.B");
  for (const auto& f : mesh_files((testing::shared_dir() / "meshes").string())) {
    QuadMesh m;
    try {
      m = load(f);
      build_adjacency(m);
    } catch (const Error&) {
      continue;
    }
    std::string bytes = encode(m);
    FileInfo info = inspect(bytes);
    EncodeOptions q;
    q.quantize_bits = 14;
    std::size_t q14 = encode(m, q).size();
    double v = static_cast<double>(m.vertex_count());
    std::printf("%-40s %8zu %8zu %7llu %9.4f %7llu %9.3f %7zu\n", fs::path(f).filename().c_str(),
                m.vertex_count(), m.face_count(), static_cast<unsigned long long>(info.connectivity_bytes),
                8.0 * info.connectivity_bytes / v, static_cast<unsigned long long>(info.geometry_bytes),
                8.0 * info.geometry_bytes / v, q14);
  }
}

}  // namespace
}  // namespace qsp
