// Geometry coder (src/geometry_coder.h): bit-exact round trips, decimal grids, quantization bounds, the
// tools the search chooses, hostile bytes.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "geometry_coder.h"
#include "geometry_values.h"
#include "layout_grid.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/partition.h"
#include "stencil.h"
#include "support/corpus.h"

namespace {

using qsp::GridLayout;
using qsp::kInvalid;
using qsp::Stencil;
namespace tool = qsp::geometry_tool;
constexpr std::uint8_t kCostly = tool::kCellShapes | tool::kLogisticMixing;

// One a x b grid numbered row by row, like a patch's inner vertices in grid_layout.
std::vector<Stencil> grid_stencil(std::uint32_t a, std::uint32_t b) {
  std::vector<Stencil> st(static_cast<std::size_t>(a) * b);
  for (std::uint32_t r = 0; r < b; ++r) {
    for (std::uint32_t c = 0; c < a; ++c) {
      Stencil& s = st[r * a + c];
      const std::uint32_t i = r * a + c;
      if (c > 0) s.w = i - 1;
      if (c > 1) s.ww = i - 2;
      if (r > 0) s.s = i - a;
      if (r > 0 && c > 0) s.sw = i - a - 1;
    }
  }
  return st;
}

float parse(const std::string& text) {
  float f = 0;
  std::from_chars(text.data(), text.data() + text.size(), f);
  return f;
}

// A smooth surface written with `decimals` decimals, as an OBJ exporter would.
std::vector<float> smooth_positions(std::uint32_t a, std::uint32_t b, int decimals) {
  std::vector<float> p;
  char buf[64];
  for (std::uint32_t r = 0; r < b; ++r) {
    for (std::uint32_t c = 0; c < a; ++c) {
      const double u = c / 10.0, v = r / 10.0;
      for (double x : {u + 0.1 * std::sin(v), v - 0.05 * u * u, 0.3 * std::sin(u) * std::cos(v) - 0.2}) {
        std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
        p.push_back(parse(buf));
      }
    }
  }
  return p;
}

// "%g" output (6 significant digits) over several decades: many decimals for small values, trailing
// zeros for large ones.
std::vector<float> significant_positions(std::uint32_t a, std::uint32_t b) {
  std::vector<float> p;
  char buf[64];
  for (std::uint32_t r = 0; r < b; ++r)
    for (std::uint32_t c = 0; c < a; ++c)
      for (double x :
           {0.45 * std::sin(c * 0.1 + 0.05 + r * 0.013) * std::pow(10.0, -static_cast<double>(r % 3)),
            0.8 * std::sin(r * 0.05) + 0.001 * c, 0.02 * r + 0.01 * c - 0.3}) {
        std::snprintf(buf, sizeof buf, "%g", x);
        p.push_back(parse(buf));
      }
  return p;
}

bool bit_equal(const std::vector<float>& x, const std::vector<float>& y) {
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (std::bit_cast<std::uint32_t>(x[i]) != std::bit_cast<std::uint32_t>(y[i])) return false;
  }
  return true;
}

void expect_format_error(std::string_view bytes, const std::vector<Stencil>& st, std::uint32_t count);

std::vector<float> round_trip(const std::vector<float>& pos, const std::vector<Stencil>& st,
                              std::uint32_t bits = 0, std::size_t* size = nullptr) {
  const std::string bytes = qsp::encode_geometry(pos, st, {bits});
  if (size) *size = bytes.size();
  return qsp::decode_geometry(bytes, 0, st, static_cast<std::uint32_t>(st.size()));
}

TEST(Geometry, EmptyAndSingleVertex) {
  std::vector<Stencil> none;
  EXPECT_TRUE(round_trip({}, none).empty());
  EXPECT_TRUE(round_trip({}, none, 12).empty());
  const std::vector<float> one = {1.5f, -0.0f, 3e-42f};
  EXPECT_TRUE(bit_equal(round_trip(one, grid_stencil(1, 1)), one));
  const std::vector<float> q = round_trip(one, grid_stencil(1, 1), 8);
  EXPECT_LE(qsp::max_geometry_error(one, q), 1e-6);
}

TEST(Geometry, DecimalGridIsExactAndSmall) {
  const auto st = grid_stencil(40, 30);
  for (int decimals : {0, 1, 4, 6}) {
    const auto pos = smooth_positions(40, 30, decimals);
    std::size_t size = 0;
    EXPECT_TRUE(bit_equal(round_trip(pos, st, 0, &size), pos)) << decimals;
    if (decimals == 4) {
      EXPECT_LT(size * 8.0 / 1200, 12.0);  // raw floats would be 96 bits
    }
  }
}

