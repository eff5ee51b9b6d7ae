// libFuzzer target: the PLY reader (ascii, binary little and big endian). read_ply_file takes a path,
// so each input is written to a per-process file in /dev/shm (or /tmp) first. Properties as for
// read_obj: no crash, no sanitizer report, only typed non-internal errors, and an accepted mesh has
// finite positions, in-range indices and no degenerate face; build_adjacency refuses it cleanly or not at
// all.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "fuzz_check.h"

namespace {

const std::string& scratch_path() {
  static const std::string path = [] {
    const char* dir = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
    return std::string(dir) + "/qsp_fuzz_" + std::to_string(::getpid()) + ".ply";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace qsp;
  const std::string& path = scratch_path();
  if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
    if (size) std::fwrite(data, 1, size, f);
    std::fclose(f);
  } else {
    fuzz::finding("cannot write " + path);
  }
  ReadReport report;
  QuadMesh mesh;
  try {
    mesh = read_ply_file(path, &report);
  } catch (const Error& e) {
    fuzz::check_error(e, "read_ply_file");
    if (e.code() == ErrorCode::kIo)
      fuzz::finding(std::string("read_ply_file: I/O error on a readable file: ") + e.what());
    return 0;
  }
  fuzz::check_reader_output(mesh, report, "read_ply_file");
  fuzz::check_adjacency(mesh);
  return 0;
}
