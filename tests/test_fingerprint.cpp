// Topology fingerprints (qsp/fingerprint.h): a .qsp's equals its mesh's whichever partition it stores,
// and the connectivity rebuilt from a file's codes is the mesh decode() gives, without positions.
#include <gtest/gtest.h>

#include "qsp/codec.h"
#include "qsp/fingerprint.h"
#include "qsp/io.h"
#include "qsp/match.h"
#include "support/corpus.h"
#include "support/mesh_gen.h"

namespace qsp {
namespace {

// Every corpus mesh of up to 5000 vertices, compressed in each partition mode (and keeping the order):
// the file's fingerprint is the mesh's (and a renumbered copy's); the connectivity rebuilt from the
// file's codes is decode()'s for files without an order section, and isomorphic to the mesh always.
TEST(Fingerprint, AQspFileHasItsMeshsFingerprint) {
  int meshes = 0;
  for (const auto& path : testing::corpus()) {
    QuadMesh mesh;
    if (!testing::read_valid(path, mesh) || mesh.vertex_count() > 5000) continue;
    SCOPED_TRACE(path.string());
    const std::uint64_t fp = mesh_fingerprint(mesh);
    EXPECT_EQ(mesh_fingerprint(testing::shuffled(mesh, 3)), fp);
    struct Case {
      PartitionMode mode;
      bool keep_order;
    };
    for (const Case c : {Case{PartitionMode::kMotorcycle, false}, Case{PartitionMode::kGreedy, false},
                         Case{PartitionMode::kMerge, false}, Case{PartitionMode::kMotorcycle, true}}) {
      SCOPED_TRACE(partition_mode_name(c.mode));
      EncodeOptions eo;
      eo.partition = c.mode;
      eo.keep_order = c.keep_order;
      eo.level = 1;
      const std::string bytes = encode(mesh, eo);
      EXPECT_EQ(file_fingerprint(bytes), fp);
      const QuadMesh rebuilt = file_connectivity(file_topology(bytes));
      ASSERT_EQ(rebuilt.vertex_count(), mesh.vertex_count());
      for (float x : rebuilt.positions) ASSERT_EQ(x, 0.0f);
      if (!c.keep_order) {
        EXPECT_EQ(rebuilt.quads, decode(bytes).quads);
      }
      EXPECT_TRUE(match(mesh, rebuilt).isomorphic);
    }
    ++meshes;
  }
  // read_valid fails any refusal the manifest does not call for; this floor guards the corpus itself
  // (testdata's 25 meshes alone in a clone without ../shared, which fails the sentinel under CI).
  EXPECT_GT(meshes, testing::shared_present() ? 40 : 20);
}

TEST(Fingerprint, DiffersAcrossTopologiesAndRefusesDamagedFiles) {
  const QuadMesh a = testing::cube(3), b = testing::grid(4, 3);
  EXPECT_NE(mesh_fingerprint(a), mesh_fingerprint(b));
  std::string bytes = encode(a);
  bytes[bytes.size() / 2] ^= 0x10;
  EXPECT_THROW(file_fingerprint(bytes), Error);
  EXPECT_THROW(file_fingerprint(bytes.substr(0, 10)), Error);
}

}  // namespace
}  // namespace qsp
