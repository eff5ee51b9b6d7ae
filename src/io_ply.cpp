// PLY reader (ASCII, binary little and big endian), qsp's own. OpenMesh was the first plan, but
// its reader silently rewrites input (duplicates vertices at non-manifold spots, drops faces that
// repeat a vertex or have bad indices) while reporting success, prints to stderr, and cannot read
// some valid layouts (int16 coordinates). Reading the file ourselves gives exact positions, the
// file's faces corner for corner, and located errors; manifoldness is checked by build_adjacency
// as for OBJ/OFF. tests/test_io.cpp compares this reader with OpenMesh on files both can read.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>
#include <tuple>
#include <unordered_set>
#include <vector>

#include "io_numbers.h"
#include "non_quads.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {

enum class PlyType : std::uint8_t {
  kNone,
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

// Each PlyType's names (PLY 1.0's, then the sized alias), size in bytes and, for integers, range; in
// the enum's order.
struct PlyTypeInfo {
  std::string_view name, alias;
  int size;
  std::int64_t lo, hi;
};
constexpr PlyTypeInfo kPlyTypes[] = {
    {"none", "", 0, 0, 0},
    {"char", "int8", 1, -128, 127},
    {"uchar", "uint8", 1, 0, 255},
    {"short", "int16", 2, -32768, 32767},
    {"ushort", "uint16", 2, 0, 65535},
    {"int", "int32", 4, INT32_MIN, INT32_MAX},
    {"uint", "uint32", 4, 0, UINT32_MAX},
    {"float", "float32", 4, INT64_MIN, INT64_MAX},  // floats are never lengths or indices
    {"double", "float64", 8, INT64_MIN, INT64_MAX},
};
const PlyTypeInfo& type_info(PlyType t) { return kPlyTypes[static_cast<std::size_t>(t)]; }

PlyType parse_type(std::string_view t) {
  for (std::size_t i = 1; i < std::size(kPlyTypes); ++i) {
    if (t == kPlyTypes[i].name || t == kPlyTypes[i].alias) return static_cast<PlyType>(i);
  }
  return PlyType::kNone;
}

int type_size(PlyType t) { return type_info(t).size; }

bool is_float_type(PlyType t) { return t == PlyType::kFloat32 || t == PlyType::kFloat64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kNone;        // value type (of the entries, for a list)
  PlyType count_type = PlyType::kNone;  // list length type; kNone for a scalar
  bool list() const { return count_type != PlyType::kNone; }
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t header_line = 0;
  std::vector<PlyProperty> properties;

  int find(std::string_view n) const {
    for (std::size_t i = 0; i < properties.size(); ++i) {
      if (properties[i].name == n) return static_cast<int>(i);
    }
    return -1;
  }
};

struct PlyHeader {
  enum class Format : std::uint8_t { kAscii, kLittle, kBig } format = Format::kAscii;
  std::size_t data_offset = 0;  // first byte after end_header's newline
  std::uint64_t header_lines = 0;
  std::vector<PlyElement> elements;
  std::vector<std::string> comments, obj_info;  // the text after the keyword and one blank
};

// A header line's text after its keyword and the blank that follows it.
std::string after_keyword(std::string_view line, std::size_t keyword) {
  std::string_view rest = line.substr(std::min(keyword, line.size()));
  if (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
  return std::string(rest);
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t s = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > s) words.push_back(line.substr(s, i - s));
  }
  return words;
}

std::string shown(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 40)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  return out;
}

[[noreturn]] void fail_at(ErrorCode code, const std::string& path, std::uint64_t line,
                          const std::string& what) {
  throw Error(code, path + ":" + std::to_string(line) + ": " + what);
}

