// dump_stencils IN.qsp PREFIX: what qspgeo.py needs besides the spec. The stencils come from the
// library (the topology and grid layout are checked by other tests; qspgeo.py checks the geometry
// text), written per coding position to PREFIX.stencil; the reference decoder's positions, as float
// bits in canonical vertex order, to PREFIX.pos (of a polygon file: its quad submesh's layout). For
// qsppoly.py, the reference decoder's whole output, decode_polygons' (without an order section, which
// qsppoly.py does not read): PREFIX.mesh ("V F", per vertex three float bits in hex, per face its
// degree and corners) and PREFIX.comments (per comment line "x" and its bytes in hex). Exit 0, else 1
// with a message.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "container.h"
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
    const std::string file = text.str();
    const qsp::container::File parsed = qsp::container::parse(file);
    // A polygon file's counts, topology and geometry are a 3.0 file of its quad submesh (the spec's
    // "Sections"): that file, for the layout's stencils and positions.
    std::string bytes = file;
    if (parsed.find(qsp::container::kTagPolygons)) {
      std::string sections;
      for (std::uint8_t tag :
           {qsp::container::kTagCounts, qsp::container::kTagTopology, qsp::container::kTagGeometry})
        qsp::container::put_section(sections, tag, parsed.find(tag)->payload);
      bytes = qsp::container::seal(parsed.major, 0, parsed.level, sections);
    }
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
      // The layout's 19 fields (the mirror source comes from the symmetry section, which qspgeo.py reads).
      const auto fields = s.vertex_fields();
      for (std::size_t f = 0; f < 19; ++f)
        st << ' ' << (fields[f] == qsp::kInvalid ? -1 : std::int64_t{fields[f]});
      st << ' ' << s.far_dist << ' ' << s.e_dist << ' ' << s.n_dist << ' ' << s.xnum << ' ' << s.xden << '\n';
    }

    // Positions in canonical order: with an order section, decode() restored the input's order.
    std::vector<float> pos = mesh.positions;
    const qsp::OrderMap om = qsp::file_order(bytes);
    for (std::size_t j = 0; j < om.vertex.size(); ++j)
      for (int a = 0; a < 3; ++a) pos[3 * std::size_t{om.vertex[j]} + a] = mesh.positions[3 * j + a];
    std::ofstream(std::string(argv[2]) + ".pos", std::ios::binary)
        .write(reinterpret_cast<const char*>(pos.data()), static_cast<std::streamsize>(pos.size() * 4));

    // The whole output as the reference decodes it.
    if (!parsed.find(qsp::container::kTagOrder)) {
      const qsp::PolygonMesh out = qsp::decode_polygons(file);
      std::ofstream ms(std::string(argv[2]) + ".mesh");
      ms << out.vertex_count() << ' ' << out.face_count() << '\n' << std::hex;
      for (float x : out.positions) {
        std::uint32_t u;
        std::memcpy(&u, &x, 4);
        ms << u << (&x == &out.positions.back() || (&x - out.positions.data()) % 3 == 2 ? '\n' : ' ');
      }
      ms << std::dec;
      for (std::size_t f = 0; f < out.face_count(); ++f) {
        ms << out.degree(f);
        for (std::uint32_t k = out.face_offsets[f]; k < out.face_offsets[f + 1]; ++k)
          ms << ' ' << out.corners[k];
        ms << '\n';
      }
    }
    std::ofstream cs(std::string(argv[2]) + ".comments");
    for (const std::string& line : qsp::file_comments(file)) {
      cs << 'x';
      for (unsigned char ch : line) cs << "0123456789abcdef"[ch >> 4] << "0123456789abcdef"[ch & 15];
      cs << '\n';
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dump_stencils: %s: %s\n", argv[1], e.what());
    return 1;
  }
}