TEST(Geometry, DecimalGridBeatsFloatBits) {
  // Same surface, 4 decimals vs the float nearest to the real value: the former must be cheaper.
  const auto st = grid_stencil(40, 30);
  const auto dec = smooth_positions(40, 30, 4);
  std::vector<float> exact;
  for (std::uint32_t r = 0; r < 30; ++r)
    for (std::uint32_t c = 0; c < 40; ++c) {
      const double u = c / 10.0, v = r / 10.0;
      exact.push_back(static_cast<float>(u + 0.1 * std::sin(v)));
      exact.push_back(static_cast<float>(v - 0.05 * u * u));
      exact.push_back(static_cast<float>(0.3 * std::sin(u) * std::cos(v) - 0.2));
    }
  std::size_t dec_size = 0, exact_size = 0;
  EXPECT_TRUE(bit_equal(round_trip(dec, st, 0, &dec_size), dec));
  EXPECT_TRUE(bit_equal(round_trip(exact, st, 0, &exact_size), exact));
  EXPECT_LT(dec_size, exact_size);
}

TEST(Geometry, DecimalGridWithExceptions) {
  // A few -0, NaN, inf and off-grid values must not push the whole axis out of decimal mode.
  const auto st = grid_stencil(30, 30);
  auto pos = smooth_positions(30, 30, 4);
  std::size_t clean = 0;
  round_trip(pos, st, 0, &clean);
  pos[3] = -0.0f;
  pos[100] = std::bit_cast<float>(0x7FC01234u);
  pos[200] = std::numeric_limits<float>::infinity();
  pos[301] = 0.123456789f;
  std::size_t size = 0;
  EXPECT_TRUE(bit_equal(round_trip(pos, st, 0, &size), pos));
  EXPECT_LT(size, clean + 4 * 12);  // about the raw float bits of each
}

TEST(Geometry, SignificantDigitsUseTrailingZeros) {
  const auto st = grid_stencil(30, 30);
  const std::vector<float> pos = significant_positions(30, 30);
  const std::string b = qsp::encode_geometry(pos, st, {});
  EXPECT_TRUE(bit_equal(qsp::decode_geometry(b, 0, st, 900), pos));
  EXPECT_EQ(static_cast<std::uint8_t>(b[2]) & 0x80, 0x80);  // x: trailing-zero coding
  // The mode bit alone must not be accepted on a float-bits axis.
  std::string bad = b;
  bad[2] = static_cast<char>(0x80);
  expect_format_error(bad, st, 900);
}

TEST(Geometry, DecimalGridValueMatchesFromChars) {
  std::mt19937_64 rng(7);
  for (int k = 0; k <= 9; ++k) {
    for (int t = 0; t < 20000; ++t) {
      // Mix small and large magnitudes; large odd integers hit binary32 midpoints.
      const int bits = 1 + static_cast<int>(rng() % 40);
      std::int64_t n = static_cast<std::int64_t>(rng() & ((std::uint64_t{1} << bits) - 1));
      if (rng() & 1) n = -n;
      const std::string text = std::to_string(n) + "e-" + std::to_string(k);
      EXPECT_EQ(std::bit_cast<std::uint32_t>(qsp::decimal_grid_value(n, k)),
                std::bit_cast<std::uint32_t>(parse(text)))
          << text;
    }
  }
  // Exact midpoints: 2^24 + 1 lies halfway between two floats; ties go to even.
  for (std::int64_t n : {16777217ll, 16777219ll, 33554434ll, 33554438ll, -16777217ll}) {
    EXPECT_EQ(qsp::decimal_grid_value(n, 0), parse(std::to_string(n)));
    EXPECT_EQ(qsp::decimal_grid_value(n * 10, 1), parse(std::to_string(n)));
  }
  EXPECT_THROW(qsp::decimal_grid_value(std::int64_t{1} << 40, 0), qsp::Error);
  EXPECT_THROW(qsp::decimal_grid_value(1, 10), qsp::Error);
}

TEST(Geometry, RandomBitsAndSpecialValuesAreBitExact) {
  std::mt19937 rng(1);
  const auto st = grid_stencil(17, 13);
  std::vector<float> pos(st.size() * 3);
  for (float& f : pos) f = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
  const std::vector<std::uint32_t> special = {0x00000000u, 0x80000000u, 0x00000001u, 0x80000001u, 0x007FFFFFu,
                                              0x807FFFFFu, 0x00800000u, 0x7F7FFFFFu, 0xFF7FFFFFu, 0x7F800000u,
                                              0xFF800000u, 0x7FC00000u, 0xFFC00000u, 0x7F800001u, 0x7FBFFFFFu,
                                              0xFFFFFFFFu, 0x3F800000u, 0xBF800000u};
  for (std::size_t i = 0; i < special.size(); ++i) pos[5 * i] = std::bit_cast<float>(special[i]);
  EXPECT_TRUE(bit_equal(round_trip(pos, st), pos));
  // All specials on one smooth row so predictions straddle them.
  auto smooth = smooth_positions(17, 13, 7);
  for (std::size_t i = 0; i < special.size(); ++i) smooth[3 * (i + 17)] = std::bit_cast<float>(special[i]);
  EXPECT_TRUE(bit_equal(round_trip(smooth, st), smooth));
}