PlyHeader parse_header(std::string_view bytes, const std::string& path) {
  PlyHeader h;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  bool have_format = false;
  std::unordered_set<std::string> names;  // of the current element's properties (a linear search per
                                          // property was quadratic in a 1 MiB header)
  constexpr std::size_t kMaxHeader = 1 << 20;
  for (;;) {
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string_view::npos || nl > kMaxHeader) {
      fail_at(ErrorCode::kParse, path, line_no + 1, "PLY header has no end_header line");
    }
    std::string_view line = bytes.substr(pos, nl - pos);
    pos = nl + 1;
    ++line_no;
    // Every CR before the LF is the line end (a comment text ending in CR could not be written back).
    while (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const auto w = split_words(line);
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply")
        fail_at(ErrorCode::kParse, path, 1, "not a PLY file (no 'ply' magic line)");
      continue;
    }
    if (w.empty()) continue;
    if (w[0] == "comment" || w[0] == "obj_info") {
      const std::size_t at = line.find(w[0]) + w[0].size();
      (w[0] == "comment" ? h.comments : h.obj_info).push_back(after_keyword(line, at));
      continue;
    }
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0")
        fail_at(ErrorCode::kParse, path, line_no, "malformed PLY format line");
      if (w[1] == "ascii") {
        h.format = PlyHeader::Format::kAscii;
      } else if (w[1] == "binary_little_endian") {
        h.format = PlyHeader::Format::kLittle;
      } else if (w[1] == "binary_big_endian") {
        h.format = PlyHeader::Format::kBig;
      } else {
        fail_at(ErrorCode::kParse, path, line_no, "unknown PLY format '" + shown(w[1]) + "'");
      }
      have_format = true;
    } else if (w[0] == "element") {
      if (w.size() != 3) fail_at(ErrorCode::kParse, path, line_no, "malformed PLY element line");
      PlyElement e;
      e.name = std::string(w[1]);
      e.header_line = line_no;
      const auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
      if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size()) {
        fail_at(ErrorCode::kParse, path, line_no, "malformed PLY element count '" + shown(w[2]) + "'");
      }
      h.elements.push_back(std::move(e));
      names.clear();
    } else if (w[0] == "property") {
      if (h.elements.empty()) fail_at(ErrorCode::kParse, path, line_no, "PLY property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.count_type = parse_type(w[2]);
        p.type = parse_type(w[3]);
        p.name = std::string(w[4]);
        if (p.count_type == PlyType::kNone || is_float_type(p.count_type)) p.type = PlyType::kNone;
      } else if (w.size() == 3) {
        p.type = parse_type(w[1]);
        p.name = std::string(w[2]);
      }
      if (p.type == PlyType::kNone) fail_at(ErrorCode::kParse, path, line_no, "malformed PLY property line");
      // A second x would otherwise be read past and dropped: which one is the position is not ours to guess.
      if (!names.insert(p.name).second) {
        fail_at(ErrorCode::kParse, path, line_no,
                "PLY element '" + shown(h.elements.back().name) + "' declares property '" + shown(p.name) +
                    "' twice");
      }
      h.elements.back().properties.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      if (w.size() != 1) fail_at(ErrorCode::kParse, path, line_no, "unexpected text after end_header");
      break;
    } else {
      fail_at(ErrorCode::kParse, path, line_no, "unknown PLY header line '" + shown(w[0]) + "'");
    }
  }
  if (!have_format) fail_at(ErrorCode::kParse, path, 2, "PLY header has no format line");
  h.data_offset = pos;
  h.header_lines = line_no;
  return h;
}

// What the header promises: checked limits, and counts the data can hold.
struct PlyLayout {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  int x = -1, y = -1, z = -1, indices = -1;
};

PlyLayout check_header(const PlyHeader& h, std::string_view bytes, const std::string& path) {
  PlyLayout l;
  const std::uint64_t available = bytes.size() - h.data_offset;
  // In ASCII the last value needs no separator after it: one byte of slack.
  const std::uint64_t room = available + (h.format == PlyHeader::Format::kAscii ? 1 : 0);
  std::uint64_t min_bytes = 0;
  for (const auto& e : h.elements) {
    // Smallest encoding of one element: a 1-character token and a separator per value in ASCII.
    std::uint64_t per = 0;
    for (const auto& p : e.properties) {
      per += h.format == PlyHeader::Format::kAscii ? 2 : type_size(p.list() ? p.count_type : p.type);
    }
    if (per && e.count > room / per) {
      fail_at(ErrorCode::kParse, path, e.header_line,
              "PLY header declares " + std::to_string(e.count) + " " + shown(e.name) + " elements but only " +
                  std::to_string(available) + " bytes of data follow (truncated file?)");
    }
    min_bytes += e.count * per;
    if (e.name == "vertex" && !l.vertex) {
      l.vertex = &e;
    } else if (e.name == "face" && !l.face) {
      l.face = &e;
    } else if (e.count > 0) {
      fail_at(ErrorCode::kUnsupported, path, e.header_line,
              "PLY element '" + shown(e.name) + "' is not supported; qsp stores quad meshes only");
    }
  }
  if (min_bytes > room) {
    fail_at(ErrorCode::kParse, path, h.header_lines,
            "PLY header declares more data than the file holds (truncated?)");
  }
  if (!l.vertex) fail_at(ErrorCode::kParse, path, h.header_lines, "PLY file has no vertex element");
  l.x = l.vertex->find("x");
  l.y = l.vertex->find("y");
  l.z = l.vertex->find("z");
  if (l.x < 0 || l.y < 0 || l.z < 0 || l.vertex->properties[l.x].list() || l.vertex->properties[l.y].list() ||
      l.vertex->properties[l.z].list()) {
    fail_at(ErrorCode::kParse, path, l.vertex->header_line,
            "PLY vertex element needs scalar x, y and z properties");
  }
  if (l.vertex->count > kMaxVertices) {
    fail_at(ErrorCode::kLimit, path, l.vertex->header_line,
            std::to_string(l.vertex->count) + " vertices; qsp's limit is " + std::to_string(kMaxVertices));
  }
  if (!l.face) return l;
  l.indices = l.face->find("vertex_indices");
  if (l.indices < 0) l.indices = l.face->find("vertex_index");
  if (l.indices < 0 || !l.face->properties[l.indices].list() ||
      is_float_type(l.face->properties[l.indices].type)) {
    fail_at(ErrorCode::kParse, path, l.face->header_line,
            "PLY face element has no integer vertex_indices list");
  }
  if (l.face->count > kMaxFaces) {
    fail_at(ErrorCode::kLimit, path, l.face->header_line,
            std::to_string(l.face->count) + " faces; qsp's limit is " + std::to_string(kMaxFaces));
  }
  return l;
}

