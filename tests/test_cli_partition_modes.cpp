// `qsp compress --partition MODE` end to end: every mode decodes to the same mesh, so recompressing
// the decoded mesh with the default partition gives exactly the bytes of compressing the original;
// and the default (auto) file is the smallest of the three modes'.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/cli.h"

namespace qsp {
namespace {

namespace fs = std::filesystem;
using testing::quote;
using testing::run_qsp;

using testing::slurp;

TEST(CliPartitionModes, EveryModeRoundTripsToTheSameMesh) {
  const testing::TempDir temp;
  const fs::path& dir = temp.path();
  for (const char* name :
       {"keenan_spot_quadrangulated.obj", "multi_component.obj", "l_shape.obj", "cube_4.obj"}) {
    SCOPED_TRACE(name);
    const std::string in = std::string(QSP_TESTDATA_DIR) + "/" + name;
    const fs::path ref = dir / "ref.qsp";
    ASSERT_EQ(
        run_qsp("compress -f --best --positions-only " + quote(in) + " " + quote(ref.string())).exit_code, 0);
    std::uintmax_t smallest = 0;
    for (const char* mode : {"motorcycle", "greedy", "merge"}) {
      const fs::path q = dir / (std::string(mode) + ".qsp"), back = dir / (std::string(mode) + ".obj"),
                     again = dir / (std::string(mode) + "_again.qsp");
      const auto c = run_qsp("compress -f --best --positions-only --partition " + std::string(mode) + " " +
                             quote(in) + " " + quote(q.string()));
      ASSERT_EQ(c.exit_code, 0) << c.err;
      const std::uintmax_t size = fs::file_size(q);
      EXPECT_GE(size, fs::file_size(ref)) << mode << ": the default keeps the smallest partition";
      smallest = smallest == 0 ? size : std::min(smallest, size);
      ASSERT_EQ(run_qsp("decompress -f " + quote(q.string()) + " " + quote(back.string())).exit_code, 0);
      ASSERT_EQ(run_qsp("compress -f --best " + quote(back.string()) + " " + quote(again.string())).exit_code,
                0);
      EXPECT_EQ(slurp(again), slurp(ref)) << mode;
    }
    EXPECT_EQ(smallest, fs::file_size(ref));
  }
}

}  // namespace
}  // namespace qsp
