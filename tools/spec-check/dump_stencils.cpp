// dump_stencils IN.qsp PREFIX: what qspgeo.py needs besides the spec. The stencils come from the
// library (the topology and grid layout are checked by other tests; qspgeo.py checks the geometry
// text), written per coding position to PREFIX.stencil; the reference decoder's positions, as float
// bits in canonical vertex order, to PREFIX.pos. Exit 0, else 1 with a message.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "codec_sections.h"
#include "layout_grid.h"
#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/partition.h"
#include "stencil.h"

namespace {

// The payload of the section at `info` (its tag byte's offset), after its varint length.
std::string_view payload(std::string_view bytes, const qsp::SectionInfo& info, std::uint64_t& offset) {
  std::uint64_t at = info.offset + 1;
  while (static_cast<std::uint8_t>(bytes[at]) & 0x80) ++at;
  offset = at + 1;
  return bytes.substr(offset, info.offset + info.size - offset);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: dump_stencils IN.qsp PREFIX\n");
    return 2;
  }
  try {
    std::ifstream in(argv[1], std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const std::string bytes = text.str();
    const qsp::QuadMesh mesh = qsp::decode(bytes);
    const qsp::FileInfo info = qsp::inspect(bytes);  // the coding order, version and sections

    std::ofstream st(std::string(argv[2]) + ".stencil");
    auto write = [&st](std::uint32_t vertex, qsp::Stencil s, std::uint32_t base) {
      st << vertex;
      for (std::uint32_t* v : s.vertex_fields())
        st << ' ' << (*v == qsp::kInvalid ? -1 : std::int64_t{*v + base});
      st << ' ' << s.far_dist << ' ' << s.e_dist << ' ' << s.n_dist << ' ' << s.xnum << ' ' << s.xden << '\n';
    };
    const qsp::FileTopology top = qsp::file_topology(bytes);
    std::uint32_t base = 0;
    for (const qsp::TopologyCode& code : top.codes) {
      const qsp::ComponentPartition part = qsp::partition_from_code(code);
      qsp::Numbering n;
      const qsp::GridLayout g = qsp::grid_layout(part, n);
      const qsp::ComponentStencils c = qsp::component_stencils(part, g, n, info.geometry_order);
      for (std::uint32_t k = 0; k < g.vertex_count; ++k)
        write(base + (c.coding.empty() ? k : c.coding[k]), c.stencil[k], base);
      base += g.vertex_count;
    }
    for (std::uint64_t u = 0; u < top.unreferenced; ++u, ++base) {  // w = the previous vertex
      qsp::Stencil s;
      if (base > 0) s.w = base - 1;
      write(base, s, 0);
    }

    // Positions in canonical order: with an order section, decode() restored the input's order.
    std::vector<float> pos = mesh.positions;
    for (const qsp::SectionInfo& section : info.sections) {
      if (section.tag != 4) continue;
      std::uint64_t offset = 0;
      const std::string_view order = payload(bytes, section, offset);
      const qsp::OrderMap om =
          qsp::decode_order(order, offset, static_cast<std::uint32_t>(mesh.vertex_count()),
                            static_cast<std::uint32_t>(mesh.face_count()));
      for (std::size_t j = 0; j < om.vertex.size(); ++j)
        for (int a = 0; a < 3; ++a) pos[3 * std::size_t{om.vertex[j]} + a] = mesh.positions[3 * j + a];
    }
    std::ofstream(std::string(argv[2]) + ".pos", std::ios::binary)
        .write(reinterpret_cast<const char*>(pos.data()), static_cast<std::streamsize>(pos.size() * 4));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dump_stencils: %s: %s\n", argv[1], e.what());
    return 1;
  }
}
