// Exact texture coordinates, normals and colours (format 3.13, the exact values section): values binary32
// does not hold come back as the same binary64 values, bit for bit, with the order kept array for array
// and without it as the same (binary32, binary64) pairs; renumbered copies give the same bytes; an array
// coded on a grid has none; every bit flip and cut of the section is refused or decodes to values that
// round to their binary32s.
#include <gtest/gtest.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "support/corpus.h"
#include "support/files.h"
#include "support/polygon.h"
#include "support/section_sweep.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;

// Exact values near each binary32 of `f`: a decimal of 10 to 17 significant digits that rounds to it
// where there is one, else a binary64 a few ulps from it; a third of them the binary32 itself.
std::vector<double> near(const std::vector<float>& f, std::mt19937_64& rng) {
  std::vector<double> out(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double x = f[i];
    double d = x;
    switch (rng() % 3) {
      case 0:
        break;
      case 1: {  // a decimal text of `digits` significant digits
        char text[40];
        std::snprintf(text, sizeof text, "%.*e", static_cast<int>(9 + rng() % 8),
                      x + x * 1e-9 * double(rng() % 7));
        d = std::strtod(text, nullptr);
        break;
      }
      default:
        d = x;
        for (int k = static_cast<int>(rng() % 5) + 1; k > 0; --k) d = std::nextafter(d, 1e300);
    }
    if (static_cast<float>(d) != f[i] ||
        std::bit_cast<std::uint32_t>(static_cast<float>(d)) != std::bit_cast<std::uint32_t>(f[i]))
      d = x;  // must round to its binary32
    out[i] = d;
  }
  return out;
}

std::multiset<std::pair<std::uint32_t, std::uint64_t>> pairs(const std::vector<float>& f,
                                                             const std::vector<double>& d) {
  std::multiset<std::pair<std::uint32_t, std::uint64_t>> out;
  for (std::size_t i = 0; i < d.size(); ++i)
    out.emplace(std::bit_cast<std::uint32_t>(f[i]), std::bit_cast<std::uint64_t>(d[i]));
  return out;
}

// Whether the exact values say more than their binary32s (the spec's rule for writing a kind): some value
// is neither its binary32 nor the value of that binary32's shortest text.
bool needed(const std::vector<float>& f, const std::vector<double>& d) {
  for (std::size_t i = 0; i < d.size(); ++i) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, f[i]).ptr;
    const double shown = std::strtod(std::string(text, end).c_str(), nullptr);
    if (std::bit_cast<std::uint64_t>(d[i]) != std::bit_cast<std::uint64_t>(double{f[i]}) &&
        std::bit_cast<std::uint64_t>(d[i]) != std::bit_cast<std::uint64_t>(shown))
      return true;
  }
  return false;
}

// A 3x2 grid of quads in the plane, each vertex's texture coordinate its position scaled.
PolygonMesh grid() {
  PolygonMesh m;
  for (int y = 0; y <= 2; ++y)
    for (int x = 0; x <= 3; ++x) m.positions.insert(m.positions.end(), {float(x), float(y), 0.0f});
  for (std::uint32_t y = 0; y < 2; ++y)
    for (std::uint32_t x = 0; x < 3; ++x) {
      m.corners.insert(m.corners.end(), {4 * y + x, 4 * y + x + 1, 4 * y + x + 5, 4 * y + x + 4});
      m.face_offsets.push_back(static_cast<std::uint32_t>(m.corners.size()));
    }
  m.texcoord_components = 2;
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    m.texcoords.push_back(m.positions[3 * v] / 3 + 0.1f);
    m.texcoords.push_back(m.positions[3 * v + 1] / 2 + 0.1f);
  }
  m.corner_texcoords = m.corners;
  return m;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), 8 * a.size()) == 0);
}

