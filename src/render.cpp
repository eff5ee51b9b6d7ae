// Pictures of a partition: an orthographic z-buffer raster at twice the size, averaged down (PNG), and
// an SVG painted back to front. One thread and fixed arithmetic, so the bytes are reproducible.
#include "qsp/render.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "qsp/error.h"

namespace qsp {
namespace {

// Raster samples per pixel side: 2 (anti-aliased) up to this many pixels, 1 beyond, so the buffers
// (11 bytes a sample) stay under 0.75 GB at kMaxRenderSide (0.9 GB peak with the picture and its PNG,
// measured at 4096x4096 and 8192x8192).
constexpr std::uint64_t kSuperPixels = std::uint64_t{1} << 24;
constexpr float kMargin = 0.04f;  // picture border left free, per side
constexpr std::array<std::uint8_t, 3> kLine = {30, 30, 34};
constexpr std::array<std::uint8_t, 3> kDot = {20, 20, 20};
constexpr std::array<std::uint8_t, 3> kTee = {210, 30, 30};
constexpr std::array<std::uint8_t, 3> kBackground = {255, 255, 255};

void check_size(const RenderOptions& o) {
  if (o.width == 0 || o.height == 0 || o.width > kMaxRenderSide || o.height > kMaxRenderSide)
    throw Error(ErrorCode::kLimit, "picture size " + std::to_string(o.width) + "x" +
                                       std::to_string(o.height) + " is outside 1 to " +
                                       std::to_string(kMaxRenderSide) + " pixels a side");
}

// The view: screen x along `right`, screen y down along -`up`, depth along `toward` (larger = nearer).
struct Projection {
  std::vector<float> x, y, z;  // per vertex, in pixels of a picture `scale_px` times the final size
  std::array<double, 3> right{}, up{}, toward{};
};

double dot3(const std::array<double, 3>& a, const float* p) {
  return a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
}

Projection project(const PolygonMesh& mesh, const RenderOptions& o, int super) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const double az = o.azimuth * kDeg, el = o.elevation * kDeg;
  Projection p;
  p.toward = {std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el)};
  p.right = {std::cos(az), 0.0, -std::sin(az)};
  p.up = {-std::sin(az) * std::sin(el), std::cos(el), -std::cos(az) * std::sin(el)};
  const std::size_t n = mesh.vertex_count();
  p.x.resize(n), p.y.resize(n), p.z.resize(n);
  // Fitted to the vertices faces use (an unreferenced vertex far away should not shrink the picture).
  std::vector<std::uint8_t> used(n, 0);
  for (std::uint32_t v : mesh.corners) used[v] = 1;
  double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (std::size_t v = 0; v < n; ++v) {
    const float* q = &mesh.positions[3 * v];
    const double sx = dot3(p.right, q), sy = dot3(p.up, q);
    if (used[v]) x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
  }
  if (x0 > x1) x0 = x1 = y0 = y1 = 0;
  const double w = static_cast<double>(o.width) * super, h = static_cast<double>(o.height) * super;
  const double sx = (x1 - x0) > 0 ? w * (1 - 2 * kMargin) / (x1 - x0) : 0;
  const double sy = (y1 - y0) > 0 ? h * (1 - 2 * kMargin) / (y1 - y0) : 0;
  double scale = sx > 0 && sy > 0 ? std::min(sx, sy) : std::max(sx, sy);
  if (scale <= 0) scale = 1;
  const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  for (std::size_t v = 0; v < n; ++v) {
    const float* q = &mesh.positions[3 * v];
    p.x[v] = static_cast<float>((dot3(p.right, q) - cx) * scale + w / 2);
    p.y[v] = static_cast<float>(h / 2 - (dot3(p.up, q) - cy) * scale);
    p.z[v] = static_cast<float>(dot3(p.toward, q) * scale);  // depth in pixels too
  }
  return p;
}

