// qsp/render.h: pictures of a partition on its mesh, drawn on the CPU: a PNG raster (z-buffer,
// flat shading) or an SVG of the faces back to front. Bytes out, never files; the same input gives
// the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "qsp/layout_export.h"
#include "qsp/mesh.h"
#include "qsp/submesh.h"

namespace qsp {

struct RenderOptions {
  std::uint32_t width = 1024, height = 1024;  // pixels (1 to kMaxRenderSide)
  // Orthographic view: the camera turned `azimuth` degrees about +y from +z (towards +x), then raised
  // `elevation` degrees; 0,0 looks along -z with +y up, the front of a y-up character facing +z. The
  // mesh is fitted to the picture with a margin.
  double azimuth = 0, elevation = 0;
  bool grid = false;  // also draw every mesh edge (thin, darker than the face)
};

inline constexpr std::uint32_t kMaxRenderSide = 8192;
// SVG holds a path per face; beyond this many faces the file is too large to be useful.
inline constexpr std::uint64_t kMaxSvgFaces = 100000;

struct Image {
  std::uint32_t width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 3 bytes per pixel, rows top to bottom
};

// The mesh flat-shaded with each face in its patch's colour (view.patch_colour through
// patch_palette; kNonQuadColour for a face in no patch, a polygon mesh's triangles and n-gons, drawn as
// fans from their first corner), the schematic edges as dark lines, extraordinary vertices as dark dots,
// T-junctions as red squares, hidden parts hidden (drawn at twice the size and averaged down, up to 2^24
// pixels). `view` must be view_partition() of this mesh (a quad mesh as polygon_mesh()), or
// polygon_view() of its quad submesh. Throws Error(kLimit) for a size of 0 or beyond kMaxRenderSide.
// Deterministic (one thread, integer-exact resolve). Safe on any mesh quad_submesh accepted.
Image render_image(const PolygonMesh& mesh, const PatchView& view, const RenderOptions& options);

// PNG bytes of `image` (8-bit RGB, zlib-compressed, one filter per row). Never fails on a valid Image.
std::string encode_png(const Image& image);

// The same picture as SVG: faces sorted back to front (ties by face index), each line, dot and mark
// drawn right after the frontmost face it touches, so nearer faces hide it. Throws Error(kLimit) when
// the mesh has more than kMaxSvgFaces faces (the message suggests PNG) or the size is out of range.
std::string render_svg(const PolygonMesh& mesh, const PatchView& view, const RenderOptions& options);

}  // namespace qsp