// One value as the file has it (exact reading).
struct PlyValue {
  enum class Kind : std::uint8_t { kFloat32, kFloat64, kInteger, kText } kind = Kind::kInteger;
  float f = 0.0f;
  double d = 0.0;
  std::int64_t i = 0;
  detail::TextNumber text;

  bool finite() const {
    return kind == Kind::kFloat32 ? std::isfinite(f) : kind == Kind::kFloat64 ? std::isfinite(d) : true;
  }
  void push(Numbers& n) const {
    switch (kind) {
      case Kind::kFloat32:
        return detail::push_float32(n, f);
      case Kind::kFloat64:
        return detail::push_float64(n, d);
      case Kind::kInteger:
        return detail::push_integer(n, i);
      case Kind::kText:
        return detail::push_text(n, text);
    }
  }
};

// Reads the data section value by value. Positions keep float32 values bit for bit; ASCII text
// goes through std::from_chars<float> like OBJ/OFF; float64 values round to nearest float32.
class PlyData {
 public:
  PlyData(const PlyHeader& h, std::string_view bytes, const std::string& path)
      : format_(h.format),
        begin_(bytes.data()),
        p_(bytes.data() + h.data_offset),
        end_(bytes.data() + bytes.size()),
        line_(h.header_lines + 1),
        path_(path) {}

  std::uint64_t line() const { return line_; }
  bool ascii() const { return format_ == PlyHeader::Format::kAscii; }

  // Where we are, for messages: a line in ASCII, a byte offset in binary.
  [[noreturn]] void fail(ErrorCode code, const std::string& what) const {
    if (ascii()) fail_at(code, path_, line_, what);
    throw Error(code, path_ + ": byte " + std::to_string(p_ - begin_) + ": " + what);
  }

  // Starts an element: ASCII elements sit on their own line.
  void begin_element() {
    if (!ascii()) return;
    skip_blank_lines();
  }
  void end_element(const char* what, std::uint64_t index) {
    if (!ascii()) return;
    skip_spaces();
    if (p_ < end_ && *p_ != '\n') {
      fail(ErrorCode::kParse, "unexpected '" + shown(token()) + "' after " + what + " " +
                                  std::to_string(index) + " (more values than the header declares)");
    }
  }
  // Only blank space may follow the last element.
  void finish() {
    if (ascii()) {
      skip_blank_lines();
      if (p_ == end_) return;
    } else if (p_ == end_) {
      return;
    }
    fail(ErrorCode::kParse,
         "unexpected data after the last element (" + std::to_string(end_ - p_) + " bytes)");
  }