TEST(Geometry, FloatModeOnNoisyData) {
  // Smooth values plus float-level noise: no decimal grid fits, so float bits are coded.
  std::mt19937 rng(3);
  const auto st = grid_stencil(50, 40);
  std::vector<float> pos;
  std::uniform_real_distribution<double> noise(-1e-3, 1e-3);
  for (std::uint32_t r = 0; r < 40; ++r)
    for (std::uint32_t c = 0; c < 50; ++c) {
      pos.push_back(static_cast<float>(c * 0.01 + noise(rng)));
      pos.push_back(static_cast<float>(100 + r * 0.01 + noise(rng)));
      pos.push_back(static_cast<float>(-1e-5 * c * r + noise(rng) * 1e-3));
    }
  std::size_t size = 0;
  EXPECT_TRUE(bit_equal(round_trip(pos, st, 0, &size), pos));
  EXPECT_LT(size, pos.size() * 4);
}

TEST(Geometry, MixedAxisModes) {
  // x on a 4-decimal grid, y plain floats, z on a 2-decimal grid: integer and float axes together.
  std::mt19937 rng(5);
  const auto st = grid_stencil(20, 20);
  auto pos = smooth_positions(20, 20, 4);
  for (std::size_t i = 1; i < pos.size(); i += 3)
    pos[i] = pos[i] + std::ldexp(static_cast<float>(rng() % 1000), -30);
  for (std::size_t i = 2; i < pos.size(); i += 3)
    pos[i] = parse(std::to_string(static_cast<int>(rng() % 300)) + "e-2");
  EXPECT_TRUE(bit_equal(round_trip(pos, st), pos));
  // Header: tools (bit 1: layout order, the default of GeometryOptions), lossless, then per axis mode
  // (+ exception count for decimal axes).
  const std::string b = qsp::encode_geometry(pos, st, {});
  // (Bit 7 of a mode byte, trailing-zero coding, and tool bit 0, value repeats, are the encoder's choice.)
  std::string header = b.substr(0, 7);
  header[0] = static_cast<char>(header[0] & ~tool::kValueRepeats);
  header[2] = static_cast<char>(header[2] & 0x7F);
  header[5] = static_cast<char>(header[5] & 0x7F);
  EXPECT_EQ(header, std::string("\x02\x00\x05\x00\x00\x03\x00", 7));
}

// A grid on the plane spanned by orthonormal u and v, each vertex moved along the normal u x v by
// uniform noise of +-0.25 (the spacing is 1), written with 3 decimals.
std::vector<float> noisy_plane(std::uint32_t a, std::uint32_t b, const std::array<double, 3>& u,
                               const std::array<double, 3>& v) {
  const std::array<double, 3> n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                   u[0] * v[1] - u[1] * v[0]};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.25, 0.25);
  std::vector<float> p;
  char buf[64];
  for (std::uint32_t r = 0; r < b; ++r) {
    for (std::uint32_t c = 0; c < a; ++c) {
      const double h = noise(rng);
      for (int k = 0; k < 3; ++k) {
        std::snprintf(buf, sizeof buf, "%.3f", c * u[k] + r * v[k] + h * n[k]);
        p.push_back(parse(buf));
      }
    }
  }
  return p;
}

// Normal chaining: where residuals lie along the surface normal, the encoder finds the chained section
// smaller and writes it, lossless and quantized, with the cheaper tools or the costly ones, and it
// decodes bit-exact. Where the normal is an axis there is nothing to chain, and the section stays
// unchained.
TEST(Geometry, NormalChainingWhereResidualsFollowTheNormal) {
  const auto st = grid_stencil(30, 30);
  const auto tilted = noisy_plane(30, 30, {2 / 3.0, 1 / 3.0, 2 / 3.0}, {1 / 3.0, 2 / 3.0, -2 / 3.0});
  const auto flat = noisy_plane(30, 30, {1, 0, 0}, {0, 1, 0});
  for (std::uint32_t bits : {0u, 14u}) {
    for (const bool costly : {false, true}) {
      SCOPED_TRACE(::testing::Message() << bits << (costly ? " bits, costly tools tried" : " bits"));
      qsp::GeometryOptions opt{bits};
      opt.try_costly_tools = costly;
      const std::string t = qsp::encode_geometry(tilted, st, opt);
      EXPECT_EQ(t[0] & tool::kNormalChaining, tool::kNormalChaining);
      const auto back = qsp::decode_geometry(t, 0, st, static_cast<std::uint32_t>(st.size()));
      if (bits == 0) {
        EXPECT_TRUE(bit_equal(back, tilted));
      } else {
        EXPECT_LT(qsp::max_geometry_error(tilted, back), 1.3e-3);  // half a step: extent ~39 / (2^14 - 1)
      }
      const std::string f = qsp::encode_geometry(flat, st, opt);
      EXPECT_EQ(f[0] & tool::kNormalChaining, 0);
    }
  }
}