// A face's normal (unnormalised): a quad's by its diagonals, other faces' by Newell's method.
std::array<double, 3> face_normal(const PolygonMesh& mesh, std::uint32_t f) {
  const std::uint32_t* q = &mesh.corners[mesh.face_offsets[f]];
  const auto at = [&mesh](std::uint32_t v) { return &mesh.positions[3 * std::size_t{v}]; };
  if (mesh.degree(f) == 4) {
    const float *p0 = at(q[0]), *p1 = at(q[1]), *p2 = at(q[2]), *p3 = at(q[3]);
    const double a[3] = {double{p2[0]} - p0[0], double{p2[1]} - p0[1], double{p2[2]} - p0[2]};
    const double b[3] = {double{p3[0]} - p1[0], double{p3[1]} - p1[1], double{p3[2]} - p1[2]};
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  }
  std::array<double, 3> n{};
  const std::uint32_t d = mesh.degree(f);
  for (std::uint32_t i = 0; i < d; ++i) {
    const float *a = at(q[i]), *b = at(q[(i + 1) % d]);
    n[0] += (double{a[1]} - b[1]) * (double{a[2]} + b[2]);
    n[1] += (double{a[2]} - b[2]) * (double{a[0]} + b[0]);
    n[2] += (double{a[0]} - b[0]) * (double{a[1]} + b[1]);
  }
  return n;
}

// Flat shading: each face its patch colour (kNonQuadColour in no patch), lit from the upper left front
// (both sides lit alike, so open meshes and either orientation read the same).
std::vector<std::array<std::uint8_t, 3>> face_colours(const PolygonMesh& mesh, const PatchView& view,
                                                      const Projection& p) {
  std::array<double, 3> light{};
  for (int k = 0; k < 3; ++k) light[k] = -0.35 * p.right[k] + 0.55 * p.up[k] + 0.76 * p.toward[k];
  const double ln = std::sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
  std::vector<std::array<std::uint8_t, 3>> out(mesh.face_count());
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::array<double, 3> nrm = face_normal(mesh, static_cast<std::uint32_t>(f));
    const double len = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
    const double lambert =
        len > 0 ? std::fabs(nrm[0] * light[0] + nrm[1] * light[1] + nrm[2] * light[2]) / (len * ln) : 0.5;
    const double shade = 0.32 + 0.68 * lambert;
    const std::uint32_t patch = view.face_patch[f];
    const auto base = patch == kInvalid ? kNonQuadColour : patch_palette(view.patch_colour[patch]);
    for (int c = 0; c < 3; ++c) out[f][c] = static_cast<std::uint8_t>(std::lround(base[c] * shade));
  }
  return out;
}

std::array<std::uint8_t, 3> darker(const std::array<std::uint8_t, 3>& c) {
  return {static_cast<std::uint8_t>(c[0] * 11 / 20), static_cast<std::uint8_t>(c[1] * 11 / 20),
          static_cast<std::uint8_t>(c[2] * 11 / 20)};
}

// The supersampled raster: nearest depth and face per sample, then colours.
struct Raster {
  int w = 0, h = 0;
  std::vector<float> depth;         // per sample; -inf where no face
  std::vector<std::uint32_t> face;  // per sample; kInvalid where no face
  std::vector<std::uint8_t> rgb;

