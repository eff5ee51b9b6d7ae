// dump_stencils IN.qsp PREFIX: what qspgeo.py needs besides the spec. The stencils come from the
// library (the topology and grid layout are checked by other tests; qspgeo.py checks the geometry
// text), written per coding position to PREFIX.stencil; the reference decoder's positions, as float
// bits in canonical vertex order, to PREFIX.pos. Exit 0, else 1 with a message.
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "qsp/canonical.h"
#include "qsp/codec.h"
#include "qsp/geometry.h"
#include "qsp/partition.h"

namespace {

std::uint64_t varint(std::string_view b, std::size_t& at) {
  std::uint64_t v = 0;
  for (int shift = 0; at < b.size(); shift += 7) {
    const auto x = static_cast<std::uint8_t>(b[at++]);
    v |= std::uint64_t{x & 0x7Fu} << shift;
    if (!(x & 0x80)) return v;
  }
  throw std::runtime_error("truncated varint");
}

struct Section {
  std::uint8_t tag;
  std::size_t offset;
  std::string_view payload;
};

// The sections of a file the reference decoder has accepted (format spec, "File structure").
std::vector<Section> sections(std::string_view b) {
  std::size_t at = 11;
  varint(b, at);  // file size
  std::vector<Section> out;
  while (at < b.size() - 8) {
    const auto tag = static_cast<std::uint8_t>(b[at++]);
    const std::uint64_t len = varint(b, at);
    out.push_back({tag, at, b.substr(at, len)});
    at += len;
  }
  return out;
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
    const qsp::QuadMesh mesh = qsp::decode(bytes);  // first: only files it accepts are parsed below
    const std::vector<Section> secs = sections(bytes);
    qsp::CodingOrder order = qsp::CodingOrder::kLayout;
    for (const Section& s : secs)
      if (s.tag == 3) order = qsp::geometry_coding_order(s.payload);

    const qsp::FileTopology top = qsp::file_topology(bytes);
    std::ofstream st(std::string(argv[2]) + ".stencil");
    std::uint32_t base = 0;
    for (const qsp::TopologyCode& code : top.codes) {
      const qsp::GridLayout g = qsp::grid_layout(qsp::partition_from_code(code), order);
      for (std::uint32_t k = 0; k < g.vertex_count; ++k) {
        qsp::GridLayout::Stencil s = g.stencil[k];
        st << base + (g.coding.empty() ? k : g.coding[k]);
        for (std::uint32_t* v : s.vertex_fields())
          st << ' ' << (*v == qsp::kInvalid ? -1 : std::int64_t{*v + base});
        st << ' ' << s.far_dist << ' ' << s.e_dist << ' ' << s.n_dist << ' ' << s.xnum << ' ' << s.xden
           << '\n';
      }
      base += g.vertex_count;
    }
    for (std::uint64_t u = 0; u < top.unreferenced; ++u, ++base) {  // w = the previous vertex
      st << base << ' ' << (base > 0 ? std::int64_t{base} - 1 : -1);
      for (int f = 1; f < 19; ++f) st << " -1";
      st << " 0 0 0 0 0\n";
    }

    // Positions in canonical order: with an order section, decode() restored the input's order.
    std::vector<float> pos = mesh.positions;
    for (const Section& s : secs) {
      if (s.tag != 4) continue;
      const qsp::OrderMap om =
          qsp::decode_order(s.payload, s.offset, mesh.vertex_count(), mesh.face_count(),
                            bytes[8] >= 2 ? qsp::StreamEnds::kCompact : qsp::StreamEnds::kLzma);
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
