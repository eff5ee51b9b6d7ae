// Exact positions (format 3.6, the exact positions section): coordinates binary32 does not hold come
// back as the same binary64 values, bit for bit, whatever steps (decimal or binary64) their axis takes;
// renumbered copies give the same bytes; a quantized file has none; every prefix, bit flip and cut of
// the section is refused or decodes to values that round to their positions. (The shared CAD-like
// files through the tool, read back by the test's own parser: SharedMeshesCli in test_hostile.cpp.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/minor.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kExact = std::string(QSP_TESTDATA_DIR) + "/golden/exact/";

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), 8 * a.size()) == 0;
}

// Values of every kind an axis meets: decimals of 1 to 17 significant digits at many scales, arbitrary
// binary64 values near and far from their binary32, tiny ones, zeros of both signs, binary32 values.
std::vector<double> values_of_kind(int kind, std::size_t n, std::mt19937_64& rng) {
  std::vector<double> out(n);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = unit(rng);
    switch (kind) {
      case 0: {  // ten-decimal CAD text
        char text[64];
        std::snprintf(text, sizeof text, "%.10f", 40 * x);
        out[i] = std::strtod(text, nullptr);
        break;
      }
      case 1:  // printf("%.17g") of a computation: arbitrary binary64
        out[i] = std::cos(x * 7.1) / 3.0;
        break;
      case 2:  // tiny values, whose shortest texts need more than 22 decimals
        out[i] = x * 1e-11;
        break;
      case 3:  // binary32 values and signed zeros
        out[i] = i % 3 == 0 ? (i % 2 ? -0.0 : 0.0) : static_cast<double>(static_cast<float>(x));
        break;
      default: {  // few significant digits at a large scale
        char text[64];
        std::snprintf(text, sizeof text, "%.3e", 1e12 * x);
        out[i] = std::strtod(text, nullptr);
      }
    }
  }
  return out;
}

TEST(ExactPositions, SectionGivesBackEveryValueBitForBit) {
  std::mt19937_64 rng(5);
  for (int x = 0; x < 5; ++x) {
    for (int z = 0; z < 5; ++z) {
      SCOPED_TRACE("kinds " + std::to_string(x) + ", " + std::to_string(z));
      const std::size_t n = 37;
      const std::vector<double> xs = values_of_kind(x, n, rng), ys = values_of_kind((x + 1) % 5, n, rng),
                                zs = values_of_kind(z, n, rng);
      std::vector<double> exact;
      std::vector<float> f;
      for (std::size_t i = 0; i < n; ++i)
        for (double v : {xs[i], ys[i], zs[i]}) exact.push_back(v), f.push_back(static_cast<float>(v));
      const std::string payload = encode_exact_section(f, exact);
      EXPECT_TRUE(same_bits(decode_exact_section(payload, 0, f), exact));
    }
  }
}

TEST(ExactPositions, AnAxisTakesTheStepsItsTextHas) {
  // Ten-decimal text takes decimal steps of 10^-10; tiny values, binary64 steps; binary32 values, width 0.
  std::mt19937_64 rng(7);
  const std::size_t n = 20;
  const std::vector<double> xs = values_of_kind(0, n, rng), ys = values_of_kind(2, n, rng);
  std::vector<double> exact;
  std::vector<float> f;
  for (std::size_t i = 0; i < n; ++i)
    for (double v : {xs[i], ys[i], static_cast<double>(static_cast<float>(xs[i]))})
      exact.push_back(v), f.push_back(static_cast<float>(v));
  const std::string payload = encode_exact_section(f, exact);
  ASSERT_GE(payload.size(), 6u);
  EXPECT_EQ(payload[0], 10);
  EXPECT_EQ(payload[1], 64);
  EXPECT_EQ(payload[5], 0) << "binary32 values are their own binary32: every residual 0";
  EXPECT_LE(static_cast<int>(payload[3]), 17) << "ten decimals near 40 take about 16 bits";
}

TEST(ExactPositions, EncoderRefusesValuesThatDoNotRoundToTheirPositions) {
  const std::vector<float> f = {1.0f, 2.0f, 3.0f};
  EXPECT_THROW(encode_exact_section(f, std::vector<double>{1.0, 2.5, 3.0}), Error);
  EXPECT_THROW(encode_exact_section(f, std::vector<double>{1.0, 2.0, INFINITY}), Error);
}

std::vector<fs::path> exact_meshes() {
  std::vector<fs::path> files = {kExact + "grid_decimals.obj", kExact + "fan_float64_keep_order.obj"};
  for (const char* name : {"pmp_hole_capsule.off", "igl_inspired_mesh_quads_conjugate.off"})
    if (fs::exists(testing::shared_dir() / "meshes" / name))
      files.push_back(testing::shared_dir() / "meshes" / name);
  return files;
}