  void triangle(const Projection& p, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t f) {
    const float ax = p.x[a], ay = p.y[a], bx = p.x[b], by = p.y[b], cx = p.x[c], cy = p.y[c];
    const float area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (!(std::fabs(area) > 0)) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({ax, bx, cx}))));
    const int x1 = std::min(w - 1, static_cast<int>(std::ceil(std::max({ax, bx, cx}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({ay, by, cy}))));
    const int y1 = std::min(h - 1, static_cast<int>(std::ceil(std::max({ay, by, cy}))));
    if (x0 > x1 || y0 > y1) return;
    const float inv = 1.0f / area;
    const float za = p.z[a], zb = p.z[b], zc = p.z[c];
    // Barycentric weights, normalised by the signed area so both windings are filled; stepped along
    // each row (the same order every run, so the same bytes).
    const float dwa = (by - cy) * inv, dwb = (cy - ay) * inv;
    for (int y = y0; y <= y1; ++y) {
      const float py = static_cast<float>(y) + 0.5f, px = static_cast<float>(x0) + 0.5f;
      float wa = ((bx - px) * (cy - py) - (by - py) * (cx - px)) * inv;
      float wb = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) * inv;
      float* row_depth = depth.data() + static_cast<std::size_t>(y) * w;
      std::uint32_t* row_face = face.data() + static_cast<std::size_t>(y) * w;
      for (int x = x0; x <= x1; ++x, wa += dwa, wb += dwb) {
        const float wc = 1.0f - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const float z = za + wb * (zb - za) + wc * (zc - za);
        if (z > row_depth[x]) row_depth[x] = z, row_face[x] = f;
      }
    }
  }

  // A line from vertex a to b as discs of radius `r` samples, drawn where the line is in front of (or
  // within `tol` depth of) the surface at its centre, and not behind a nearer surface under the disc.
  void segment(const Projection& p, std::uint32_t a, std::uint32_t b, float r, float tol,
               const std::array<std::uint8_t, 3>* colour,
               const std::vector<std::array<std::uint8_t, 3>>* dark) {
    const float ax = p.x[a], ay = p.y[a], az = p.z[a];
    const float dx = p.x[b] - ax, dy = p.y[b] - ay, dz = p.z[b] - az;
    const float len = std::sqrt(dx * dx + dy * dy);
    const int steps = std::min(1 << 16, static_cast<int>(std::ceil(len * 2)) + 1);
    const int ri = static_cast<int>(std::ceil(r));
    for (int k = 0; k <= steps; ++k) {
      const float t = static_cast<float>(k) / static_cast<float>(steps);
      const float x = ax + t * dx, y = ay + t * dy, z = az + t * dz;
      const int ix = static_cast<int>(std::floor(x)), iy = static_cast<int>(std::floor(y));
      if (ix < 0 || iy < 0 || ix >= w || iy >= h) continue;
      if (z < depth[static_cast<std::size_t>(iy) * w + ix] - tol) continue;
      for (int oy = -ri; oy <= ri; ++oy)
        for (int ox = -ri; ox <= ri; ++ox) {
          if (static_cast<float>(ox * ox + oy * oy) > r * r) continue;
          const int qx = ix + ox, qy = iy + oy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const std::size_t i = static_cast<std::size_t>(qy) * w + qx;
          if (depth[i] > z + tol + r) continue;
          const std::array<std::uint8_t, 3>* c = colour;
          if (!c) {
            if (face[i] == kInvalid) continue;
            c = &(*dark)[face[i]];
          }
          std::copy(c->begin(), c->end(), rgb.begin() + 3 * i);
        }
    }
  }

  // A dot (disc) or square mark of radius `r` samples at vertex v, if v is not hidden.
  void mark(const Projection& p, std::uint32_t v, float r, float tol, bool square,
            const std::array<std::uint8_t, 3>& colour) {
    const int ix = static_cast<int>(std::floor(p.x[v])), iy = static_cast<int>(std::floor(p.y[v]));
    if (ix < 0 || iy < 0 || ix >= w || iy >= h) return;
    if (p.z[v] < depth[static_cast<std::size_t>(iy) * w + ix] - tol) return;
    const int ri = static_cast<int>(std::ceil(r));
    for (int oy = -ri; oy <= ri; ++oy)
      for (int ox = -ri; ox <= ri; ++ox) {
        if (!square && static_cast<float>(ox * ox + oy * oy) > r * r) continue;
        const int qx = ix + ox, qy = iy + oy;
        if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
        std::copy(colour.begin(), colour.end(), rgb.begin() + 3 * (static_cast<std::size_t>(qy) * w + qx));
      }
  }
};