  // Vertex `index`'s coordinate as a float32; one float32 does not hold exactly is noted in `r`.
  float coordinate(PlyType t, const char* what, std::uint64_t index, ReadReport& r) {
    float f = 0.0f;
    if (!is_float_type(t)) {
      const std::int64_t v = integer(t, what, index);  // ASCII too: an integer in the type's range
      f = static_cast<float>(v);
      if (static_cast<double>(f) != static_cast<double>(v)) [[unlikely]]
        r.note_rounded(ascii() ? line_ : 0, index, std::to_string(v), f);
    } else if (ascii()) {
      const std::string_view tok = next_token(what, index);
      const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), f);
      if (ec == std::errc::invalid_argument || ptr != tok.data() + tok.size()) {
        fail(ErrorCode::kParse,
             std::string("malformed number '") + shown(tok) + "' in " + what + " " + std::to_string(index));
      }
      if (ec == std::errc::result_out_of_range) {
        fail(ErrorCode::kBadNumber, "number '" + shown(tok) + "' in " + what + " " + std::to_string(index) +
                                        " is outside the float32 range");
      }
      detail::TextNumber text;
      const char* e = tok.data() + tok.size();
      if (detail::read_number(
              tok.data(), e, [e](const char* q) { return q == e; }, text) == detail::NumberStatus::kOk &&
          !detail::float32_by_digits(text) && !detail::float32_holds(text)) [[unlikely]]
        r.note_rounded(line_, index, tok, f);
    } else if (t == PlyType::kFloat32) {
      f = std::bit_cast<float>(static_cast<std::uint32_t>(raw(4, what, index)));
    } else if (t == PlyType::kFloat64) {
      const double d = std::bit_cast<double>(raw(8, what, index));
      f = static_cast<float>(d);  // to nearest, as std::from_chars rounds text
      // Refused as text is: rounding to infinity, or a nonzero value to zero, would change the mesh.
      if (std::isfinite(d) && (std::isinf(f) || (f == 0.0f && d != 0.0))) {
        fail(ErrorCode::kBadNumber, std::string(what) + " " + std::to_string(index) +
                                        " has a coordinate outside the float32 range (it does not round to "
                                        "a finite nonzero float)");
      }
      if (static_cast<double>(f) != d && std::isfinite(d)) [[unlikely]] {
        std::string text;
        detail::append_double(text, d);
        r.note_rounded(0, index, text, f);
      }
    }
    if (!std::isfinite(f)) {
      fail(ErrorCode::kBadNumber,
           std::string(what) + " " + std::to_string(index) +
               " has a non-finite coordinate (NaN and infinity are not valid mesh data)");
    }
    return f;
  }

  // One scalar value as it is in the file (exact reading): binary bits or integers; ASCII integers
  // for integer types, exact text for float types. NaN and infinity are returned (as float64).
  PlyValue value(PlyType t, const char* what, std::uint64_t index) {
    PlyValue v;
    if (!is_float_type(t)) {
      v.kind = PlyValue::Kind::kInteger;
      v.i = integer(t, what, index);
    } else if (!ascii()) {
      if (t == PlyType::kFloat32) {
        v.kind = PlyValue::Kind::kFloat32;
        v.f = std::bit_cast<float>(static_cast<std::uint32_t>(raw(4, what, index)));
      } else {
        v.kind = PlyValue::Kind::kFloat64;
        v.d = std::bit_cast<double>(raw(8, what, index));
      }
    } else {
      const std::string_view tok = next_token(what, index);
      const char* e = tok.data() + tok.size();
      const detail::NumberStatus st = detail::read_number(
          tok.data(), e, [e](const char* q) { return q == e; }, v.text);
      v.kind = PlyValue::Kind::kText;
      double d = 0;
      if (st == detail::NumberStatus::kMalformed) {
        fail(ErrorCode::kParse,
             std::string("malformed number '") + shown(tok) + "' in " + what + " " + std::to_string(index));
      } else if (st == detail::NumberStatus::kNotFinite) {
        std::from_chars(tok.data(), e, d);
        v.kind = PlyValue::Kind::kFloat64;
        v.d = d;
      } else if (st == detail::NumberStatus::kFloatRange) {
        if (!detail::text_double(v.text, d)) {
          fail(ErrorCode::kBadNumber, "number '" + shown(tok) + "' in " + what + " " + std::to_string(index) +
                                          " is outside the float64 range");
        }
        v.text.f = static_cast<float>(d);
      }
    }
    return v;
  }

  std::int64_t integer(PlyType t, const char* what, std::uint64_t index) {
    if (ascii()) {
      const std::string_view tok = next_token(what, index);
      std::int64_t v = 0;
      const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
      if (ec != std::errc() || ptr != tok.data() + tok.size()) {
        fail(ErrorCode::kParse,
             std::string("malformed integer '") + shown(tok) + "' in " + what + " " + std::to_string(index));
      }
      // A value the declared type cannot hold is not what the writer meant (binary files cannot have one).
      if (const PlyTypeInfo& type = type_info(t); v < type.lo || v > type.hi) {
        fail(ErrorCode::kParse, "integer " + std::to_string(v) + " in " + what + " " + std::to_string(index) +
                                    " is out of range for its PLY type " + std::string(type.name));
      }
      return v;
    }
    const std::uint64_t b = raw(type_size(t), what, index);
    switch (t) {
      case PlyType::kInt8:
        return static_cast<std::int8_t>(b);
      case PlyType::kUint8:
        return static_cast<std::uint8_t>(b);
      case PlyType::kInt16:
        return static_cast<std::int16_t>(b);
      case PlyType::kUint16:
        return static_cast<std::uint16_t>(b);
      case PlyType::kInt32:
        return static_cast<std::int32_t>(b);
      case PlyType::kUint32:
        return static_cast<std::uint32_t>(b);
      default:
        break;
    }
    fail(ErrorCode::kParse, std::string("expected an integer in ") + what + " " + std::to_string(index));
  }

  // Any value of a property qsp does not keep; checked for syntax only.
  void skip(const PlyProperty& p, const char* what, std::uint64_t index) {
    const std::uint64_t n = p.list() ? length(p.count_type, what, index) : 1;
    for (std::uint64_t i = 0; i < n; ++i) {
      if (ascii()) {
        const std::string_view tok = next_token(what, index);
        double d = 0;
        const auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), d);
        if (ec == std::errc::invalid_argument || ptr != tok.data() + tok.size()) {
          fail(ErrorCode::kParse,
               std::string("malformed number '") + shown(tok) + "' in " + what + " " + std::to_string(index));
        }
      } else {
        (void)raw(type_size(p.type), what, index);
      }
    }
  }

  std::uint64_t length(PlyType t, const char* what, std::uint64_t index) {
    const std::int64_t n = integer(t, what, index);
    // Every entry takes at least one byte, so a longer list cannot be in the file.
    if (n < 0 || static_cast<std::uint64_t>(n) > static_cast<std::uint64_t>(end_ - p_)) {
      fail(ErrorCode::kParse,
           "invalid list length " + std::to_string(n) + " in " + what + " " + std::to_string(index));
    }
    return static_cast<std::uint64_t>(n);
  }

 private:
  std::uint64_t raw(int size, const char* what, std::uint64_t index) {
    if (end_ - p_ < size) {
      fail(ErrorCode::kParse,
           std::string("file ends inside ") + what + " " + std::to_string(index) + " (truncated)");
    }
    std::uint64_t v = 0;
    for (int i = 0; i < size; ++i) {
      const std::uint64_t byte = static_cast<unsigned char>(p_[i]);
      v |= format_ == PlyHeader::Format::kLittle ? byte << (8 * i) : byte << (8 * (size - 1 - i));
    }
    p_ += size;
    return v;
  }
  void skip_spaces() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r')) ++p_;
  }
  void skip_blank_lines() {
    for (;;) {
      skip_spaces();
      if (p_ < end_ && *p_ == '\n') {
        ++p_;
        ++line_;
        continue;
      }
      return;
    }
  }
  std::string_view token() const {
    const char* e = p_;
    while (e < end_ && *e != ' ' && *e != '\t' && *e != '\r' && *e != '\n') ++e;
    return {p_, static_cast<std::size_t>(e - p_)};
  }
  // Next ASCII value on the current element's line.
  std::string_view next_token(const char* what, std::uint64_t index) {
    skip_spaces();
    if (p_ == end_ || *p_ == '\n') {
      fail(ErrorCode::kParse, std::string(p_ == end_ ? "file ends inside " : "too few values in ") + what +
                                  " " + std::to_string(index) + (p_ == end_ ? " (truncated)" : ""));
    }
    std::string_view tok = token();
    p_ += tok.size();
    // from_chars refuses a leading '+', which some writers emit (OBJ and OFF accept it too); "+-1" stays
    // malformed.
    if (tok.size() > 1 && tok[0] == '+' && tok[1] != '-' && tok[1] != '+') tok.remove_prefix(1);
    return tok;
  }

  PlyHeader::Format format_;
  const char* begin_;
  const char* p_;
  const char* end_;
  std::uint64_t line_;
  const std::string& path_;
};