TEST(Geometry, PartialStencils) {
  // Columns without w (south only), rows without s, and stencils with ww/sw but no w.
  auto st = grid_stencil(9, 7);
  for (std::size_t i = 0; i < st.size(); i += 4) st[i].w = kInvalid;
  for (std::size_t i = 0; i < st.size(); i += 5) st[i].sw = kInvalid;
  const auto pos = smooth_positions(9, 7, 3);
  EXPECT_TRUE(bit_equal(round_trip(pos, st), pos));
  const auto q = round_trip(pos, st, 20);
  EXPECT_LT(qsp::max_geometry_error(pos, q), 1e-5);
}

TEST(Geometry, NoStencilAtAll) {
  // Vertices with no grid neighbours (schematic corners) predict from the previous vertex.
  std::vector<Stencil> st(500);
  const auto pos = smooth_positions(25, 20, 4);
  EXPECT_TRUE(bit_equal(round_trip(pos, st), pos));
  const auto q = round_trip(pos, st, 16);
  EXPECT_LT(qsp::max_geometry_error(pos, q), 1e-4);
}

TEST(Geometry, QuantizationErrorBound) {
  const auto st = grid_stencil(30, 20);
  auto pos = smooth_positions(30, 20, 6);
  pos[7] = -1e-30f;
  double extent = 0;
  for (int a = 0; a < 3; ++a) {
    float lo = pos[a], hi = pos[a];
    for (std::size_t i = a; i < pos.size(); i += 3) lo = std::min(lo, pos[i]), hi = std::max(hi, pos[i]);
    extent = std::max(extent, double{hi} - lo);
  }
  for (std::uint32_t bits = 1; bits <= 30; ++bits) {
    const auto q = round_trip(pos, st, bits);
    ASSERT_EQ(q.size(), pos.size());
    const double step = extent / ((std::uint64_t{1} << bits) - 1);
    // Half a step (rounded up to 23 bits) plus the final rounding to float.
    EXPECT_LE(qsp::max_geometry_error(pos, q), 0.5 * step * (1 + 1e-6) + 4e-7) << bits;
    for (float f : q) EXPECT_TRUE(std::isfinite(f));
  }
}

// No residual-length decision whose outcome the grid size forces is coded: the same all-zero residuals
// cost less at 1 bit (one decision per coordinate) than at 2 bits (two), where coding all six
// decisions at either size gave equal payloads.
TEST(Geometry, LengthsAboveTheMaximumAreNotCoded) {
  const auto st = grid_stencil(100, 100);
  const std::vector<float> flat(3 * st.size(), 0.0f);
  std::size_t one = 0, two = 0;
  EXPECT_TRUE(bit_equal(round_trip(flat, st, 1, &one), flat));
  EXPECT_TRUE(bit_equal(round_trip(flat, st, 2, &two), flat));
  EXPECT_LT(one + 8, two);
}

TEST(Geometry, QuantizationExtremes) {
  const auto st = grid_stencil(3, 1);
  const float big = std::numeric_limits<float>::max();
  const std::vector<float> pos = {-big, 0, 1, big, -0.0f, 1, 0, 1e-45f, 1};
  for (std::uint32_t bits : {1u, 2u, 14u, 30u}) {
    const auto q = round_trip(pos, st, bits);
    for (float f : q) EXPECT_TRUE(std::isfinite(f)) << bits;
  }
  const std::vector<float> flat(30, 2.5f);
  EXPECT_TRUE(bit_equal(round_trip(flat, grid_stencil(5, 2), 10), flat));
  std::vector<float> nan = flat;
  nan[4] = std::nanf("");
  try {
    qsp::encode_geometry(nan, grid_stencil(5, 2), {10});
    FAIL() << "NaN quantized";
  } catch (const qsp::Error& e) {
    EXPECT_EQ(e.code(), qsp::ErrorCode::kBadNumber);
  }
}

