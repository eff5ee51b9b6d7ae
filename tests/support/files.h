// Files in tests, once: a whole file's bytes (slurp), bytes written to a file (spit), and a temporary
// folder that is gone when the test is (TempDir, or the TempDirTest fixture).
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>

namespace qsp::testing {

// A whole file's bytes (empty if it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Writes `bytes` to `path`, replacing it; fails the test (not throws) when it cannot.
inline void spit(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  EXPECT_TRUE(f.good()) << "cannot write " << path;
}

// A fresh folder under GoogleTest's temporary folder, named after the running test and unique
// (mkdtemp), removed with everything in it when the object goes.
class TempDir {
 public:
  TempDir() {
    std::string name = "qsp_";
    if (const auto* info = ::testing::UnitTest::GetInstance()->current_test_info())
      name += std::string(info->test_suite_name()) + "." + info->name() + "_";
    for (char& c : name)
      if (c == '/') c = '_';  // parameterized tests
    std::string pattern = ::testing::TempDir() + name + "XXXXXX";
    if (::mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "cannot make a folder like " << pattern;
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  // The path of `name` inside the folder, as a string (what run_qsp's command lines quote).
  std::string p(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A fixture whose tests each get their own TempDir: dir_ is its folder, p(name) a path in it.
class TempDirTest : public ::testing::Test {
 protected:
  std::string p(const std::string& name) const { return temp_.p(name); }

  TempDir temp_;
  const std::filesystem::path dir_ = temp_.path();
};

}  // namespace qsp::testing
