// The corpus itself: the shared meshes are there when the run needs them, every file is listed in its
// manifest, and corpus() holds exactly testdata/ plus those files. A test that needs ../shared/meshes
// calls QSP_NEEDS_SHARED() (tests/support/corpus.h): skipped in a plain clone, failed under CI.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "support/corpus.h"

namespace fs = std::filesystem;

namespace qsp {
namespace {

std::size_t testdata_mesh_count() {
  const fs::path t(QSP_TESTDATA_DIR);
  return testing::mesh_files_in(t).size() + testing::mesh_files_in(t / "golden").size() +
         testing::mesh_files_in(t / "known-answers").size();
}

// The sentinel: fails where the shared meshes are required (CI=true, as CI sets it, or
// QSP_REQUIRE_SHARED=1) and missing; in a plain clone it is skipped, saying what that costs.
TEST(Corpus, SharedMeshesArePresentWhereRequired) {
  const fs::path meshes = testing::shared_dir() / "meshes";
  if (testing::shared_present()) return;
  if (testing::shared_required()) {
    FAIL() << meshes << " (its MANIFEST.tsv) is missing, and this run requires it (CI=true or "
           << "QSP_REQUIRE_SHARED=1): every test that needs it would be skipped";
  }
  std::printf(
      "[ corpus   ] %s is absent: the tests that need it are skipped (ctest lists them as Skipped), and the "
      "corpus loops run over the %zu meshes of testdata/ only\n",
      meshes.string().c_str(), testdata_mesh_count());
  GTEST_SKIP() << meshes << " absent (plain clone): shared-mesh tests skipped";
}

// Each shared folder holds exactly the files its manifest lists, and corpus() is testdata/ plus them.
TEST(Corpus, HoldsExactlyTestdataAndTheManifestsFiles) {
  QSP_NEEDS_SHARED();
  std::size_t rows = 0;
  for (const fs::path& dir : testing::shared_mesh_dirs()) {
    SCOPED_TRACE(dir.string());
    std::set<std::string> listed, found;
    for (const auto& [name, row] : testing::read_manifest(dir / "MANIFEST.tsv")) listed.insert(name);
    for (const fs::path& p : testing::mesh_files_in(dir)) found.insert(p.filename().string());
    EXPECT_FALSE(listed.empty());
    EXPECT_EQ(found, listed) << "files against manifest rows";
    rows += listed.size();
  }
  EXPECT_EQ(testing::shared_meshes().size(), rows);
  EXPECT_EQ(testing::corpus().size(), testdata_mesh_count() + rows);
  std::printf("[ corpus   ] %zu testdata meshes + %zu shared (%d of them valid quad meshes)\n",
              testdata_mesh_count(), rows, testing::expected_valid_count(testing::shared_meshes()));
}

}  // namespace
}  // namespace qsp