// A caller's bad argument is a usage error; stencils that break their promise (one per vertex, looking
// back) are the library's own bug.
TEST(Geometry, CallerMistakesAreTypedErrors) {
  const auto st = grid_stencil(2, 2);
  const std::vector<float> pos(12, 1.0f);
  auto code_of = [](auto&& f) {
    try {
      f();
    } catch (const qsp::Error& e) {
      return e.code();
    }
    return qsp::ErrorCode{};
  };
  EXPECT_EQ(code_of([&] { qsp::encode_geometry(std::vector<float>(11, 1.0f), st, {}); }),
            qsp::ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { qsp::encode_geometry(pos, st, {31}); }), qsp::ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { qsp::encode_geometry(pos, grid_stencil(3, 1), {}); }), qsp::ErrorCode::kInternal);
  auto bad = st;
  bad[1].w = 1;  // refers to itself
  EXPECT_EQ(code_of([&] { qsp::encode_geometry(pos, bad, {}); }), qsp::ErrorCode::kInternal);
  const std::vector<float> other(12, 2.0f);
  EXPECT_EQ(qsp::max_geometry_error(pos, pos), 0.0);
  EXPECT_EQ(qsp::max_geometry_error(pos, other), 1.0);
  EXPECT_EQ(code_of([&] { qsp::max_geometry_error(pos, std::vector<float>(3)); }), qsp::ErrorCode::kUsage);
  EXPECT_EQ(code_of([&] { qsp::decimal_grid_value(1, 10); }), qsp::ErrorCode::kUsage);
}

// The stencils the codec will pass for a shared mesh: every component's grid layout, one after the
// other, with the positions in that order.
// False if ../shared/meshes/NAME is not there.
bool shared_mesh_along_partition(const char* name, std::vector<float>& pos, std::vector<Stencil>& st) {
  const std::filesystem::path path = qsp::testing::shared_dir() / "meshes" / name;
  if (!std::filesystem::exists(path)) return false;
  const qsp::QuadMesh mesh = qsp::read_mesh_file(path.string());
  const qsp::Adjacency adj = qsp::build_adjacency(mesh);
  const qsp::Partition part = qsp::partition_motorcycle(adj);
  for (const auto& comp : part.components) {
    qsp::Numbering n;
    const GridLayout g = qsp::grid_layout(comp, n);
    const qsp::ComponentStencils layout = qsp::component_stencils(comp, g, n, qsp::CodingOrder::kLayout);
    const qsp::LayoutMap map = qsp::layout_to_mesh(comp, adj);
    const auto base = static_cast<std::uint32_t>(st.size());
    for (std::uint32_t v = 0; v < g.vertex_count; ++v) {
      Stencil s = layout.stencil[v];
      for (std::uint32_t* j : s.vertex_fields())
        if (*j != kInvalid) *j += base;
      st.push_back(s);
      for (int a = 0; a < 3; ++a) pos.push_back(mesh.positions[3 * std::size_t{map.vertex[v]} + a]);
    }
  }
  return true;
}

TEST(Geometry, RealMeshesAlongTheirPartition) {
  QSP_NEEDS_SHARED();
  for (const char* name :
       {"keenan_spot_quadrangulated.obj", "quadriflow_gargoyle.obj", "mh_fedora.obj", "igl_horse_quad.obj"}) {
    SCOPED_TRACE(name);
    std::vector<float> pos;
    std::vector<Stencil> st;
    ASSERT_TRUE(shared_mesh_along_partition(name, pos, st)) << "no shared mesh " << name;
    std::size_t lossless = 0, q14 = 0;
    EXPECT_TRUE(bit_equal(round_trip(pos, st, 0, &lossless), pos));
    EXPECT_LT(lossless * 8.0 / st.size(), 60.0);  // raw floats: 96
    const auto q = round_trip(pos, st, 14, &q14);
    EXPECT_LT(q14 * 8.0 / st.size(), 30.0);
    float lo = pos[0], hi = pos[0];
    for (float f : pos) lo = std::min(lo, f), hi = std::max(hi, f);
    EXPECT_LE(qsp::max_geometry_error(pos, q), (double{hi} - lo) / 16383 * 0.51);
  }
}

