// Colours (format 3.8, the colours section): vertex colours (3 or 4 components) and face colours (1, 3
// or 4) come back value for value, bit for bit, whatever their values (decimals, PLY bytes, arbitrary
// floats, -0); renumbered copies give the same bytes at every level; --quantize-color rounds to its
// grid; every prefix, bit flip and cut of the section is refused or decodes to finite colours. (The
// files through the tool, read back by the test's own parser: ColorsCli in test_cli_colors.cpp.)
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "support/files.h"
#include "support/minor.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

const std::string kColors = std::string(QSP_TESTDATA_DIR) + "/golden/colors/";

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), 4 * a.size()) == 0);
}

// `n` values of one kind: 0 three-decimal text, 1 PLY bytes (0-255), 2 arbitrary floats of both signs
// (and -0), 3 one value for all (a flat colour), 4 bytes with a few far-off floats among them.
std::vector<float> values_of_kind(int kind, std::size_t n, std::mt19937& rng) {
  std::vector<float> out(n);
  std::uniform_real_distribution<float> unit(0, 1);
  for (std::size_t i = 0; i < n; ++i) {
    const float x = unit(rng);
    switch (kind) {
      case 0:
        out[i] = std::strtof(std::to_string(std::round(x * 1000) / 1000).c_str(), nullptr);
        break;
      case 1:
        out[i] = std::floor(x * 256);
        break;
      case 2:
        out[i] = i % 7 == 3 ? -0.0f : (x - 0.3f) * std::ldexp(1.0f, static_cast<int>(rng() % 40) - 20);
        break;
      case 3:
        out[i] = 0.5f;
        break;
      default:
        out[i] = i % 11 == 5 ? 1e5f * x : std::floor(x * 256);
    }
  }
  return out;
}

// A mesh of the goldens (quads, or polygons: triangles, n-gons, cut vertices).
std::vector<fs::path> meshes() {
  std::vector<fs::path> out;
  for (const char* dir : {"", "polygons/"})
    for (const auto& e : fs::directory_iterator(std::string(QSP_TESTDATA_DIR) + "/golden/" + dir))
      if (e.path().extension() == ".obj") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// `m` with colours: vertex ones of `kv` components, face ones of `kf`, each component its own kind.
PolygonMesh coloured(PolygonMesh m, unsigned kv, unsigned kf, std::uint32_t seed) {
  std::mt19937 rng(seed);
  const auto fill = [&](std::vector<float>& values, std::size_t count, unsigned K) {
    values.assign(count * K, 0.0f);
    for (unsigned c = 0; c < K; ++c) {
      const std::vector<float> v = values_of_kind(static_cast<int>((seed + c) % 5), count, rng);
      for (std::size_t i = 0; i < count; ++i) values[K * i + c] = v[i];
    }
  };
  m.vertex_color_components = static_cast<std::uint8_t>(kv);
  fill(m.vertex_colors, kv ? m.vertex_count() : 0, kv);
  m.face_color_components = static_cast<std::uint8_t>(kf);
  fill(m.face_colors, kf ? m.face_count() : 0, kf);
  return m;
}

// Each vertex's colour by its position, each face's by its corners' positions (from the smallest), so
// a canonical file's renumbering is free.
using Position = std::array<float, 3>;
std::map<Position, std::vector<float>> vertex_colors_by_position(const PolygonMesh& m) {
  std::map<Position, std::vector<float>> out;
  const std::size_t K = m.vertex_color_components;
  for (std::size_t v = 0; v < m.vertex_count() && K; ++v)
    out[{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}].assign(
        m.vertex_colors.begin() + static_cast<std::ptrdiff_t>(K * v),
        m.vertex_colors.begin() + static_cast<std::ptrdiff_t>(K * v + K));
  return out;
}
std::multimap<std::vector<Position>, std::vector<std::uint32_t>> face_colors_by_corners(
    const PolygonMesh& m) {
  std::multimap<std::vector<Position>, std::vector<std::uint32_t>> out;
  const std::size_t K = m.face_color_components;
  for (std::size_t f = 0; f < m.face_count() && K; ++f) {
    std::vector<Position> corners;
    for (std::uint32_t c = m.face_offsets[f]; c < m.face_offsets[f + 1]; ++c) {
      const std::uint32_t v = m.corners[c];
      corners.push_back({m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]});
    }
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
    std::vector<std::uint32_t> bits(K);
    std::memcpy(bits.data(), &m.face_colors[K * f], 4 * K);
    out.emplace(corners, bits);
  }
  return out;
}