// Line and mark sizes in final pixels, growing with the picture.
struct Sizes {
  float line, dot, tee;
};
Sizes sizes_for(const RenderOptions& o) {
  const float s = static_cast<float>(std::min(o.width, o.height)) / 1024.0f;
  return {std::max(0.6f, 0.9f * s), std::max(1.5f, 2.6f * s), std::max(1.5f, 2.6f * s)};
}

}  // namespace

Image render_image(const PolygonMesh& mesh, const PatchView& view, const RenderOptions& o) {
  check_size(o);
  const int kSuper = std::uint64_t{o.width} * o.height <= kSuperPixels ? 2 : 1;
  const Projection p = project(mesh, o, kSuper);
  const auto colour = face_colours(mesh, view, p);
  Raster r;
  r.w = static_cast<int>(o.width) * kSuper;
  r.h = static_cast<int>(o.height) * kSuper;
  const std::size_t samples = static_cast<std::size_t>(r.w) * r.h;
  r.depth.assign(samples, -std::numeric_limits<float>::infinity());
  r.face.assign(samples, kInvalid);
  for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {  // a fan from the first corner
    const std::uint32_t* q = &mesh.corners[mesh.face_offsets[f]];
    for (std::uint32_t i = 2; i < mesh.degree(f); ++i) r.triangle(p, q[0], q[i - 1], q[i], f);
  }
  r.rgb.resize(3 * samples);
  for (std::size_t i = 0; i < samples; ++i) {
    const auto& c = r.face[i] == kInvalid ? kBackground : colour[r.face[i]];
    std::copy(c.begin(), c.end(), r.rgb.begin() + 3 * i);
  }
  const float tol = 3.0f;  // depth slack in sample units: a line on the surface is never hidden by it
  if (o.grid) {
    std::vector<std::array<std::uint8_t, 3>> dark(colour.size());
    for (std::size_t f = 0; f < colour.size(); ++f) dark[f] = darker(colour[f]);
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
      const std::uint32_t* q = &mesh.corners[mesh.face_offsets[f]];
      const std::uint32_t d = mesh.degree(f);
      for (std::uint32_t c = 0; c < d; ++c) r.segment(p, q[c], q[(c + 1) % d], 0.5f, tol, nullptr, &dark);
    }
  }
  const Sizes sz = sizes_for(o);
  for (std::uint32_t e = 0; e < view.edge_count(); ++e)
    for (std::uint32_t k = view.edge_first[e]; k + 1 < view.edge_first[e + 1]; ++k)
      r.segment(p, view.edge_path[k], view.edge_path[k + 1], sz.line * kSuper, tol, &kLine, nullptr);
  for (std::uint32_t v : view.t_junctions) r.mark(p, v, sz.tee * kSuper, tol, true, kTee);
  for (std::uint32_t v : view.extraordinary) {  // a light ring sets the dot off from the lines
    r.mark(p, v, sz.dot * kSuper * 1.5f, tol, false, kBackground);
    r.mark(p, v, sz.dot * kSuper, tol, false, kDot);
  }

  Image img;
  img.width = o.width;
  img.height = o.height;
  img.rgb.resize(3 * std::size_t{o.width} * o.height);
  for (std::uint32_t y = 0; y < o.height; ++y)
    for (std::uint32_t x = 0; x < o.width; ++x)
      for (int c = 0; c < 3; ++c) {
        unsigned sum = 0;
        for (int sy = 0; sy < kSuper; ++sy)
          for (int sx = 0; sx < kSuper; ++sx)
            sum += r.rgb[3 * ((std::size_t{y} * kSuper + sy) * r.w + std::size_t{x} * kSuper + sx) + c];
        img.rgb[3 * (std::size_t{y} * o.width + x) + c] =
            static_cast<std::uint8_t>((sum + kSuper * kSuper / 2) / (kSuper * kSuper));
      }
  return img;
}