// Coordinates drawn from a few values (CAD-like, symmetric) are coded as repeats: the rank of the value
// among those seen on the axis, nearest to the prediction first, instead of an unpredictable residual.
TEST(Geometry, RepeatedValuesCostTheirRank) {
  const auto st = grid_stencil(40, 40);
  std::mt19937 rng(11);
  std::vector<float> pos(st.size() * 3);
  for (float& f : pos) f = static_cast<float>(1000 * static_cast<int>(rng() % 8) - 3500);
  for (std::uint32_t bits : {0u, 16u}) {
    std::size_t size = 0;
    const auto back = round_trip(pos, st, bits, &size);
    if (bits == 0) {
      EXPECT_TRUE(bit_equal(back, pos));
    } else {
      EXPECT_LE(qsp::max_geometry_error(pos, back), 7000.0 / 65535);
    }
    // log2(8) = 3 bits of rank per coordinate; a residual of these jumps costs ~13 bits.
    EXPECT_LT(size * 8.0 / st.size(), 3 * 4.5) << bits;
  }
}

// encode_geometry reports the header it chose, and a choice given back restricts it to that header:
// the codec's other encodes of a mesh skip the trials that way, so both must hold exactly.
TEST(Geometry, HeaderChoiceIsReportedAndHonoured) {
  const auto st = grid_stencil(30, 30);
  std::mt19937 rng(5);
  std::vector<float> repeating(st.size() * 3);  // repeats pay
  for (float& f : repeating) f = static_cast<float>(1000 * static_cast<int>(rng() % 8) - 3500);
  const std::vector<float> decimal = smooth_positions(30, 30, 4);  // a 4-decimal grid, no repeats
  struct Case {
    const std::vector<float>* pos;
    std::uint32_t bits;
    qsp::GeometryChoice expected;
  };
  for (const Case& c : {Case{&repeating, 0, {true, true}}, Case{&repeating, 16, {true, false}},
                        Case{&decimal, 0, {false, true}}}) {
    SCOPED_TRACE(c.bits);
    qsp::GeometryOptions opt{c.bits};
    qsp::GeometryChoice chosen{!c.expected.repeats, !c.expected.decimal};
    const std::string best = qsp::encode_geometry(*c.pos, st, opt, &chosen);
    EXPECT_EQ(chosen.repeats, c.expected.repeats);
    if (c.bits == 0) {
      EXPECT_EQ(chosen.decimal, c.expected.decimal);
    }
    // Given back, the choice gives the same bytes; the other repeats setting gives a larger section
    // that still decodes to the same positions.
    opt.choice = chosen;
    EXPECT_EQ(qsp::encode_geometry(*c.pos, st, opt), best);
    opt.choice = qsp::GeometryChoice{!chosen.repeats, chosen.decimal};
    qsp::GeometryChoice other;
    const std::string worse = qsp::encode_geometry(*c.pos, st, opt, &other);
    EXPECT_EQ(other.repeats, !chosen.repeats);
    EXPECT_GT(worse.size(), best.size());
    const auto a = qsp::decode_geometry(best, 0, st, static_cast<std::uint32_t>(st.size()));
    const auto b = qsp::decode_geometry(worse, 0, st, static_cast<std::uint32_t>(st.size()));
    EXPECT_TRUE(bit_equal(a, b));
    if (c.bits == 0) {
      EXPECT_TRUE(bit_equal(a, *c.pos));
    }
  }
}

