// The .qsp codec: round trips, canonical bytes, keep-order, levels and tools, limits.
#include <gtest/gtest.h>

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

#include "codec_encode.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/partition.h"
#include "support/corpus.h"
#include "support/load.h"
#include "support/mesh_gen.h"
#include "support/quantized.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

// ---- Meshes ----

using testing::load;

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
      EXPECT_EQ(fi.geometry_tools & ~geometry_tool::kAll, 0) << int{fi.geometry_tools};
      EXPECT_EQ(fi.geometry_order, o);
      EXPECT_EQ(fi.level, kMaxLevel);
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

// The costly tools (cell shapes and logistic mixing) over every mesh of the corpus, lossless and at 14
// bits: forced on or off they decode to exactly the same mesh; the levels that try them (7 to 9) never
// write a larger file than the level below (6, which does not), and they are smaller on most meshes.
// The partition is fixed to keep this affordable under the sanitizers; both coding orders are tried.
TEST(Codec, CostlyToolsRoundTripAndNeverGrowAFile) {
  constexpr std::uint8_t kCostly = geometry_tool::kCellShapes | geometry_tool::kLogisticMixing;
  int tried = 0, smaller = 0, pawn_ratio_checked = 0;
  for (const auto& path : qsp::testing::corpus()) {
    QuadMesh mesh;
    if (!testing::read_valid(path, mesh)) continue;
    if (mesh.vertex_count() > kSearchVertexLimit || mesh.face_count() == 0) continue;
    SCOPED_TRACE(path.string());
    for (std::uint32_t bits : {0u, 14u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      o.partition = PartitionMode::kMotorcycle;
      o.level = 6;
      const std::string cheap = encode(mesh, o);
      o.level = 7;  // the lowest level that tries them
      const std::string chosen = encode(mesh, o);
      EXPECT_LE(chosen.size(), cheap.size()) << bits << " bits";
      const std::uint8_t tools = inspect(cheap).geometry_tools;
      EXPECT_EQ(tools & kCostly, 0);
      const std::string forced = encode_tuned(mesh, o, {static_cast<std::uint8_t>(tools | kCostly)});
      EXPECT_EQ(inspect(forced).geometry_tools & kCostly, kCostly);
      const QuadMesh a = decode(cheap), b = decode(forced), c = decode(chosen);
      EXPECT_EQ(a.quads, b.quads);
      EXPECT_EQ(c.quads, a.quads);
      ASSERT_EQ(a.positions.size(), b.positions.size());
      EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), 4 * a.positions.size()), 0)
          << bits << " bits";
      EXPECT_EQ(std::memcmp(c.positions.data(), a.positions.data(), 4 * a.positions.size()), 0);
      smaller += chosen.size() < cheap.size();
      if (bits == 14 && path.filename() == "osd_catmark_pawn.obj") {  // a surface of revolution
        // Without mirror prediction, which the pawn's symmetry also gains from (3.17).
        const auto plain = static_cast<std::uint8_t>(tools & ~geometry_tool::kMirror);
        const std::string none = encode_tuned(mesh, o, {plain});
        const std::string shapes = encode_tuned(mesh, o, {static_cast<std::uint8_t>(plain | kCostly)});
        EXPECT_LT(10 * shapes.size(), 7 * none.size())
            << "shape transfers: pawn " << shapes.size() << " vs " << none.size();
        ++pawn_ratio_checked;
      }
      ++tried;
    }
  }
  EXPECT_GE(tried, 20);
  EXPECT_GE(smaller, tried / 2) << "the costly tools are smaller on too few meshes";
  if (testing::shared_present()) {
    EXPECT_EQ(pawn_ratio_checked, 1);
  }
}

// Every combination of the geometry tools, forced, decodes to the mesh the default gives, in both
// coding orders, lossless and quantized (format-spec/geometry_section.md: every combination is valid).
TEST(Codec, EveryToolCombinationDecodes) {
  for (const char* name : {"mh_fedora.obj", "l_shape.obj", "multi_component.obj"}) {
    SCOPED_TRACE(name);
    const std::string path = std::string(QSP_TESTDATA_DIR) + "/" + name;
    const std::string alt = std::string(QSP_TESTDATA_DIR) + "/golden/" + name;
    const QuadMesh mesh = load(fs::exists(path) ? path : alt);
    for (std::uint32_t bits : {0u, 12u}) {
      EncodeOptions o;
      o.quantize_bits = bits;
      const QuadMesh want = decode(encode(mesh, o));
      for (CodingOrder order : {CodingOrder::kPatch, CodingOrder::kLayout}) {
        o.geometry_order = order;
        for (std::uint8_t tools = 0; tools <= geometry_tool::kAll; ++tools) {
          if (tools & geometry_tool::kLayoutOrder) continue;  // the order names it
          const std::string bytes = encode_tuned(mesh, o, {tools});
          const FileInfo info = inspect(bytes);
          EXPECT_EQ(info.geometry_tools & ~geometry_tool::kLayoutOrder, tools);
          EXPECT_EQ(info.geometry_order, order);
          const QuadMesh got = decode(bytes);
          ASSERT_EQ(got.positions.size(), want.positions.size());
          EXPECT_EQ(got.quads, want.quads) << int{tools};
          EXPECT_EQ(std::memcmp(got.positions.data(), want.positions.data(), 4 * want.positions.size()), 0)
              << bits << " bits, tools " << int{tools};
        }
      }
    }
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
