// Normals predicted from the faces and octahedral normals (normal_prediction.h).
#include "normal_prediction.h"

#include <cmath>

namespace qsp {

GeometryNormals geometry_normals(std::span<const std::uint32_t> face_offsets,
                                 std::span<const std::uint32_t> corner_vertices,
                                 std::span<const float> positions, std::span<const std::uint32_t> names,
                                 std::uint32_t count) {
  GeometryNormals out;
  out.unit.assign(3 * std::size_t{count}, 0.0);
  out.valid.assign(count, 0);
  const auto at = [&](std::uint32_t corner, int k) {
    return static_cast<double>(
        positions[3 * std::size_t{corner_vertices[corner]} + static_cast<unsigned>(k)]);
  };
  for (std::size_t f = 0; f + 1 < face_offsets.size(); ++f) {
    const std::uint32_t first = face_offsets[f], d = face_offsets[f + 1] - first;
    // Newell: the sum over the face's edges i -> j of (yi - yj)(zi + zj), (zi - zj)(xi + xj), (xi - xj)(yi +
    // yj).
    double n[3] = {0, 0, 0};
    for (std::uint32_t i = 0; i < d; ++i) {
      const std::uint32_t a = first + i, b = first + (i + 1) % d;
      for (int k = 0; k < 3; ++k) {
        const int u = (k + 1) % 3, w = (k + 2) % 3;
        n[k] += (at(a, u) - at(b, u)) * (at(a, w) + at(b, w));
      }
    }
    for (std::uint32_t i = 0; i < d; ++i) {
      const std::uint32_t x = names[first + i];
      if (x >= count) continue;  // none (kInvalid)
      for (int k = 0; k < 3; ++k) out.unit[3 * std::size_t{x} + k] += n[k];
    }
  }
  for (std::uint32_t x = 0; x < count; ++x) {
    double* s = &out.unit[3 * std::size_t{x}];
    const double length = std::sqrt((s[0] * s[0] + s[1] * s[1]) + s[2] * s[2]);
    if (!(length > 0) || !std::isfinite(length)) continue;
    for (int k = 0; k < 3; ++k) s[k] = s[k] / length;
    out.valid[x] = 1;
  }
  return out;
}

namespace {
// The octahedral coordinates of n (z negated if `mirror`), in [-1, 1]^2: n / (|x| + |y| + |z|), the lower
// half folded out over the diagonals; (0, 0) for no direction.
std::array<double, 2> unfold(const std::array<double, 3>& n, bool mirror) {
  const double z = mirror ? -n[2] : n[2];
  const double l1 = (std::fabs(n[0]) + std::fabs(n[1])) + std::fabs(z);
  if (!(l1 > 0) || !std::isfinite(l1)) return {0, 0};
  const double x = n[0] / l1, y = n[1] / l1;
  if (!(z / l1 < 0)) return {x, y};
  return {(1 - std::fabs(y)) * (x < 0 ? -1 : 1), (1 - std::fabs(x)) * (y < 0 ? -1 : 1)};
}
}  // namespace

std::array<std::int64_t, 2> Octahedral::nearest(const std::array<double, 3>& n, bool mirror) const {
  const std::array<double, 2> u = unfold(n, mirror);
  const auto h_ = static_cast<double>(h);
  return {static_cast<std::int64_t>(std::round(u[0] * h_)), static_cast<std::int64_t>(std::round(u[1] * h_))};
}

std::array<std::int64_t, 2> Octahedral::best(const std::array<double, 3>& n, bool mirror) const {
  const std::array<double, 2> u = unfold(n, mirror);
  const auto h_ = static_cast<double>(h);
  const auto s0 = static_cast<std::int64_t>(std::floor(u[0] * h_)),
             t0 = static_cast<std::int64_t>(std::floor(u[1] * h_));
  // The squared distance to the unit input, not the dot product: at 16 bits and more the cosines of
  // neighbouring points differ by less than binary32's rounding of them.
  const double length = std::sqrt((n[0] * n[0] + n[1] * n[1]) + n[2] * n[2]);
  std::array<std::int64_t, 2> out{0, 0};
  double best_distance = INFINITY;
  for (std::int64_t s = s0; s <= s0 + 1; ++s)
    for (std::int64_t t = t0; t <= t0 + 1; ++t) {
      if (s < -h || s > h || t < -h || t > h) continue;
      const std::array<float, 3> m = normal(s, t, mirror);
      double distance = 0;
      for (int k = 0; k < 3; ++k) distance += (n[k] / length - m[k]) * (n[k] / length - m[k]);
      if (distance < best_distance) best_distance = distance, out = {s, t};
    }
  return out;
}

std::array<float, 3> Octahedral::normal(std::int64_t s, std::int64_t t, bool mirror) const {
  std::int64_t x = s, y = t, z = h - std::abs(s) - std::abs(t);
  if (z < 0) x = (h - std::abs(t)) * (s < 0 ? -1 : 1), y = (h - std::abs(s)) * (t < 0 ? -1 : 1);
  if (mirror) z = -z;
  const auto dx = static_cast<double>(x), dy = static_cast<double>(y), dz = static_cast<double>(z);
  const double length = std::sqrt((dx * dx + dy * dy) + dz * dz);  // exact integers below 2^53
  return {static_cast<float>(dx / length), static_cast<float>(dy / length), static_cast<float>(dz / length)};
}

}  // namespace qsp