// Large sections hand their symbols to a second thread that runs the range coder (GeometryOptions::
// coder_thread). It must give the bytes the single-threaded encoder gives, for every kind of symbol
// (residuals, trailing zeros, repeats, chained axes, float axes), across many blocks, and on sections
// too small to fill one.
TEST(Geometry, CoderThreadGivesTheSameBytes) {
  constexpr std::uint32_t a = 210, b = 200;  // 42000 vertices: above the default threshold
  const auto st = grid_stencil(a, b);
  std::mt19937 rng(3);
  std::vector<float> repeating(st.size() * 3), floats = smooth_positions(a, b, 4);
  for (float& f : repeating) f = static_cast<float>(1000 * static_cast<int>(rng() % 8) - 3500);
  for (std::size_t i = 1; i < floats.size(); i += 3)
    floats[i] += std::ldexp(static_cast<float>(rng() % 1000), -30);
  const auto tilted = noisy_plane(a, b, {2 / 3.0, 1 / 3.0, 2 / 3.0}, {1 / 3.0, 2 / 3.0, -2 / 3.0});
  const auto small_st = grid_stencil(3, 3);
  const auto small = smooth_positions(3, 3, 2);
  struct Case {
    const char* name;
    const std::vector<float>* pos;
    const std::vector<Stencil>* st;
  };
  for (const Case& c : {Case{"decimal", nullptr, &st}, Case{"significant", nullptr, &st},
                        Case{"repeating", &repeating, &st}, Case{"float axis", &floats, &st},
                        Case{"chained", &tilted, &st}, Case{"one block", &small, &small_st}}) {
    std::vector<float> own;
    if (!c.pos)
      own = std::string(c.name) == "decimal" ? smooth_positions(a, b, 4) : significant_positions(a, b);
    const std::vector<float>& pos = c.pos ? *c.pos : own;
    for (std::uint32_t bits : {0u, 14u}) {
      for (const bool costly : {false, true}) {  // logistic mixing's symbols carry the mixer's contexts
        SCOPED_TRACE(std::string(c.name) + " bits " + std::to_string(bits) + (costly ? " costly tools" : ""));
        qsp::GeometryOptions opt{bits};
        opt.header_sample = 4096;  // as the codec codes sections this large: once, not every header in full
        if (costly) opt.tools = kCostly | tool::kValueRepeats | tool::kNormalChaining;
        opt.coder_thread = false;
        const std::string direct = qsp::encode_geometry(pos, *c.st, opt);
        opt.coder_thread = true;
        EXPECT_EQ(qsp::encode_geometry(pos, *c.st, opt), direct);
        if (!costly && c.st == &st) {
          qsp::GeometryOptions threaded{bits};  // the default coder thread: on, as the section is large
          threaded.header_sample = opt.header_sample;
          EXPECT_EQ(qsp::encode_geometry(pos, *c.st, threaded), direct);
        }
        EXPECT_EQ((direct[0] & kCostly) == kCostly, costly);
        const auto back = qsp::decode_geometry(direct, 0, *c.st, static_cast<std::uint32_t>(c.st->size()));
        if (bits == 0) {
          EXPECT_TRUE(bit_equal(back, pos));
        }
      }
    }
  }
  const std::vector<Stencil> none;
  qsp::GeometryOptions forced{14};
  forced.coder_thread = true;
  EXPECT_TRUE(qsp::decode_geometry(qsp::encode_geometry({}, none, forced), 0, none, 0).empty());
}

// The shape transfers carry a coded cell's shape into the next by a similarity, so where every cell is a
// turned and scaled copy of its neighbour (the conformal map exp(z) of a square grid, a logarithmic
// spiral, laid on a tilted plane) they predict what the parallelogram's second-order error misses. At
// 14 bits the cell shapes tool must code such a grid in under 80% of the bytes without it (with
// logistic mixing in both: measured 733 against 935), and decode it to the same grid points.
TEST(Geometry, ShapeTransfersFollowSimilarCells) {
  constexpr std::uint32_t a = 30, b = 30;
  const auto st = grid_stencil(a, b);
  std::vector<float> pos;
  for (std::uint32_t r = 0; r < b; ++r) {
    for (std::uint32_t c = 0; c < a; ++c) {
      const double m = std::exp(0.1 * (static_cast<double>(c) - 15)), re = m * std::cos(0.1 * r),
                   im = m * std::sin(0.1 * r);
      pos.insert(pos.end(), {static_cast<float>(re + 0.3 * im), static_cast<float>(0.8 * im),
                             static_cast<float>(0.5 * re - 0.2 * im)});
    }
  }
  qsp::GeometryOptions opt{14};
  opt.tools = tool::kLogisticMixing;
  const std::string old = qsp::encode_geometry(pos, st, opt);
  opt.tools = kCostly;
  const std::string shaped = qsp::encode_geometry(pos, st, opt);
  EXPECT_LT(10 * shaped.size(), 8 * old.size()) << shaped.size() << " vs " << old.size();
  const auto n = static_cast<std::uint32_t>(st.size());
  EXPECT_TRUE(bit_equal(qsp::decode_geometry(shaped, 0, st, n), qsp::decode_geometry(old, 0, st, n)));
}

// Predicting edge points and schematic vertices across their patch (o/ow/ofar, x0..x2) pays where
// patches are small: CAD-like subdivision cages, where the opposite side of a patch is often an
// exact copy. Without those fields the coder falls back to predicting along the edge.
TEST(Geometry, AcrossPatchPredictionPaysOnSmallPatches) {
  QSP_NEEDS_SHARED();
  for (const char* name : {"osd_catmark_pawn.obj", "osd_catmark_car.obj", "osd_catmark_lefthanded.obj"}) {
    SCOPED_TRACE(name);
    std::vector<float> pos;
    std::vector<Stencil> st;
    ASSERT_TRUE(shared_mesh_along_partition(name, pos, st)) << "no shared mesh " << name;
    auto along = st;
    std::size_t used = 0;
    for (auto& s : along) {
      used += s.o != kInvalid || s.x0 != kInvalid;
      s.o = s.ow = s.ofar = s.x0 = s.x1 = s.x2 = kInvalid;
    }
    EXPECT_GT(used, st.size() / 4);
    for (std::uint32_t bits : {0u, 14u}) {
      SCOPED_TRACE(bits);
      std::size_t with = 0, without = 0;
      const auto back = round_trip(pos, st, bits, &with);
      if (bits == 0) {
        EXPECT_TRUE(bit_equal(back, pos));
      }
      round_trip(pos, along, bits, &without);
      std::printf("%s %u bits: %zu bytes across, %zu along\n", name, bits, with, without);
      EXPECT_LT(static_cast<double>(with), 0.96 * static_cast<double>(without));
    }
  }
}