PolygonMesh read_exact(const fs::path& path) {
  const std::string text = testing::slurp(path);
  return to_polygon_mesh(
      path.extension() == ".off" ? read_off_mesh(text, path.string()) : read_obj_mesh(text, path.string()),
      kPolygonMeshCategories);
}

TEST(ExactPositions, FilesKeepThemAndRenumberedCopiesGiveTheSameBytes) {
  for (const fs::path& f : exact_meshes()) {
    SCOPED_TRACE(f.string());
    const PolygonMesh m = read_exact(f);
    ASSERT_EQ(m.positions64.size(), m.positions.size()) << "the reader keeps what binary32 does not hold";
    for (int level : {1, 9}) {
      EncodeOptions o;
      o.level = level;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_EQ(static_cast<int>(bytes[9]), testing::minor_of_file_with(bytes, 6))
          << "a file with exact positions says format 3.6";
      EXPECT_EQ(encode_polygons(testing::renumbered(m, 21), o), bytes);
      // Each decoded vertex's binary64 values are its input vertex's (found by its binary32 position).
      const PolygonMesh back = decode_polygons(bytes);
      ASSERT_EQ(back.positions64.size(), back.positions.size());
      for (std::size_t i = 0; i < back.positions64.size(); ++i)
        EXPECT_EQ(static_cast<float>(back.positions64[i]), back.positions[i]);
      o.keep_order = true;
      const PolygonMesh kept = decode_polygons(encode_polygons(m, o));
      EXPECT_TRUE(same_bits(kept.positions64, m.positions64));
      EXPECT_EQ(kept.corners, m.corners);
      // Quantized files are lossy: no exact positions.
      o.quantize_bits = 14;
      const std::string lossy = encode_polygons(m, o);
      EXPECT_EQ(container::parse(lossy).find(container::kTagExact), nullptr);
      EXPECT_TRUE(lossy[9] < 6 || lossy[9] == testing::minor_of_file_with(lossy, 0));
      EXPECT_TRUE(decode_polygons(lossy).positions64.empty());
    }
  }
}

// 1.0000000596046448 reads as the float64 1 + 2^-24, halfway between the float32s 1 and 1 + 2^-23; the
// text itself is nearer the second, which is what the reader's own float32 is. A lossless file codes
// the float32 nearest the float64 (1, ties to even) and gives the float64 back; --float32's rounding,
// the reader's, is the text's.
TEST(ExactPositions, AFloat64HalfwayBetweenTwoFloat32sCodesTheNearestOfIt) {
  const std::string text = "v 1.0000000596046448 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
  const PolygonMesh m = to_polygon_mesh(read_obj_mesh(text, "tie.obj"), kPolygonMeshCategories);
  ASSERT_EQ(m.positions64.size(), 12u);
  EXPECT_EQ(m.positions64[0], 1.0 + std::ldexp(1.0, -24));
  EXPECT_EQ(m.positions[0], 1.0f + std::ldexp(1.0f, -23)) << "the reader's float32 is the text's";
  const PolygonMesh back = decode_polygons(encode_polygons(m));
  bool found = false;
  for (std::size_t v = 0; v < back.vertex_count(); ++v) {
    if (back.positions64[3 * v] != 1.0 + std::ldexp(1.0, -24)) continue;
    found = true;
    EXPECT_EQ(back.positions[3 * v], 1.0f);
  }
  EXPECT_TRUE(found);
}

TEST(ExactPositions, TheQuadReaderRefusesAFileWithThem) {
  const std::string bytes = encode_polygons(read_exact(kExact + "grid_decimals.obj"));
  try {
    decode(bytes);
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("decode_polygons() reads them"), std::string::npos) << e.what();
  }
}

TEST(ExactPositions, ASectionInAQuantizedFileIsRefused) {
  const std::string quantized =
      testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/tilted_noise_q14.qsp");
  const std::string payload(6, '\0');  // decimal steps, width 0: every residual 0
  try {
    decode_polygons(container::with_section(quantized, container::kTagExact, payload, 6));
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(e.what()).find("quantized"), std::string::npos) << e.what();
  }
}

TEST(ExactPositions, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name : {"grid_decimals", "fan_float64_keep_order"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kExact + name + ".qsp");
    testing::sweep_section(good, container::kTagExact, 6, [](const PolygonMesh& got) {
      ASSERT_EQ(got.positions64.size(), got.positions.size());
      for (std::size_t i = 0; i < got.positions64.size(); ++i) {
        ASSERT_TRUE(std::isfinite(got.positions64[i]));
        ASSERT_EQ(std::bit_cast<std::uint32_t>(static_cast<float>(got.positions64[i])),
                  std::bit_cast<std::uint32_t>(got.positions[i]));
      }
    });
  }
}

}  // namespace
}  // namespace qsp