// Every golden and shared OBJ with texture coordinates or normals (up to 20,000 faces), given exact
// values near its own, and colours (three components) per vertex and per face.
TEST(ExactValues, CorpusMeshesKeepThemExactly) {
  std::mt19937_64 rng(7);
  int tested = 0;
  std::vector<fs::path> files = testing::shared_meshes();
  for (const auto& e : fs::recursive_directory_iterator(fs::path(QSP_TESTDATA_DIR) / "golden"))
    files.push_back(e.path());
  for (const fs::path& path : files) {
    if (path.extension() != ".obj") continue;
    PolygonMesh m;
    try {
      m = testing::read_obj_polygons(path);
    } catch (const Error&) {
      continue;  // not a mesh: the corpus tests say which
    }
    if ((m.texcoords.empty() && m.normals.empty()) || m.face_count() > 20000) continue;
    SCOPED_TRACE(path.string());
    m.tags.clear();  // some (vertexedit) need the order kept; they are not what this tests
    m.texcoords64 = near(m.texcoords, rng);
    m.normals64 = near(m.normals, rng);
    if (m.vertex_color_components == 0) {
      m.vertex_color_components = 3;
      for (std::size_t i = 0; i < 3 * m.vertex_count(); ++i)
        m.vertex_colors.push_back(float(rng() % 1000) / 999);
    }
    if (m.face_color_components == 0) {
      m.face_color_components = 3;
      for (std::size_t i = 0; i < 3 * m.face_count(); ++i) m.face_colors.push_back(float(rng() % 1000) / 999);
    }
    m.vertex_colors64 = near(m.vertex_colors, rng);
    m.face_colors64 = near(m.face_colors, rng);
    for (bool keep : {false, true}) {
      EncodeOptions o;
      o.keep_order = keep;
      const std::string bytes = encode_polygons(m, o);
      EXPECT_NE(container::parse(bytes).find(container::kTagExactValues), nullptr);
      const PolygonMesh back = decode_polygons(bytes);
      for (const auto& [f, d, bf, bd] :
           {std::tuple{&m.texcoords, &m.texcoords64, &back.texcoords, &back.texcoords64},
            std::tuple{&m.normals, &m.normals64, &back.normals, &back.normals64},
            std::tuple{&m.vertex_colors, &m.vertex_colors64, &back.vertex_colors, &back.vertex_colors64},
            std::tuple{&m.face_colors, &m.face_colors64, &back.face_colors, &back.face_colors64}}) {
        if (!needed(*f, *d)) {
          EXPECT_TRUE(bd->empty());
          continue;
        }
        ASSERT_EQ(bd->size(), d->size());
        EXPECT_EQ(pairs(*bf, *bd), pairs(*f, *d));
        if (keep) {
          EXPECT_TRUE(same_bits(*bd, *d));
        }
      }
      if (!keep) {
        EXPECT_EQ(encode_polygons(testing::renumbered(m, 3), o), bytes) << "canonical";
      }
    }
    ++tested;
  }
  EXPECT_GE(tested, 10);
  if (testing::shared_present()) {
    EXPECT_GE(tested, 30);
  }
}

// A texture coordinate on its grid, octahedral normals and quantized colours carry no exact values: the
// grid is the value.
TEST(ExactValues, ArraysOnAGridHaveNone) {
  PolygonMesh m = grid();
  std::mt19937_64 rng(3);
  m.texcoords64 = near(m.texcoords, rng);
  m.texcoords64[0] = 0.1000000000001;
  m.texcoords[0] = static_cast<float>(m.texcoords64[0]);
  EncodeOptions o;
  EXPECT_NE(container::parse(encode_polygons(m, o)).find(container::kTagExactValues), nullptr);
  o.quantize_texcoord_bits = 12;
  const std::string bytes = encode_polygons(m, o);
  EXPECT_EQ(container::parse(bytes).find(container::kTagExactValues), nullptr);
  EXPECT_TRUE(decode_polygons(bytes).texcoords64.empty());
  // Values that are the texts of their binary32s ("0.1", whose binary64 is not 0.1f's) need none either.
  for (std::size_t i = 0; i < m.texcoords.size(); ++i) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, m.texcoords[i]).ptr;
    m.texcoords64[i] = std::strtod(std::string(text, end).c_str(), nullptr);
  }
  EXPECT_FALSE(needed(m.texcoords, m.texcoords64));
  EXPECT_EQ(container::parse(encode_polygons(m, {})).find(container::kTagExactValues), nullptr);
}

// Every prefix and bit flip of the file is refused; every bit flip and cut of the section, resealed,
// is refused with a format error naming a byte offset or decodes to values rounding to their binary32s.
TEST(ExactValues, EveryPrefixBitFlipAndCutIsSafe) {
  const std::string good =
      testing::slurp(std::string(QSP_TESTDATA_DIR) + "/golden/exact/values_uv_normals.qsp");
  ASSERT_NE(container::parse(good).find(container::kTagExactValues), nullptr);
  const int decoded =
      testing::sweep_section(good, container::kTagExactValues, good[9], [](const PolygonMesh& got) {
        for (const auto& [f, d] :
             {std::pair{&got.texcoords, &got.texcoords64}, std::pair{&got.normals, &got.normals64}}) {
          if (d->empty()) continue;
          ASSERT_EQ(d->size(), f->size());
          for (std::size_t i = 0; i < d->size(); ++i)
            ASSERT_EQ(std::bit_cast<std::uint32_t>(static_cast<float>((*d)[i])),
                      std::bit_cast<std::uint32_t>((*f)[i]));
        }
      });
  EXPECT_GT(decoded, 0) << "some flips change a residual to another value of the same binary32";
}

}  // namespace
}  // namespace qsp