void expect_format_error(std::string_view bytes, const std::vector<Stencil>& st, std::uint32_t count) {
  try {
    qsp::decode_geometry(bytes, 0, st, count);
    ADD_FAILURE() << "accepted " << bytes.size() << " bytes";
  } catch (const qsp::Error& e) {
    EXPECT_EQ(e.code(), qsp::ErrorCode::kFormat) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("geometry section: ", 0), 0u) << e.what();
  }
}

std::vector<std::string> sample_encodings(const std::vector<Stencil>& st) {
  auto dec = smooth_positions(6, 5, 4);
  dec[4] = -0.0f;  // one exception
  std::vector<float> raw = smooth_positions(6, 5, 4);
  for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = std::nextafter(raw[i], 10.0f) * (i % 2 ? 1 : -1);
  return {qsp::encode_geometry(dec, st, {}), qsp::encode_geometry(raw, st, {}),
          qsp::encode_geometry(dec, st, {12}), qsp::encode_geometry(significant_positions(6, 5), st, {})};
}

// A section cut short is refused, or decodes to other positions: the payload is the rest of the
// section, and compact stream ends read missing zeros back, so a cut can be another valid stream. (A
// file cannot be cut unseen: its size field and checksum cover every section.) A byte appended, or
// the section read for other stencils, is refused.
TEST(Geometry, EveryTruncationIsRefusedOrDecodesOtherPositions) {
  const auto st = grid_stencil(6, 5);
  for (const std::string& bytes : sample_encodings(st)) {
    const std::vector<float> want = qsp::decode_geometry(bytes, 0, st, 30);
    int refused = 0;
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      try {
        EXPECT_FALSE(bit_equal(qsp::decode_geometry(bytes.substr(0, n), 0, st, 30), want)) << n;
      } catch (const qsp::Error& e) {
        EXPECT_EQ(e.code(), qsp::ErrorCode::kFormat) << e.what();
        ++refused;
      }
    }
    EXPECT_GE(refused + 2, static_cast<int>(bytes.size()));  // only the last bytes may be another stream
    expect_format_error(bytes + '\0', st, 30);
    expect_format_error(bytes, grid_stencil(29, 1), 29);
  }
}

TEST(Geometry, BitFlipsNeverCrash) {
  const auto st = grid_stencil(6, 5);
  for (const std::string& bytes : sample_encodings(st)) {
    for (std::size_t bit = 0; bit < bytes.size() * 8; ++bit) {
      std::string b = bytes;
      b[bit / 8] = static_cast<char>(b[bit / 8] ^ (1 << (bit % 8)));
      try {
        EXPECT_EQ(qsp::decode_geometry(b, 0, st, 30).size(), 90u);
      } catch (const qsp::Error& e) {
        EXPECT_EQ(e.code(), qsp::ErrorCode::kFormat);
      }
    }
  }
}

TEST(Geometry, RandomGarbageNeverCrashes) {
  std::mt19937 rng(11);
  const auto st = grid_stencil(8, 8);
  for (int t = 0; t < 3000; ++t) {
    std::string b(rng() % 64, '\0');
    for (char& c : b) c = static_cast<char>(rng());
    if (b.size() > 3 && t % 2) {  // plausible header so the payload gets decoded
      b[0] = static_cast<char>(rng() % 32);
      b[1] = static_cast<char>(rng() % 31);
    }
    try {
      qsp::decode_geometry(b, 0, st, 64);
    } catch (const qsp::Error& e) {
      EXPECT_EQ(e.code(), qsp::ErrorCode::kFormat);
    }
  }
}

TEST(Geometry, HugeCountsAreRefusedBeforeAllocating) {
  const auto st = grid_stencil(4, 4);
  // Header with a decimal axis claiming 2^40 exceptions in a few bytes.
  std::string b = {0, 0, 5};
  for (int i = 0; i < 5; ++i) b.push_back(static_cast<char>(0xFF));
  b.push_back(0x1F);
  expect_format_error(b, st, 16);
  // Three float axes and no payload for 16 vertices.
  expect_format_error(std::string(5, '\0'), st, 16);
  // A reserved tool bit.
  expect_format_error(std::string(1, '\x20') + std::string(4, '\0'), st, 16);
}

}  // namespace