TEST(Colors, SectionGivesBackEveryValueBitForBit) {
  const PolygonMesh mesh =
      testing::read_obj_polygons(std::string(QSP_TESTDATA_DIR) + "/golden/polygons/polygons_mixed.obj");
  ASSERT_GT(mesh.face_count(), 2u);
  const auto nv = static_cast<std::uint32_t>(mesh.vertex_count());
  for (unsigned kv : {0u, 3u, 4u}) {
    for (unsigned kf : {0u, 1u, 3u, 4u}) {
      if (!kv && !kf) continue;
      for (std::uint32_t seed = 0; seed < 5; ++seed) {
        SCOPED_TRACE(std::to_string(kv) + " vertex, " + std::to_string(kf) + " face components, seed " +
                     std::to_string(seed));
        const PolygonMesh m = coloured(mesh, kv, kf, seed);
        const std::string payload =
            encode_colors_section(m.face_offsets, m.corners, nv, static_cast<std::uint8_t>(kv),
                                  m.vertex_colors, static_cast<std::uint8_t>(kf), m.face_colors, 0);
        const DecodedColors back = decode_colors_section(payload, 0, m.face_offsets, m.corners, nv);
        EXPECT_EQ(back.vertex_components, kv);
        EXPECT_EQ(back.face_components, kf);
        EXPECT_TRUE(same_bits(back.vertex, m.vertex_colors));
        EXPECT_TRUE(same_bits(back.face, m.face_colors));
      }
    }
  }
}

TEST(Colors, EncoderRefusesWhatTheFormatCannotHold) {
  PolygonMesh m = coloured(testing::read_obj_polygons(kColors + "grid_rgb.obj"), 3, 0, 1);
  const auto nv = static_cast<std::uint32_t>(m.vertex_count());
  const auto section = [&](std::uint8_t kv, std::uint8_t kf, std::uint32_t bits) {
    return encode_colors_section(m.face_offsets, m.corners, nv, kv, m.vertex_colors, kf, m.face_colors, bits);
  };
  EXPECT_THROW(section(2, 0, 0), Error);   // two components
  EXPECT_THROW(section(0, 0, 0), Error);   // nothing
  EXPECT_THROW(section(3, 0, 25), Error);  // a grid finer than 2^-24
  m.vertex_colors[4] = NAN;
  try {
    section(3, 0, 0);
    FAIL() << "encoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kBadNumber);
    EXPECT_NE(std::string(e.what()).find("vertex colour 1"), std::string::npos) << e.what();
  }
}

TEST(Colors, FilesKeepThemAndRenumberedCopiesGiveTheSameBytes) {
  std::uint32_t seed = 0;
  for (const fs::path& f : meshes()) {
    SCOPED_TRACE(f.string());
    const PolygonMesh plain = testing::read_obj_polygons(f);
    for (const auto& [kv, kf] :
         {std::pair{3u, 0u}, std::pair{4u, 1u}, std::pair{0u, 3u}, std::pair{3u, 4u}}) {
      const PolygonMesh m = coloured(plain, kv, kf, ++seed);
      for (int level : {1, 9}) {
        EncodeOptions o;
        o.level = level;
        const std::string bytes = encode_polygons(m, o);
        EXPECT_EQ(static_cast<int>(bytes[9]), testing::minor_of_file_with(bytes, 8))
            << "a file with colours says format 3.8";
        EXPECT_EQ(encode_polygons(testing::renumbered(m, seed), o), bytes);
        const PolygonMesh back = decode_polygons(bytes);
        EXPECT_EQ(vertex_colors_by_position(back), vertex_colors_by_position(m));
        EXPECT_EQ(face_colors_by_corners(back), face_colors_by_corners(m));
        o.keep_order = true;
        const PolygonMesh kept = decode_polygons(encode_polygons(m, o));
        EXPECT_EQ(kept.corners, m.corners);
        EXPECT_TRUE(same_bits(kept.vertex_colors, m.vertex_colors));
        EXPECT_TRUE(same_bits(kept.face_colors, m.face_colors));
        EXPECT_EQ(inspect(bytes).color_bytes, container::parse(bytes).find(container::kTagColors)->size());
      }
    }
  }
}

