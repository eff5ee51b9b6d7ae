// libFuzzer target: the exact readers (read_obj_mesh, read_off_mesh, read_ply_mesh) and the Mesh
// writers. The format is sniffed from the input ("ply" magic, an [ST][C][N]OFF header, else OBJ), so
// the read_obj, read_off and read_ply seed folders all serve. Properties: no crash, no sanitizer
// report, only typed non-internal errors; an accepted mesh passes check_mesh, writes back in its own
// format, reads back to the same faces and numbers, and that second write is the first one byte for
// byte; an OBJ also writes in canonical order, to the same faces.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fuzz_check.h"
#include "qsp/polymesh.h"

namespace {

using namespace qsp;

MeshFormat sniff(std::string_view s) {
  if (s.substr(0, 3) == "ply") return MeshFormat::kPly;
  std::size_t i = 0;
  for (;;) {  // the first word after blank and comment lines
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r' || s[i] == '\n')) ++i;
    if (i < s.size() && s[i] == '#') {
      while (i < s.size() && s[i] != '\n') ++i;
      continue;
    }
    break;
  }
  std::size_t e = i;
  while (e < s.size() && s[e] != ' ' && s[e] != '\t' && s[e] != '\r' && s[e] != '\n') ++e;
  const std::string_view word = s.substr(i, e - i);
  return word.size() >= 3 && word.substr(word.size() - 3) == "OFF" ? MeshFormat::kOff : MeshFormat::kObj;
}

Mesh read(std::string_view bytes, MeshFormat format, const char* source) {
  if (format == MeshFormat::kPly) return read_ply_mesh(bytes, source);
  return format == MeshFormat::kOff ? read_off_mesh(bytes, source) : read_obj_mesh(bytes, source);
}

bool same_numbers(const Numbers& a, const Numbers& b) {
  return a.precision == b.precision && fuzz::same_bits(a.f32, b.f32) && a.f64.size() == b.f64.size() &&
         (a.f64.empty() || std::memcmp(a.f64.data(), b.f64.data(), 8 * a.f64.size()) == 0) &&
         a.decimals.size() == b.decimals.size();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const MeshFormat format = sniff(bytes);
  Mesh m;
  try {
    m = read(bytes, format, "fuzz");
  } catch (const Error& e) {
    fuzz::check_error(e, "read_mesh");
    return 0;
  }
  try {
    check_mesh(m);
  } catch (const Error& e) {
    fuzz::finding(std::string("check_mesh refuses an accepted mesh: ") + e.what());
  }
  std::string once, twice;
  Mesh back;
  try {
    once = write_mesh(m, format);
    back = read(once, format, "rewritten");
    twice = write_mesh(back, format);
  } catch (const Error& e) {
    fuzz::finding(std::string("write/read of an accepted mesh failed: ") + e.what());
  }
  if (back.corner_vertices != m.corner_vertices || back.face_offsets != m.face_offsets ||
      !same_numbers(back.positions, m.positions) || !same_numbers(back.texcoords, m.texcoords) ||
      back.corner_texcoords != m.corner_texcoords || back.groups.face != m.groups.face) {
    fuzz::finding("read(write(m)) != m");
  }
  if (once != twice) fuzz::finding("write(read(write(m))) != write(m)");
  if (format == MeshFormat::kObj) {
    try {
      const Mesh canonical = read_obj_mesh(write_obj_mesh(m, {.keep_order = false}), "canonical");
      if (canonical.corner_vertices != m.corner_vertices) fuzz::finding("canonical OBJ changed the faces");
    } catch (const Error& e) {
      fuzz::finding(std::string("canonical OBJ of an accepted mesh failed: ") + e.what());
    }
  }
  return 0;
}
