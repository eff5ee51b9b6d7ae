// The topology section's coder (src/codec_topology.cpp): hand-built codes round-trip, limits hold while
// decoding, implied lengths are not stored.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "codec_sections.h"
#include "qsp/canonical.h"
#include "qsp/error.h"
#include "qsp/partition.h"

namespace qsp {
namespace {

// ---- Topology streams ----

// A single quad: one patch and one hole, four darts each (worked out in qsp_format.md).
TopologyCode single_quad_code() {
  TopologyCode c;
  c.kind = ComponentKind::kDisk;
  c.next_ref = {0, 0, 0, 2, 4, 1, 2, 1};
  c.edge_length = {1, 1, 1, 1};
  c.corner = {1, 0, 1, 0, 0, 1, 1, 0};
  return c;
}

TEST(Topology, HandBuiltCodesRoundTrip) {
  TopologyCode torus;
  torus.kind = ComponentKind::kTorus;
  torus.a = 9, torus.b = 6, torus.twist = 2;
  TopologyCode annulus;
  annulus.kind = ComponentKind::kAnnulus;
  annulus.a = 12, annulus.b = 3;
  TopologyCode big = single_quad_code();
  big.edge_length = {70000, 3, 3, 70000};  // edges 0 and 3 are opposite, so are 1 and 2
  std::vector<TopologyCode> codes = {single_quad_code(), torus, annulus, big};
  std::string bytes = encode_topology(codes);
  std::vector<TopologyCode> back = decode_topology(bytes, 0, codes.size(), 1000, 100000);
  ASSERT_EQ(back.size(), codes.size());
  for (std::size_t i = 0; i < codes.size(); ++i) EXPECT_TRUE(back[i] == codes[i]) << i;
  // The code is a valid partition: a 1x1 grid.
  ComponentPartition p = partition_from_code(back[0]);
  EXPECT_EQ(grid_layout(p).quads.size(), 4u);
  // Limits are enforced while decoding.
  EXPECT_THROW(decode_topology(bytes, 0, codes.size(), 7, 100000), Error);  // 8 schematic edges
  EXPECT_THROW(decode_topology(bytes, 0, codes.size(), 1000, 69999), Error);
}

TEST(Topology, LengthsImpliedByOppositeSidesAreNotStored) {
  // A 5x7 patch: only two of the four lengths are coded, and a code whose opposite sides disagree
  // is refused by the encoder as a bug.
  TopologyCode c = single_quad_code();
  c.edge_length = {5, 7, 7, 5};
  std::vector<TopologyCode> one{c};
  auto back = decode_topology(encode_topology(one), 0, 1, 100, 100);
  EXPECT_TRUE(back[0] == c);
  c.edge_length = {5, 7, 6, 5};
  EXPECT_THROW(encode_topology(std::vector<TopologyCode>{c}), Error);
}

}  // namespace
}  // namespace qsp
