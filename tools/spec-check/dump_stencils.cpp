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
#include <vector>

#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/partition.h"
#include "stencil.h"

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
    const qsp::FileInfo info = qsp::inspect(bytes);  // the coding order

    // Per coding position: the layout vertex coded there, the 19 vertex fields, far_dist, e_dist,
    // n_dist, xnum, xden.
    const qsp::FileTopology top = qsp::file_topology(bytes);
    std::vector<qsp::ComponentPartition> parts;
    for (const qsp::TopologyCode& code : top.codes) parts.push_back(qsp::partition_from_code(code));
    const qsp::MeshLayout layout =
        qsp::assemble(parts, static_cast<std::uint32_t>(top.unreferenced), info.geometry_order);
    std::ofstream st(std::string(argv[2]) + ".stencil");
    for (std::uint32_t k = 0; k < layout.stencil.size(); ++k) {
      const qsp::Stencil& s = layout.stencil[k];
      st << (layout.coding.empty() ? k : layout.coding[k]);
      for (std::uint32_t v : s.vertex_fields()) st << ' ' << (v == qsp::kInvalid ? -1 : std::int64_t{v});
      st << ' ' << s.far_dist << ' ' << s.e_dist << ' ' << s.n_dist << ' ' << s.xnum << ' ' << s.xden << '\n';
    }

    // Positions in canonical order: with an order section, decode() restored the input's order.
    std::vector<float> pos = mesh.positions;
    const qsp::OrderMap om = qsp::file_order(bytes);
    for (std::size_t j = 0; j < om.vertex.size(); ++j)
      for (int a = 0; a < 3; ++a) pos[3 * std::size_t{om.vertex[j]} + a] = mesh.positions[3 * j + a];
    std::ofstream(std::string(argv[2]) + ".pos", std::ios::binary)
        .write(reinterpret_cast<const char*>(pos.data()), static_cast<std::streamsize>(pos.size() * 4));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dump_stencils: %s: %s\n", argv[1], e.what());
    return 1;
  }
}