// --quantize-color BITS: a component goes to the grid of step 2^-BITS, within half a step, unless it is
// exactly on a decimal grid at least as coarse (bytes; three decimals at 12 bits), which it keeps; the
// vertex colours' kinds here are 2, 3, 4, 0 (arbitrary floats, one value, bytes with far-off floats,
// three decimals) and the faces' 2, 3, 4.
TEST(Colors, QuantizedColoursAreOnTheirGridOrACoarserDecimalOne) {
  const PolygonMesh plain = testing::read_obj_polygons(kColors + "grid_rgb.obj");
  for (std::uint32_t bits : {4u, 8u, 12u}) {
    SCOPED_TRACE(bits);
    const PolygonMesh m = coloured(plain, 4, 3, 7);
    EncodeOptions o;
    o.keep_order = true;
    o.quantize_color_bits = bits;
    const PolygonMesh back = decode_polygons(encode_polygons(m, o));
    ASSERT_EQ(back.vertex_colors.size(), m.vertex_colors.size());
    ASSERT_EQ(back.face_colors.size(), m.face_colors.size());
    const double half = std::ldexp(1.0, -static_cast<int>(bits) - 1);
    for (const auto& [got, want, K] : {std::tuple{&back.vertex_colors, &m.vertex_colors, 4u},
                                       std::tuple{&back.face_colors, &m.face_colors, 3u}}) {
      for (unsigned c = 0; c < K; ++c) {
        bool on_grid = true, exact = true, bytes = true;
        for (std::size_t i = c; i < want->size(); i += K) {
          const double x = (*want)[i], y = (*got)[i];
          EXPECT_LE(std::fabs(x - y), half) << i;
          on_grid = on_grid && std::ldexp(y, static_cast<int>(bits)) ==
                                   std::nearbyint(std::ldexp(y, static_cast<int>(bits)));
          exact = exact && std::bit_cast<std::uint32_t>(static_cast<float>(x)) ==
                               std::bit_cast<std::uint32_t>(static_cast<float>(y));
          bytes = bytes && x == std::floor(x) && x >= 0 && x < 256;
        }
        EXPECT_TRUE(on_grid || exact) << "component " << c;
        if (bytes) {
          EXPECT_TRUE(exact) << "bytes stay exact, component " << c;
        }
      }
    }
  }
  // Byte colours: the quantized file is the lossless one.
  const PolygonMesh bytes = coloured(plain, 3, 0, 1);  // kinds 1, 2, 3: bytes first
  PolygonMesh only_bytes = bytes;
  for (std::size_t i = 0; i < only_bytes.vertex_colors.size(); ++i)
    only_bytes.vertex_colors[i] = bytes.vertex_colors[i - i % 3];
  EncodeOptions q;
  q.quantize_color_bits = 8;
  EXPECT_EQ(encode_polygons(only_bytes, q), encode_polygons(only_bytes));
}

TEST(Colors, TheQuadReaderRefusesAFileWithThem) {
  const std::string bytes = testing::slurp(kColors + "grid_rgb.qsp");
  try {
    decode(bytes);
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("colours"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("decode_polygons() reads them"), std::string::npos) << e.what();
  }
}

TEST(Colors, ATinySectionCannotDeclareAHugeMesh) {
  // The mesh implies its component count: a section of a few bytes over many vertices is refused before
  // its values are decoded.
  PolygonMesh big;
  big.positions.assign(3 * 100000, 0.0f);
  const std::string payload = std::string(1, '\x03') + std::string(3, '\x01');  // 3 components, 0 decimals
  try {
    decode_colors_section(payload, 0, big.face_offsets, big.corners, 100000);
    FAIL() << "decoded";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    EXPECT_NE(std::string(e.what()).find("cannot fit"), std::string::npos) << e.what();
  }
}

TEST(Colors, EveryPrefixBitFlipAndCutIsSafe) {
  for (const char* name : {"grid_rgb", "polygons_rgba_keep_order"}) {
    SCOPED_TRACE(name);
    const std::string good = testing::slurp(kColors + name + ".qsp");
    testing::sweep_section(good, container::kTagColors, 8, [](const PolygonMesh& got) {
      ASSERT_EQ(got.vertex_colors.size(), got.vertex_color_components * got.vertex_count());
      ASSERT_EQ(got.face_colors.size(), got.face_color_components * got.face_count());
      for (const float x : got.vertex_colors) ASSERT_TRUE(std::isfinite(x));
      for (const float x : got.face_colors) ASSERT_TRUE(std::isfinite(x));
    });
  }
}

}  // namespace
}  // namespace qsp