// The vertex and face properties' places in a Mesh (exact reading), in header order.
struct PlyTargets {
  std::vector<PlyField> vertex, face;
  std::uint8_t color_components = 0, face_color_components = 0;
  bool normals = false, texcoords = false;
};

ScalarType scalar_type(PlyType t) { return static_cast<ScalarType>(static_cast<int>(t) - 1); }

PlyTargets ply_targets(const PlyLayout& l) {
  PlyTargets t;
  const auto scalar = [](const PlyElement& e, std::string_view name) {
    const int i = e.find(name);
    return i >= 0 && !e.properties[i].list() ? i : -1;
  };
  // Role of each property index, or -1 for a PLY property of its own.
  const auto roles = [&](const PlyElement& e, bool vertex) {
    std::vector<std::pair<PlyRole, int>> role(e.properties.size(), {PlyRole::kProperty, -1});
    const auto group = [&](PlyRole r, std::initializer_list<std::string_view> names, bool& found) {
      std::vector<int> at;
      for (const std::string_view n : names) at.push_back(scalar(e, n));
      if (std::find(at.begin(), at.end(), -1) != at.end()) return;
      for (std::size_t c = 0; c < at.size(); ++c) role[at[c]] = {r, static_cast<int>(c)};
      found = true;
    };
    bool unused = false, colors = false;
    if (vertex) {
      for (std::size_t c = 0; c < 3; ++c)
        role[std::array<int, 3>{l.x, l.y, l.z}[c]] = {PlyRole::kPosition, static_cast<int>(c)};
      group(PlyRole::kNormal, {"nx", "ny", "nz"}, t.normals);
      for (const auto& pair : {std::pair<std::string_view, std::string_view>{"u", "v"},
                               {"s", "t"},
                               {"texture_u", "texture_v"},
                               {"texture_s", "texture_t"}}) {
        if (!t.texcoords) group(PlyRole::kTexcoord, {pair.first, pair.second}, t.texcoords);
      }
    } else {
      role[l.indices] = {PlyRole::kVertexIndices, 0};
    }
    group(PlyRole::kColor, {"red", "green", "blue"}, colors);
    std::uint8_t components = 0;
    if (colors) {
      components = 3;
      const int alpha = scalar(e, "alpha");
      if (alpha >= 0) {
        role[alpha] = {PlyRole::kColor, 3};
        components = 4;
      }
    }
    (vertex ? t.color_components : t.face_color_components) = components;
    (void)unused;
    return role;
  };
  const auto fields = [&](const PlyElement& e, bool vertex, std::vector<PlyField>& out) {
    const auto role = roles(e, vertex);
    std::uint32_t property = 0;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const PlyProperty& p = e.properties[i];
      PlyField f;
      f.role = role[i].first;
      f.index = f.role == PlyRole::kProperty ? property++ : static_cast<std::uint32_t>(role[i].second);
      f.name = p.name;
      f.type = scalar_type(p.type);
      if (p.list()) f.count_type = scalar_type(p.count_type);
      out.push_back(std::move(f));
    }
  };
  fields(*l.vertex, true, t.vertex);
  if (l.face) fields(*l.face, false, t.face);
  return t;
}

