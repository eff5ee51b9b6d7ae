// What the normals section adds to the texture coordinates coder (format-spec/qsp_format.md, "Normals
// section", flag bits 5 and 6): each normal predicted from the decoded faces whose corners name it, and
// octahedral normals (two integers per normal). Every step is one binary64 operation in the written
// order (this file is compiled with -ffp-contract=off like the rest), so every decoder gets the same bits.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace qsp {

// Per value below `count`: the sum, over the corners naming it (in corner order), of their face's Newell
// normal from `positions` (3 per vertex), normalised; `valid` is 0 where that sum has no direction (zero
// or not finite).
struct GeometryNormals {
  std::vector<double> unit;         // 3 per value
  std::vector<std::uint8_t> valid;  // per value
  std::array<double, 3> at(std::uint32_t i) const {
    return {unit[3 * std::size_t{i}], unit[3 * std::size_t{i} + 1], unit[3 * std::size_t{i} + 2]};
  }
};
GeometryNormals geometry_normals(std::span<const std::uint32_t> face_offsets,
                                 std::span<const std::uint32_t> corner_vertices,
                                 std::span<const float> positions, std::span<const std::uint32_t> names,
                                 std::uint32_t count);

// The octahedral grid of `bits` (2 to 24) bits: integers s, t in [-h, h], h = 2^(bits-1) - 1.
struct Octahedral {
  std::int64_t h;
  explicit Octahedral(std::uint32_t bits) : h((std::int64_t{1} << (bits - 1)) - 1) {}
  // The grid point of direction n (any length; (0, 0) for none), z negated first if `mirror`: the
  // prediction's rule, rounding each coordinate half away from zero.
  std::array<std::int64_t, 2> nearest(const std::array<double, 3>& n, bool mirror) const;
  // The grid point whose decoded normal is closest to n scaled to unit length (of the four around it;
  // the encoder's choice, the first on a tie).
  std::array<std::int64_t, 2> best(const std::array<double, 3>& n, bool mirror) const;
  // The unit normal (binary32) of grid point (s, t), z negated if `mirror`.
  std::array<float, 3> normal(std::int64_t s, std::int64_t t, bool mirror) const;
};

}  // namespace qsp