namespace {

void put_u32(std::string& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<char>((v >> s) & 0xFF));
}

void put_chunk(std::string& out, const char type[4], const std::string& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t start = out.size();
  out.append(type, 4);
  out += data;
  const auto crc =
      crc32(0L, reinterpret_cast<const Bytef*>(out.data() + start), static_cast<uInt>(out.size() - start));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

}  // namespace

std::string encode_png(const Image& img) {
  // Filter "Sub" on every row: flat regions become runs of zeros, which deflate well.
  const std::size_t stride = 3 * std::size_t{img.width};
  std::string raw;
  raw.reserve((stride + 1) * img.height);
  for (std::uint32_t y = 0; y < img.height; ++y) {
    raw.push_back(1);
    const std::uint8_t* row = img.rgb.data() + y * stride;
    for (std::size_t i = 0; i < stride; ++i)
      raw.push_back(static_cast<char>(i < 3 ? row[i] : static_cast<std::uint8_t>(row[i] - row[i - 3])));
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()), 6) != Z_OK)
    throw Error(ErrorCode::kInternal, "zlib could not compress the picture");
  packed.resize(packed_size);
  std::string out = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  put_u32(ihdr, img.width);
  put_u32(ihdr, img.height);
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, adaptive filters, no interlace
  put_chunk(out, "IHDR", ihdr);
  put_chunk(out, "IDAT", packed);
  put_chunk(out, "IEND", "");
  return out;
}