// What the QuadMesh reading drops, counted by the roles the exact reading gives the properties, so both
// file them under the same --drop category.
void count_extras(const PlyTargets& t, const PlyLayout& l, const PlyHeader& h, ReadReport& r) {
  const auto has = [](const std::vector<PlyField>& fields, PlyRole role) {
    return std::any_of(fields.begin(), fields.end(), [role](const PlyField& f) { return f.role == role; });
  };
  const std::uint64_t vertices = l.vertex->count, faces = l.face ? l.face->count : 0;
  if (has(t.vertex, PlyRole::kNormal)) r.normals += vertices;
  if (has(t.vertex, PlyRole::kTexcoord)) r.texcoords += vertices;
  if (has(t.vertex, PlyRole::kColor)) r.vertex_colors += vertices;
  if (has(t.vertex, PlyRole::kProperty)) r.other_properties += vertices;
  if (has(t.face, PlyRole::kColor)) r.face_colors += faces;
  if (has(t.face, PlyRole::kProperty)) r.other_properties += faces;
  r.obj_info += h.obj_info.size();
}

// Index of the first repeated vertex pair of a face, or false.
bool repeats(const std::vector<std::uint32_t>& c, std::vector<std::uint32_t>& scratch,
             std::uint32_t& vertex) {
  if (c.size() <= 16) {
    for (std::size_t a = 0; a < c.size(); ++a) {
      for (std::size_t b = a + 1; b < c.size(); ++b) {
        if (c[a] == c[b]) {
          vertex = c[a];
          return true;
        }
      }
    }
    return false;
  }
  scratch = c;
  std::sort(scratch.begin(), scratch.end());
  const auto d = std::adjacent_find(scratch.begin(), scratch.end());
  if (d == scratch.end()) return false;
  vertex = *d;
  return true;
}

// Both readings: exact (a Mesh with every property) or quads (float32 positions, quads counted and
// refused as before).
template <bool kExact>
Mesh read_ply_impl(std::string_view bytes, const std::string& path, ReadReport& r) {
  r = ReadReport{};
  const PlyHeader header = parse_header(bytes, path);
  const PlyLayout layout = check_header(header, bytes, path);

  Mesh mesh;
  const PlyTargets targets = ply_targets(layout);
  count_extras(targets, layout, header, r);
  r.leading_comments = header.comments;  // PLY's comments are its header's: the leading block
  r.comments = header.comments.size();
  if constexpr (kExact) {
    mesh.comments = header.comments;
    mesh.ply.obj_info = header.obj_info;
    mesh.ply.format = header.format == PlyHeader::Format::kAscii    ? PlyFormat::kAscii
                      : header.format == PlyHeader::Format::kLittle ? PlyFormat::kBinaryLittleEndian
                                                                    : PlyFormat::kBinaryBigEndian;
    mesh.ply.faces_first = layout.face && layout.face < layout.vertex;
    mesh.ply.vertex = targets.vertex;
    mesh.ply.face = targets.face;
    mesh.vertex_color_components = targets.color_components;
    mesh.face_color_components = targets.face_color_components;
    mesh.face_offsets.push_back(0);
    for (const auto& [fields, element, props] :
         {std::tuple{&targets.vertex, layout.vertex, &mesh.vertex_properties},
          std::tuple{&targets.face, layout.face, &mesh.face_properties}}) {
      for (std::size_t k = 0; k < fields->size(); ++k) {
        const PlyField& f = (*fields)[k];
        if (f.role != PlyRole::kProperty) continue;
        Property p;
        p.name = f.name;
        p.type = f.type;
        p.list = element->properties[k].list();
        p.count_type = f.count_type;
        if (p.list) p.offsets.push_back(0);
        props->push_back(std::move(p));
      }
    }
  }
  PlyData in(header, bytes, path);
  detail::NonQuads non_quads;  // at face indices; the first one's line for the message
  std::uint64_t first_non_quad_line = 0;
  std::vector<PlyValue> values;
  std::vector<std::uint32_t> corners, scratch;
  for (const auto& e : header.elements) {
    const bool is_vertex = &e == layout.vertex, is_face = &e == layout.face;
    const char* what = is_vertex ? "vertex" : is_face ? "face" : "element";
    const std::vector<PlyField>* fields = is_vertex ? &targets.vertex : is_face ? &targets.face : nullptr;
    if (is_vertex) {
      if constexpr (kExact) {
        mesh.positions.f32.reserve(3 * e.count);
      } else {
        mesh.positions.f32.resize(3 * e.count);
      }
    }
    if (is_face) {
      mesh.corner_vertices.reserve(4 * e.count);
      if (in.ascii()) r.face_line.reserve(e.count);
    }
    values.resize(e.properties.size());
    for (std::uint64_t i = 0; i < e.count; ++i) {
      in.begin_element();
      const std::uint64_t line = in.line();
      for (int k = 0; k < static_cast<int>(e.properties.size()); ++k) {
        const PlyProperty& p = e.properties[k];
        if (is_face && k == layout.indices) {
          const std::uint64_t n = in.length(p.count_type, what, i);
          corners.clear();
          for (std::uint64_t c = 0; c < n; ++c) {
            const std::int64_t v = in.integer(p.type, what, i);
            if (v < 0 || static_cast<std::uint64_t>(v) >= layout.vertex->count) {
              in.fail(ErrorCode::kBadIndex, "face " + std::to_string(i) + " refers to vertex " +
                                                std::to_string(v) + " (the file has " +
                                                std::to_string(layout.vertex->count) +
                                                " vertices, numbered from 0)");
            }
            if (kExact || c < 4) corners.push_back(static_cast<std::uint32_t>(v));
          }
          if (!kExact && n != 4) {
            if (non_quads.count == 0) first_non_quad_line = line;
            non_quads.add(i, n);
            continue;
          }
          if (n < 3) {
            in.fail(ErrorCode::kDegenerateFace, "face " + std::to_string(i) + " has " + std::to_string(n) +
                                                    (n == 1 ? " vertex" : " vertices") +
                                                    "; a face needs at least 3 distinct vertices");
          }
          std::uint32_t repeated = 0;
          if (repeats(corners, scratch, repeated)) {
            in.fail(ErrorCode::kDegenerateFace,
                    "face " + std::to_string(i) + " repeats vertex " + std::to_string(repeated) +
                        (n == 4 ? "; a quad needs 4 distinct vertices" : "; a face needs distinct vertices"));
          }
          if (mesh.corner_vertices.size() + n > 0xFFFFFFFEu)
            in.fail(ErrorCode::kLimit, "more than 2^32 - 2 face corners");
          mesh.corner_vertices.insert(mesh.corner_vertices.end(), corners.begin(), corners.end());
          if constexpr (kExact)
            mesh.face_offsets.push_back(static_cast<std::uint32_t>(mesh.corner_vertices.size()));
          if (in.ascii())
            r.face_line.push_back(static_cast<std::uint32_t>(std::min<std::uint64_t>(line, 0xFFFFFFFFu)));
        } else if (!kExact && is_vertex && (k == layout.x || k == layout.y || k == layout.z)) {
          mesh.positions.f32[3 * i + (k == layout.x   ? 0
                                      : k == layout.y ? 1
                                                      : 2)] = in.coordinate(p.type, what, i, r);
        } else if (kExact && fields && p.list()) {  // a list property of its own
          Property& prop = (is_vertex ? mesh.vertex_properties : mesh.face_properties)[(*fields)[k].index];
          const std::uint64_t n = in.length(p.count_type, what, i);
          for (std::uint64_t c = 0; c < n; ++c) in.value(p.type, what, i).push(prop.values);
          if (prop.values.size() > 0xFFFFFFFEu) in.fail(ErrorCode::kLimit, "more than 2^32 - 2 list values");
          prop.offsets.push_back(static_cast<std::uint32_t>(prop.values.size()));
        } else if (kExact && fields) {
          values[k] = in.value(p.type, what, i);
          const PlyField& f = (*fields)[k];
          if (f.role != PlyRole::kProperty && !values[k].finite()) {
            in.fail(ErrorCode::kBadNumber, std::string(what) + " " + std::to_string(i) +
                                               " has a non-finite '" + shown(p.name) +
                                               "' (NaN and infinity are not valid mesh data)");
          }
        } else {
          in.skip(p, what, i);
        }
      }
      in.end_element(what, i);
      if constexpr (kExact) {
        if (!fields) continue;
        // The scalar values to their arrays, components in order whatever the header's order.
        for (int round = 0; round < 4; ++round) {
          for (std::size_t k = 0; k < fields->size(); ++k) {
            const PlyField& f = (*fields)[k];
            if (e.properties[k].list() || f.role == PlyRole::kVertexIndices) continue;
            if (f.role == PlyRole::kProperty) {
              if (round == 0)
                values[k].push((is_vertex ? mesh.vertex_properties : mesh.face_properties)[f.index].values);
              continue;
            }
            if (f.index != static_cast<std::uint32_t>(round)) continue;
            Numbers& to = f.role == PlyRole::kPosition   ? mesh.positions
                          : f.role == PlyRole::kNormal   ? mesh.normals
                          : f.role == PlyRole::kTexcoord ? mesh.texcoords
                          : is_vertex                    ? mesh.vertex_colors
                                                         : mesh.face_colors;
            values[k].push(to);
          }
        }
      }
    }
  }
  in.finish();
  non_quads.throw_if_any(in.ascii() ? path + ":" + std::to_string(first_non_quad_line) + ": " : path + ": ",
                         "face");
  const std::size_t faces = kExact ? mesh.face_count() : mesh.corner_vertices.size() / 4;
  if (!in.ascii()) r.face_line.assign(faces, 0);  // binary faces have no line
  if constexpr (kExact) {
    if (targets.normals) mesh.corner_normals = mesh.corner_vertices;
    if (targets.texcoords) mesh.corner_texcoords = mesh.corner_vertices;
  }
  return mesh;
}

}  // namespace

QuadMesh read_ply_file(const std::string& path, ReadReport* report) {
  return read_ply(read_file_bytes(path), path, report);
}

QuadMesh read_ply(std::string_view bytes, const std::string& path, ReadReport* report) {
  ReadReport local;
  Mesh m = read_ply_impl<false>(bytes, path, report ? *report : local);
  QuadMesh q;
  q.positions = std::move(m.positions.f32);
  q.quads = std::move(m.corner_vertices);
  return q;
}

Mesh read_ply_mesh(std::string_view bytes, const std::string& path, ReadNotes* notes) {
  ReadReport r;
  Mesh m = read_ply_impl<true>(bytes, path, r);
  if (notes) {
    *notes = ReadNotes{};
    notes->face_line = std::move(r.face_line);
  }
  return m;
}

}  // namespace qsp