std::string render_svg(const PolygonMesh& mesh, const PatchView& view, const RenderOptions& o) {
  check_size(o);
  if (mesh.face_count() > kMaxSvgFaces)
    throw Error(ErrorCode::kLimit, "SVG output holds at most " + std::to_string(kMaxSvgFaces) +
                                       " faces and this mesh has " + std::to_string(mesh.face_count()) +
                                       "; write a .png instead");
  const Projection p = project(mesh, o, 1);
  const auto colour = face_colours(mesh, view, p);
  const std::uint32_t nf = static_cast<std::uint32_t>(mesh.face_count());
  // Back to front by mean depth, ties by face index.
  std::vector<float> depth(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    float z = 0;
    for (std::uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) z += p.z[mesh.corners[c]];
    depth[f] = z / static_cast<float>(mesh.degree(f));
  }
  std::vector<std::uint32_t> order(nf);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return depth[a] < depth[b]; });
  std::vector<std::uint32_t> rank(nf);
  for (std::uint32_t k = 0; k < nf; ++k) rank[order[k]] = k;

  // Overlay items, each after the last-drawn face that touches it: 0 = segment, 1 = dot, 2 = tee.
  struct Item {
    std::uint32_t after, kind, a, b;
  };
  std::vector<Item> items;
  // The last-drawn face at each vertex and on each schematic edge's mesh edges, from the corners.
  std::vector<std::uint32_t> last_at(mesh.vertex_count(), 0);
  std::unordered_map<std::uint64_t, std::uint32_t> last_on;
  const auto edge_key = [](std::uint32_t u, std::uint32_t v) {
    return std::uint64_t{std::min(u, v)} << 32 | std::max(u, v);
  };
  for (std::uint32_t e = 0; e < view.edge_count(); ++e)
    for (std::uint32_t k = view.edge_first[e]; k + 1 < view.edge_first[e + 1]; ++k)
      last_on.emplace(edge_key(view.edge_path[k], view.edge_path[k + 1]), 0);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t* q = &mesh.corners[mesh.face_offsets[f]];
    const std::uint32_t d = mesh.degree(f);
    for (std::uint32_t c = 0; c < d; ++c) {
      last_at[q[c]] = std::max(last_at[q[c]], rank[f]);
      if (const auto it = last_on.find(edge_key(q[c], q[(c + 1) % d])); it != last_on.end())
        it->second = std::max(it->second, rank[f]);
    }
  }
  const auto last_face_at = [&last_at](std::uint32_t v) { return last_at[v]; };
  for (std::uint32_t e = 0; e < view.edge_count(); ++e)
    for (std::uint32_t k = view.edge_first[e]; k + 1 < view.edge_first[e + 1]; ++k) {
      const std::uint32_t u = view.edge_path[k], v = view.edge_path[k + 1];
      items.push_back({last_on.at(edge_key(u, v)), 0, u, v});
    }
  for (std::uint32_t v : view.t_junctions) items.push_back({last_face_at(v), 2, v, 0});
  for (std::uint32_t v : view.extraordinary) items.push_back({last_face_at(v), 1, v, 0});
  std::stable_sort(items.begin(), items.end(),
                   [](const Item& a, const Item& b) { return a.after < b.after; });

  const Sizes sz = sizes_for(o);
  std::string out;
  char buf[256];
  std::snprintf(
      buf, sizeof buf,
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%u\" "
      "height=\"%u\" viewBox=\"0 0 %u %u\">\n",
      o.width, o.height, o.width, o.height);
  out += buf;
  std::snprintf(buf, sizeof buf,
                "<style>.s{fill:none;stroke:#1e1e22;stroke-width:%.2f;stroke-linecap:round}"
                ".x{fill:#141414;stroke:#ffffff;stroke-width:%.2f}.t{fill:#d21e1e}</style>\n",
                2 * sz.line, 0.5f * sz.dot);
  out += buf;
  out += "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n<g stroke-linejoin=\"round\">\n";
  std::size_t next_item = 0;
  auto hex = [](const std::array<std::uint8_t, 3>& c, char* s) {
    std::snprintf(s, 8, "#%02x%02x%02x", c[0], c[1], c[2]);
  };
  for (std::uint32_t k = 0; k < nf; ++k) {
    const std::uint32_t f = order[k];
    const std::uint32_t* q = &mesh.corners[mesh.face_offsets[f]];
    char fill[8], stroke[8];
    hex(colour[f], fill);
    hex(o.grid ? darker(colour[f]) : colour[f], stroke);
    // The stroke in the fill's colour closes the hairline seams renderers leave between polygons.
    std::snprintf(buf, sizeof buf, "<path d=\"M%.1f %.1fL", p.x[q[0]], p.y[q[0]]);
    out += buf;
    for (std::uint32_t c = 1; c < mesh.degree(f); ++c) {
      std::snprintf(buf, sizeof buf, c > 1 ? " %.1f %.1f" : "%.1f %.1f", p.x[q[c]], p.y[q[c]]);
      out += buf;
    }
    std::snprintf(buf, sizeof buf, "Z\" fill=\"%s\" stroke=\"%s\" stroke-width=\"%s\"/>\n", fill, stroke,
                  o.grid ? "0.6" : "0.4");
    out += buf;
    for (; next_item < items.size() && items[next_item].after == k; ++next_item) {
      const Item& it = items[next_item];
      if (it.kind == 0) {
        std::snprintf(buf, sizeof buf, "<path class=\"s\" d=\"M%.1f %.1fL%.1f %.1f\"/>\n", p.x[it.a],
                      p.y[it.a], p.x[it.b], p.y[it.b]);
      } else if (it.kind == 1) {
        std::snprintf(buf, sizeof buf, "<circle class=\"x\" cx=\"%.1f\" cy=\"%.1f\" r=\"%.1f\"/>\n",
                      p.x[it.a], p.y[it.a], 1.2f * sz.dot);
      } else {
        std::snprintf(buf, sizeof buf,
                      "<rect class=\"t\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n",
                      p.x[it.a] - sz.tee, p.y[it.a] - sz.tee, 2 * sz.tee, 2 * sz.tee);
      }
      out += buf;
    }
  }
  out += "</g>\n</svg>\n";
  return out;
}

}  // namespace qsp
