// OBJ and OFF readers: strict single-pass parsers over an in-memory buffer. No iostreams, no
// per-line allocation; numbers go through std::from_chars so floats round exactly as it rounds.
#include "io_text.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {

// Printable, bounded rendering of untrusted text for messages.
std::string quote_token(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f && c != '\'') {
      out += static_cast<char>(c);
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  if (token.size() > kMaxShown) out += "...";
  out += "'";
  return out;
}

std::string plural(std::uint64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::string corners_name(std::uint64_t n) {
  if (n == 3) return "triangle";
  if (n == 0) return "no vertices";
  return plural(n, "vertex", "vertices");
}

// Faces that are not quads: counted all the way through so the message can say how many.
struct NonQuads {
  std::uint64_t count = 0;
  std::uint64_t line[3] = {}, corners[3] = {};  // the first ones

  void add(std::uint64_t at, std::uint64_t n) {
    if (count < 3) {
      line[count] = at;
      corners[count] = n;
    }
    ++count;
  }
  // Adds those of the text after this one's, which starts `line_offset` lines further on.
  void merge(const NonQuads& later, std::uint64_t line_offset) {
    std::uint64_t i = 0;
    for (; i < later.count && i < 3 && count < 3; ++i) add(later.line[i] + line_offset, later.corners[i]);
    count += later.count - i;
  }
  void throw_if_any(std::string_view source) const {
    if (count == 0) return;
    std::string examples;  // "line 10: triangle, line 12: 5 vertices, ..."
    for (std::uint64_t i = 0; i < count && i < 3; ++i) {
      if (i > 0) examples += ", ";
      examples += "line " + std::to_string(line[i]) + ": " + corners_name(corners[i]);
    }
    std::string msg = std::string(source) + ":" + std::to_string(line[0]) + ": ";
    if (count == 1) {
      msg += "1 face is not a quad (" + examples + ")";
    } else {
      msg += std::to_string(count) + " faces are not quads (first: " + examples + (count > 3 ? ", ..." : "") +
             ")";
    }
    msg += "; qsp stores quad meshes only and never triangulates or drops faces";
    throw Error(ErrorCode::kNotQuad, msg);
  }
};

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Cursor over the text with line tracking. Blanks are spaces, tabs, a CR before a LF and
// backslash-newline continuations; a statement ends at a line end, '#' or the end of the text. A line
// ends at LF, CRLF or a CR alone (classic Mac OS): treating a lone CR as a blank once let a comment
// swallow the statements after it.
class Scanner {
 public:
  // `file_start`: false for a later part of a split OBJ read, where a byte order mark is content.
  Scanner(std::string_view text, std::string_view source, bool file_start = true)
      : p_(text.data()), end_(text.data() + text.size()), source_(source) {
    // A UTF-8 byte order mark is not content.
    if (file_start && text.size() >= 3 && std::memcmp(p_, "\xEF\xBB\xBF", 3) == 0) p_ += 3;
  }

  const char* pos() const { return p_; }
  const char* end() const { return end_; }
  std::uint64_t line() const { return line_; }
  bool done() const { return p_ == end_; }
  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }

  void skip_blank() {
    for (;;) {
      while (p_ < end_ && blank_at(p_)) ++p_;
      if (p_ < end_ && *p_ == '\\' && continuation_at(p_)) {
        skip_continuation();
        continue;
      }
      return;
    }
  }
  // True at the end of a statement (after skip_blank).
  bool at_eol() const { return p_ == end_ || *p_ == '\n' || *p_ == '#' || lone_cr(p_); }

  // Consumes the end of a statement: optional comment, then the newline.
  void finish_line() {
    if (p_ < end_ && *p_ == '#') skip_comment();
    if (p_ < end_) {
      ++p_;  // the LF, or a lone CR
      ++line_;
    }
  }
  // Skips a comment up to its line end; a backslash does not continue a comment.
  void skip_comment() {
    // Not memchr for the LF: in a file without LFs that scans to the end for every comment.
    while (p_ < end_ && *p_ != '\n' && !lone_cr(p_)) ++p_;
  }
  // Skips the rest of a statement whose content qsp only counts (honours continuations).
  void skip_statement() {
    for (;;) {
      skip_blank();
      if (at_eol()) return;
      while (p_ < end_ && !is_blank(*p_) && *p_ != '\n' && *p_ != '\\') ++p_;
      if (p_ < end_ && *p_ == '\\' && !continuation_at(p_)) ++p_;
    }
  }
  // Next blank-delimited word (keyword); empty at the end of the statement.
  std::string_view word() {
    const char* s = p_;
    while (p_ < end_ && !is_blank(*p_) && *p_ != '\n') ++p_;
    return {s, static_cast<std::size_t>(p_ - s)};
  }
  // The token starting at `s`, for messages.
  std::string_view token_at(const char* s) const {
    const char* e = s;
    while (e < end_ && !is_blank(*e) && *e != '\n') ++e;
    return {s, static_cast<std::size_t>(e - s)};
  }
  bool token_ends_at(const char* s) const {
    return s == end_ || is_blank(*s) || *s == '\n' || (*s == '\\' && continuation_at(s));
  }

  [[noreturn]] void fail(ErrorCode code, std::uint64_t line, const std::string& what) const {
    throw Error(code, std::string(source_) + ":" + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void fail(ErrorCode code, const std::string& what) const { fail(code, line_, what); }

  // A finite float32 number token, exactly as std::from_chars rounds it.
  float number(const char* context) {
    const char* s = skip_plus();
    float value = 0.0f;
    const auto [ptr, ec] = std::from_chars(s, end_, value);
    if (ec == std::errc::invalid_argument || !token_ends_at(ptr) || (s != p_ && *s == '-')) {
      fail(ErrorCode::kParse, "malformed number " + quote_token(token_at(p_)) + " in " + context);
    }
    if (ec == std::errc::result_out_of_range) {
      fail(ErrorCode::kBadNumber, "number " + quote_token(token_at(p_)) + " in " + context +
                                      " is outside the float32 range (it does not round to a finite "
                                      "nonzero float)");
    }
    if (!std::isfinite(value)) {
      fail(ErrorCode::kBadNumber, "number " + quote_token(token_at(p_)) + " in " + context +
                                      " is not finite (NaN and infinity are not valid mesh data)");
    }
    p_ = ptr;
    return value;
  }

  // An integer token (a '/' may end it when allow_slash). Returns false on overflow
  // (the caller reports the range); throws on malformed text.
  bool integer(std::int64_t& value, const char* context, bool allow_slash) {
    const char* s = skip_plus();
    const auto [ptr, ec] = std::from_chars(s, end_, value);
    const bool ends = token_ends_at(ptr) || (allow_slash && ptr < end_ && *ptr == '/');
    if (ec == std::errc::invalid_argument || !ends || (s != p_ && *s == '-')) {
      fail(ErrorCode::kParse, "malformed integer " + quote_token(token_at(token_start_)) + " in " + context);
    }
    p_ = ptr;
    return ec != std::errc::result_out_of_range;
  }
  // Sign and magnitude of an index token. from_chars on uint32 covers every index qsp can hold
  // and is cheaper than a wide type; returns false when the magnitude does not fit.
  bool index(std::uint32_t& magnitude, bool& negative, const char* context, bool allow_slash) {
    const char* s = p_;
    negative = false;
    if (s < end_ && (*s == '-' || *s == '+')) {
      negative = *s == '-';
      ++s;
    }
    const auto [ptr, ec] = std::from_chars(s, end_, magnitude);
    const bool ends = token_ends_at(ptr) || (allow_slash && ptr < end_ && *ptr == '/');
    if (ec == std::errc::invalid_argument || !ends) {
      fail(ErrorCode::kParse, "malformed integer " + quote_token(token_at(token_start_)) + " in " + context);
    }
    p_ = ptr;
    return ec != std::errc::result_out_of_range;
  }
  void mark_token() { token_start_ = p_; }
  const char* token_start() const { return token_start_; }
  void advance() { ++p_; }
  char peek() const { return p_ < end_ ? *p_ : '\0'; }

 private:
  // from_chars refuses a leading '+', which some writers emit; a following '-' stays malformed.
  const char* skip_plus() const { return p_ + 1 < end_ && *p_ == '+' ? p_ + 1 : p_; }
  // A CR that does not start a CRLF: a line end of its own.
  bool lone_cr(const char* s) const { return *s == '\r' && (s + 1 == end_ || s[1] != '\n'); }
  // A blank that does not end the line (s < end_).
  bool blank_at(const char* s) const { return is_blank(*s) && !lone_cr(s); }
  bool continuation_at(const char* s) const {
    ++s;
    while (s < end_ && blank_at(s)) ++s;
    return s == end_ || *s == '\n' || lone_cr(s);
  }
  void skip_continuation() {
    ++p_;
    while (p_ < end_ && blank_at(p_)) ++p_;
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
  }

  const char* p_;
  const char* end_;
  const char* token_start_ = nullptr;
  std::uint64_t line_ = 1;
  std::string_view source_;
};

// push_back inlines; vector::insert of a range does not (measured ~2% on large OBJ files).
template <typename T, std::size_t N>
inline void append(std::vector<T>& v, const T (&a)[N]) {
  for (std::size_t i = 0; i < N; ++i) v.push_back(a[i]);
}

std::uint32_t clamp_line(std::uint64_t line) {
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(line, 0xFFFFFFFFu));
}

// Index of the first repeated corner pair of a quad, or -1.
int repeated_corner(const std::uint32_t* q, int* other) {
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      if (q[i] == q[j]) {
        *other = j;
        return i;
      }
    }
  }
  return -1;
}

// Numbers on the rest of a statement (validated, not kept).
std::uint64_t skip_numbers(Scanner& in, const char* context) {
  std::uint64_t n = 0;
  for (;;) {
    in.skip_blank();
    if (in.at_eol()) return n;
    (void)in.number(context);
    ++n;
  }
}

// ----------------------------------------------------------------------------------------------
// OBJ

// One part of a split OBJ read (read_obj_parts): what the merge needs besides mesh and report.
struct ObjPart {
  QuadMesh mesh;
  ReadReport report;
  std::uint64_t vertex_count = 0;
  std::uint64_t face_count = 0;
  std::uint64_t end_line = 1;  // the scanner's line at the end of the part
  std::uint32_t max_index = 0;
  NonQuads non_quads;
  // Later part only. Relative indices there count back from the part's own vertices: `missing` is
  // how far the deepest one reaches before the part, `relative` has per face (missing at the end: 0)
  // a bit per corner given relatively, whose stored index still lacks the earlier vertex count.
  std::uint64_t missing = 0;
  std::vector<std::uint8_t> relative;
  bool ok = false;  // read without error
};

class ObjReader {
 public:
  // `later_part`: the text starts mid-file at a line start (read_obj_parts), so vertices before
  // it are unknown; relative indices are recorded for the merge instead of checked.
  ObjReader(std::string_view text, std::string_view source, ReadReport& report, bool later_part = false)
      : in_(text, source, !later_part), source_(source), report_(report), later_part_(later_part) {}

  QuadMesh run() {
    parse();
    non_quads_.throw_if_any(source_);
    check_forward_indices();
    return std::move(mesh_);
  }

  // Parses a part without the checks that need the whole file (non-quads, forward indices).
  void run_part(ObjPart& part) {
    parse();
    part.mesh = std::move(mesh_);
    part.vertex_count = vertex_count_;
    part.face_count = face_count_;
    part.end_line = in_.line();
    part.max_index = max_index_;
    part.non_quads = non_quads_;
    part.missing = missing_;
    part.relative = std::move(relative_);
  }

 private:
  void parse() {
    while (!in_.done()) {
      in_.skip_blank();
      if (in_.at_eol()) {
        in_.finish_line();
        continue;
      }
      statement();
      in_.skip_blank();
      if (!in_.at_eol()) {
        in_.fail(ErrorCode::kParse, "unexpected " + quote_token(in_.token_at(in_.pos())) +
                                        " at the end of a `" + std::string(keyword_) + "` statement");
      }
      in_.finish_line();
    }
  }

  void statement() {
    const std::uint64_t line = in_.line();
    const std::string_view k = in_.word();
    keyword_ = k;
    if (k == "v") return vertex();
    if (k == "f") return face(line);
    if (k == "vt") return count_numbers(report_.texcoords, 1, 3, "`vt` statement");
    if (k == "vn") return count_numbers(report_.normals, 3, 3, "`vn` statement");
    if (k == "vp") return count_numbers(report_.parameter_vertices, 1, 3, "`vp` statement");
    if (k == "g" || k == "o") return count_statement(report_.groups);
    if (k == "s") return count_statement(report_.smoothing);
    if (k == "usemtl" || k == "mtllib" || k == "usemap" || k == "maplib")
      return count_statement(report_.materials);
    if (k == "t") return count_statement(report_.tags);  // OpenSubdiv tags: `t crease 2/1/0 1 2 4.0`
    if (k == "l" || k == "p") {
      in_.fail(ErrorCode::kUnsupported, line,
               std::string("`") + std::string(k) + "` (" + (k == "l" ? "polyline" : "point") +
                   ") elements are not supported; qsp stores quad meshes only");
    }
    static constexpr std::string_view kFreeForm[] = {
        "cstype",   "deg",      "bmat", "step",       "curv",      "curv2", "surf", "parm",
        "trim",     "hole",     "scrv", "sp",         "end",       "con",   "mg",   "bevel",
        "c_interp", "d_interp", "lod",  "shadow_obj", "trace_obj", "ctech", "stech"};
    if (std::find(std::begin(kFreeForm), std::end(kFreeForm), k) != std::end(kFreeForm)) {
      in_.fail(ErrorCode::kUnsupported, line,
               "`" + std::string(k) +
                   "` (free-form geometry or display attribute) is not supported; qsp "
                   "stores quad meshes only");
    }
    in_.fail(ErrorCode::kParse, line, "unknown statement " + quote_token(k));
  }

  void vertex() {
    float xyz[3];
    for (int i = 0; i < 3; ++i) {
      in_.skip_blank();
      if (in_.at_eol()) {
        in_.fail(ErrorCode::kParse, "`v` needs 3 coordinates, found " + std::to_string(i));
      }
      xyz[i] = in_.number("`v` statement");
    }
    if (vertex_count_ >= kMaxVertices) {
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxVertices) + " vertices");
    }
    append(mesh_.positions, xyz);
    ++vertex_count_;
    in_.skip_blank();
    if (in_.at_eol()) return;
    // Optional w, or r g b (some exporters write x y z r g b, a few x y z w r g b / r g b a).
    const std::uint64_t extra = skip_numbers(in_, "`v` statement");
    if (extra != 1 && extra != 3 && extra != 4) {
      in_.fail(ErrorCode::kParse, "`v` has " + std::to_string(3 + extra) +
                                      " numbers; expected x y z, optionally followed by w or r g b");
    }
    ++report_.vertex_colors;
  }

  void face(std::uint64_t line) {
    std::uint32_t q[4];
    std::uint64_t corners = 0;
    bool attributes = false;
    unsigned relative = 0;  // bit per corner given as a relative index
    for (;;) {
      in_.skip_blank();
      if (in_.at_eol()) break;
      in_.mark_token();
      std::uint32_t magnitude = 0;
      bool negative = false;
      const bool in_range = in_.index(magnitude, negative, "`f` statement", true);
      if (in_.peek() == '/') {  // v/vt, v//vn or v/vt/vn
        attributes = true;
        in_.advance();
        if (in_.peek() != '/') attribute_index("texture coordinate");
        if (in_.peek() == '/') {
          in_.advance();
          attribute_index("normal");
        }
        if (!in_.token_ends_at(in_.pos())) {
          in_.fail(ErrorCode::kParse,
                   "malformed vertex reference " + quote_token(in_.token_at(in_.token_start())));
        }
      }
      const std::uint32_t index = resolve(magnitude, negative, in_range);
      if (corners < 4) {
        q[corners] = index;
        relative |= static_cast<unsigned>(negative) << corners;
      }
      ++corners;
    }
    if (attributes) ++report_.face_attribute_refs;
    if (corners != 4) {
      non_quads_.add(line, corners);
      return;
    }
    // A later part cannot compare a relative corner with an absolute one before the merge does.
    const bool deferred = later_part_ && relative != 0;
    int other = 0;
    const int first = deferred ? -1 : repeated_corner(q, &other);
    if (first >= 0) {
      in_.fail(ErrorCode::kDegenerateFace, line,
               "face repeats vertex " + std::to_string(std::uint64_t{q[first]} + 1) + " (corners " +
                   std::to_string(first + 1) + " and " + std::to_string(other + 1) +
                   "); a quad needs 4 distinct vertices");
    }
    if (face_count_ >= kMaxFaces)
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxFaces) + " faces");
    if (deferred) {
      relative_.resize(face_count_, 0);
      relative_.push_back(static_cast<std::uint8_t>(relative));
    }
    ++face_count_;
    append(mesh_.quads, q);
    report_.face_line.push_back(clamp_line(line));
  }

  // vt/vn indices are checked for syntax only: qsp keeps neither.
  void attribute_index(const char* what) {
    std::uint32_t magnitude = 0;
    bool negative = false;
    if (!in_.index(magnitude, negative, "`f` statement", true) || magnitude == 0) {
      in_.fail(ErrorCode::kParse,
               std::string("invalid ") + what + " index in " + quote_token(in_.token_at(in_.token_start())));
    }
  }

  // OBJ index (1-based, or negative = relative to the vertices so far) to 0-based. Positive
  // indices may refer to vertices defined later; they are range-checked at the end.
  std::uint32_t resolve(std::uint32_t magnitude, bool negative, bool in_range) {
    const auto token = [&] { return quote_token(in_.token_at(in_.token_start())); };
    if (magnitude == 0 && in_range) {
      in_.fail(ErrorCode::kBadIndex, "vertex index 0 in " + token() + " is invalid (OBJ indices start at 1)");
    }
    if (negative) {
      if (!in_range || (magnitude > vertex_count_ && !later_part_)) {
        in_.fail(ErrorCode::kBadIndex, "vertex index " + token() + " is out of range (" +
                                           plural(vertex_count_, "vertex", "vertices") +
                                           " defined before this line)");
      }
      // In a later part this may wrap; the merge adds the vertices before the part.
      if (magnitude > vertex_count_) missing_ = std::max(missing_, magnitude - vertex_count_);
      return static_cast<std::uint32_t>(vertex_count_ - magnitude);
    }
    if (!in_range || magnitude > kMaxVertices) {
      in_.fail(ErrorCode::kBadIndex, "vertex index " + token() + " is out of range (beyond qsp's limit of " +
                                         std::to_string(kMaxVertices) + " vertices)");
    }
    const std::uint32_t index = magnitude - 1;
    max_index_ = std::max(max_index_, index);
    return index;
  }

  void check_forward_indices() {
    if (face_count_ == 0 || max_index_ < vertex_count_) return;
    for (std::size_t f = 0; f < face_count_; ++f) {
      for (int i = 0; i < 4; ++i) {
        const std::uint32_t index = mesh_.quads[4 * f + i];
        if (index >= vertex_count_) {
          in_.fail(ErrorCode::kBadIndex, report_.face_line[f],
                   "vertex index " + std::to_string(std::uint64_t{index} + 1) +
                       " is out of range (the file has " + plural(vertex_count_, "vertex", "vertices") + ")");
        }
      }
    }
  }

  void count_numbers(std::uint64_t& counter, std::uint64_t min, std::uint64_t max, const char* context) {
    const std::uint64_t n = skip_numbers(in_, context);
    if (n < min || n > max) {
      std::string want =
          min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max);
      in_.fail(ErrorCode::kParse,
               std::string(context) + " has " + std::to_string(n) + " numbers, expected " + want);
    }
    ++counter;
  }
  void count_statement(std::uint64_t& counter) {
    in_.skip_statement();
    ++counter;
  }

  Scanner in_;
  std::string_view source_;
  ReadReport& report_;
  QuadMesh mesh_;
  std::string_view keyword_;
  std::uint64_t vertex_count_ = 0;
  std::uint64_t face_count_ = 0;
  std::uint32_t max_index_ = 0;
  NonQuads non_quads_;
  const bool later_part_;
  std::uint64_t missing_ = 0;
  std::vector<std::uint8_t> relative_;
};

// Adds a part's counters; face lines are merged separately.
void add_counts(ReadReport& to, const ReadReport& from) {
  // A new ReadReport member must be merged here too.
  static_assert(sizeof(ReadReport) == 11 * sizeof(std::uint64_t) + sizeof(std::vector<std::uint32_t>));
  to.texcoords += from.texcoords;
  to.normals += from.normals;
  to.face_attribute_refs += from.face_attribute_refs;
  to.groups += from.groups;
  to.materials += from.materials;
  to.smoothing += from.smoothing;
  to.tags += from.tags;
  to.vertex_colors += from.vertex_colors;
  to.face_colors += from.face_colors;
  to.parameter_vertices += from.parameter_vertices;
  to.other_properties += from.other_properties;
}

// Appends `from` and frees it at once.
template <typename T>
void append_and_free(std::vector<T>& to, std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
  std::vector<T>().swap(from);
}

// Reads the parts between `splits` on this thread and one more, each taking the next unread part,
// and merges them in file order. Several parts rather than two halves: when the other core is busy,
// this thread reads most parts itself instead of waiting for half the file. Throws the sequential
// read's error for non-quads (the common refusal: triangle meshes). nullopt when a part fails or the
// merge finds another problem only the whole file shows (a relative index reaching too far back, a
// repeated vertex, limits, forward indices out of range): the caller re-reads sequentially, which
// throws the error that comes first in the file, with its message.
std::optional<QuadMesh> read_obj_parts(std::string_view text, std::string_view source,
                                       std::span<const std::size_t> splits, ReadReport& report) {
  const std::size_t n = splits.size() + 1;
  std::vector<ObjPart> parts(n);
  std::atomic<std::size_t> next{0};
  const auto work = [&]() noexcept {
    for (std::size_t i; (i = next.fetch_add(1)) < n;) {
      const std::size_t begin = i == 0 ? 0 : splits[i - 1];
      const std::size_t end = i + 1 == n ? text.size() : splits[i];
      try {
        ObjReader(text.substr(begin, end - begin), source, parts[i].report, i != 0).run_part(parts[i]);
        parts[i].ok = true;
      } catch (...) {  // the sequential read decides; no need to read further
        next = n;
      }
    }
  };
  std::thread worker;
  try {
    worker = std::thread(work);
  } catch (const std::system_error&) {
    return std::nullopt;  // no thread to be had: read sequentially
  }
  work();
  worker.join();

  std::uint64_t vertex_count = 0, face_count = 0, line = 1;  // before the current part
  std::uint32_t max_index = 0;
  NonQuads non_quads;
  for (ObjPart& part : parts) {
    if (!part.ok || part.missing > vertex_count) return std::nullopt;
    // Relative corners: add the earlier vertices (modulo 2^32, undoing any wrap).
    const auto base = static_cast<std::uint32_t>(vertex_count);
    for (std::size_t f = 0; f < part.relative.size(); ++f) {
      if (part.relative[f] == 0) continue;
      std::uint32_t* q = &part.mesh.quads[4 * f];
      for (int i = 0; i < 4; ++i) {
        if (part.relative[f] >> i & 1) q[i] += base;
      }
      int other = 0;
      if (repeated_corner(q, &other) >= 0) return std::nullopt;
    }
    if (line != 1) {
      for (std::uint32_t& l : part.report.face_line) l = clamp_line(l + line - 1);
    }
    non_quads.merge(part.non_quads, line - 1);
    vertex_count += part.vertex_count;
    face_count += part.face_count;
    line += part.end_line - 1;
    max_index = std::max(max_index, part.max_index);
  }
  if (vertex_count > kMaxVertices || face_count > kMaxFaces) return std::nullopt;

  // One array at a time, each part's freed as it is copied: the parts and one merged array at most
  // (reserving all three first held 45 MB more than the sequential read on a 99 MB file).
  const auto merge = [&](auto array, std::uint64_t size) {
    auto& to = array(parts[0]);
    to.reserve(size);
    for (std::size_t i = 1; i < n; ++i) append_and_free(to, array(parts[i]));
  };
  merge([](ObjPart& p) -> std::vector<float>& { return p.mesh.positions; }, 3 * vertex_count);
  merge([](ObjPart& p) -> std::vector<std::uint32_t>& { return p.mesh.quads; }, 4 * face_count);
  merge([](ObjPart& p) -> std::vector<std::uint32_t>& { return p.report.face_line; }, face_count);
  QuadMesh& mesh = parts[0].mesh;
  ReadReport& first = parts[0].report;
  for (std::size_t i = 1; i < n; ++i) add_counts(first, parts[i].report);
  report = std::move(first);
  // Nothing above failed, so the sequential read would reach its end and refuse non-quads there,
  // with the report complete.
  non_quads.throw_if_any(source);
  if (face_count != 0 && max_index >= vertex_count) return std::nullopt;
  return std::move(mesh);
}

// ----------------------------------------------------------------------------------------------
// OFF

class OffReader {
 public:
  OffReader(std::string_view text, std::string_view source, ReadReport& report)
      : in_(text, source), source_(source), report_(report) {}

  QuadMesh run() {
    header();
    vertices();
    faces();
    // Only blanks and comments may follow the last face.
    skip_empty();
    if (!in_.done()) {
      in_.fail(ErrorCode::kParse, "unexpected " + quote_token(in_.token_at(in_.pos())) +
                                      " after the last face (the "
                                      "header declares " +
                                      plural(face_count_, "face", "faces") + ")");
    }
    non_quads_.throw_if_any(source_);
    return std::move(mesh_);
  }

 private:
  // Skips blank lines and comment lines (and blanks at the current position).
  void skip_empty() {
    for (;;) {
      in_.skip_blank();
      if (in_.done() || !in_.at_eol()) return;
      in_.finish_line();
    }
  }

  void expect_eol(const char* what) {
    in_.skip_blank();
    if (!in_.at_eol()) {
      in_.fail(ErrorCode::kParse, "unexpected " + quote_token(in_.token_at(in_.pos())) + " after " + what);
    }
    in_.finish_line();
  }

  std::uint64_t count(const char* what) {
    in_.skip_blank();
    if (in_.at_eol()) in_.fail(ErrorCode::kParse, std::string("OFF counts line is missing the ") + what);
    in_.mark_token();
    std::int64_t v = 0;
    const bool ok = in_.integer(v, "the OFF counts line", false);
    if (v < 0) in_.fail(ErrorCode::kParse, std::string("negative ") + what + " in the OFF counts line");
    if (!ok)
      in_.fail(ErrorCode::kLimit, std::string(what) + " " + quote_token(in_.token_at(in_.token_start())) +
                                      " is beyond qsp's limits");
    return static_cast<std::uint64_t>(v);
  }

  void header() {
    skip_empty();
    if (in_.done()) in_.fail(ErrorCode::kParse, "empty file (expected an OFF header)");
    const std::uint64_t header_line = in_.line();
    std::string_view key = in_.word();
    std::string_view k = key;
    if (k.size() >= 2 && k.substr(0, 2) == "ST") has_texcoords_ = true, k.remove_prefix(2);
    if (!k.empty() && k[0] == 'C') has_colors_ = true, k.remove_prefix(1);
    if (!k.empty() && k[0] == 'N') has_normals_ = true, k.remove_prefix(1);
    if (k == "4OFF" || k == "nOFF" || k == "4nOFF") {
      in_.fail(ErrorCode::kUnsupported,
               "OFF variant " + quote_token(key) + " (homogeneous or n-dimensional) is not supported");
    }
    if (k != "OFF") {
      in_.fail(ErrorCode::kParse, header_line,
               "expected an OFF header (OFF, COFF, NOFF, STOFF, ...), found " + quote_token(key));
    }
    in_.skip_blank();
    if (!in_.at_eol()) {
      if (in_.token_at(in_.pos()) == "BINARY") {
        in_.fail(ErrorCode::kUnsupported, "binary OFF is not supported");
      }
      // Some writers put the counts on the header line.
    } else {
      in_.finish_line();
      skip_empty();
      if (in_.done()) in_.fail(ErrorCode::kParse, "file ends before the OFF counts line");
    }
    counts_line_ = in_.line();
    vertex_count_ = count("vertex count");
    face_count_ = count("face count");
    in_.skip_blank();
    if (!in_.at_eol()) (void)count("edge count");  // often 0 or wrong; not checked
    expect_eol("the OFF counts (vertices faces edges)");

    // Refuse counts the text cannot hold before allocating anything for them.
    if (vertex_count_ > kMaxVertices) {
      in_.fail(ErrorCode::kLimit, counts_line_,
               "header declares " + std::to_string(vertex_count_) + " vertices; qsp's limit is " +
                   std::to_string(kMaxVertices));
    }
    if (face_count_ > kMaxFaces) {
      in_.fail(ErrorCode::kLimit, counts_line_,
               "header declares " + std::to_string(face_count_) + " faces; qsp's limit is " +
                   std::to_string(kMaxFaces));
    }
    // Smallest possible entries: "0 0 0\n" per vertex, "0\n" per face; the last needs no newline.
    const std::uint64_t need = std::max<std::uint64_t>(6 * vertex_count_ + 2 * face_count_, 1) - 1;
    if (need > in_.remaining()) {
      in_.fail(ErrorCode::kParse, counts_line_,
               "header declares " + plural(vertex_count_, "vertex", "vertices") + " and " +
                   plural(face_count_, "face", "faces") + " but only " + std::to_string(in_.remaining()) +
                   " bytes follow (truncated file or wrong counts)");
    }
    mesh_.positions.reserve(3 * vertex_count_);
    mesh_.quads.reserve(4 * face_count_);
    report_.face_line.reserve(face_count_);
  }

  std::string counts_hint() const {
    return "; does the header (line " + std::to_string(counts_line_) + ": " +
           plural(vertex_count_, "vertex", "vertices") + ", " + plural(face_count_, "face", "faces") +
           ") match the file?";
  }

  // One vertex per line: x y z [normal] [colour] [texture coordinates].
  void vertices() {
    const std::uint64_t base = 3 + (has_normals_ ? 3 : 0) + (has_colors_ ? 3 : 0) + (has_texcoords_ ? 2 : 0);
    const std::uint64_t most = base + (has_colors_ ? 1 : 0);  // RGB or RGBA
    for (std::uint64_t v = 0; v < vertex_count_; ++v) {
      skip_empty();
      if (in_.done()) {
        in_.fail(ErrorCode::kParse, "file ends after " + std::to_string(v) + " of " +
                                        plural(vertex_count_, "vertex", "vertices") + " (truncated)" +
                                        counts_hint());
      }
      float xyz[3];
      std::uint64_t n = 0;
      for (; n < 3; ++n) {
        in_.skip_blank();
        if (in_.at_eol()) break;
        xyz[n] = in_.number("an OFF vertex");
      }
      if (n == 3) n += skip_numbers(in_, "an OFF vertex");
      if (n < base || n > most) {
        const std::string want =
            base == most ? std::to_string(base) : std::to_string(base) + " or " + std::to_string(most);
        in_.fail(ErrorCode::kParse, "vertex " + std::to_string(v) + " has " + plural(n, "number", "numbers") +
                                        ", expected " + want + counts_hint());
      }
      append(mesh_.positions, xyz);
      if (has_normals_) ++report_.normals;
      if (has_colors_) ++report_.vertex_colors;
      if (has_texcoords_) ++report_.texcoords;
      in_.finish_line();
    }
  }

  // Faces are token streams: "n i1 ... in [colour]", possibly over several lines; a colour is what
  // remains on the line of the last index.
  void faces() {
    for (std::uint64_t f = 0; f < face_count_; ++f) {
      skip_empty();
      if (in_.done()) {
        in_.fail(ErrorCode::kParse, "file ends after " + std::to_string(f) + " of " +
                                        plural(face_count_, "face", "faces") + " (truncated)" +
                                        counts_hint());
      }
      const std::uint64_t line = in_.line();
      in_.mark_token();
      std::int64_t n = 0;
      const char* start = in_.pos();
      const std::string_view first = in_.token_at(start);
      if (first.find_first_of(".eE") != std::string_view::npos) {
        in_.fail(ErrorCode::kParse,
                 "expected a face (vertex count, then indices), found " + quote_token(first) + counts_hint());
      }
      if (!in_.integer(n, "an OFF face", false) || n < 0 || static_cast<std::uint64_t>(n) > in_.remaining()) {
        in_.fail(ErrorCode::kParse,
                 "face vertex count " + quote_token(first) + " is invalid" + counts_hint());
      }
      std::uint32_t q[4];
      for (std::int64_t i = 0; i < n; ++i) {
        skip_empty();
        if (in_.done()) {
          in_.fail(ErrorCode::kParse, line,
                   "file ends inside face " + std::to_string(f) + " (" + std::to_string(i) + " of " +
                       std::to_string(n) + " indices)");
        }
        in_.mark_token();
        std::uint32_t index = 0;
        bool negative = false;
        const bool ok = in_.index(index, negative, "an OFF face", false);
        if (!ok || (negative && index != 0) || index >= vertex_count_) {
          in_.fail(ErrorCode::kBadIndex, "vertex index " + quote_token(in_.token_at(in_.token_start())) +
                                             " is out of range (the file has " +
                                             plural(vertex_count_, "vertex", "vertices") +
                                             ", numbered from 0)");
        }
        if (i < 4) q[i] = index;
      }
      in_.skip_blank();
      if (!in_.at_eol()) {
        const std::uint64_t c = skip_numbers(in_, "an OFF face colour");
        if (c != 1 && c != 3 && c != 4) {
          in_.fail(ErrorCode::kParse, "face " + std::to_string(f) + " has " + plural(c, "number", "numbers") +
                                          " after its indices; expected a colour (1, 3 or 4 numbers)" +
                                          counts_hint());
        }
        ++report_.face_colors;
      }
      in_.finish_line();
      if (n != 4) {
        non_quads_.add(line, static_cast<std::uint64_t>(n));
        continue;
      }
      int other = 0;
      const int dup = repeated_corner(q, &other);
      if (dup >= 0) {
        in_.fail(ErrorCode::kDegenerateFace, line,
                 "face repeats vertex " + std::to_string(q[dup]) + " (corners " + std::to_string(dup + 1) +
                     " and " + std::to_string(other + 1) + "); a quad needs 4 distinct vertices");
      }
      append(mesh_.quads, q);
      report_.face_line.push_back(clamp_line(line));
    }
  }

 private:
  Scanner in_;
  std::string_view source_;
  ReadReport& report_;
  QuadMesh mesh_;
  NonQuads non_quads_;
  bool has_normals_ = false, has_colors_ = false, has_texcoords_ = false;
  std::uint64_t vertex_count_ = 0, face_count_ = 0, counts_line_ = 0;
};

}  // namespace

namespace detail {

std::size_t obj_split_point(std::string_view text, std::size_t from) {
  for (std::size_t i = text.find('\n', from); i != std::string_view::npos; i = text.find('\n', i + 1)) {
    if (i + 1 == text.size()) break;  // nothing after it
    // A backslash then blanks before the LF: a continuation (or a comment's backslash; skipping
    // that split point too is merely cautious).
    std::size_t j = i;
    while (j > 0 && (text[j - 1] == ' ' || text[j - 1] == '\t' || text[j - 1] == '\r')) --j;
    if (j == 0 || text[j - 1] != '\\') return i + 1;
  }
  return std::string_view::npos;
}

std::vector<std::size_t> obj_read_splits(std::string_view text) {
  std::vector<std::size_t> splits;
  if (text.size() < kParallelObjBytes) return splits;
  for (std::size_t i = 1; i < kParallelObjParts; ++i) {
    const std::size_t split = obj_split_point(
        text, std::max(i * (text.size() / kParallelObjParts), splits.empty() ? 0 : splits.back()));
    if (split == std::string_view::npos) break;
    splits.push_back(split);
  }
  return splits;
}

QuadMesh read_obj_split(std::string_view text, std::string_view source, ReadReport* report,
                        std::span<const std::size_t> splits, bool* parallel) {
  ReadReport local;
  ReadReport& r = report ? *report : local;
  std::size_t previous = 0;
  bool valid = !splits.empty();
  for (const std::size_t split : splits) {
    valid = valid && split > previous && obj_split_point(text, split - 1) == split;
    previous = split;
  }
  if (parallel) *parallel = valid;  // also when read_obj_parts throws
  if (valid) {
    if (std::optional<QuadMesh> mesh = read_obj_parts(text, source, splits, r)) return std::move(*mesh);
    if (parallel) *parallel = false;
  }
  r = ReadReport{};
  return ObjReader(text, source, r).run();
}

}  // namespace detail

QuadMesh read_obj(std::string_view text, std::string_view source, ReadReport* report) {
  std::vector<std::size_t> splits = detail::obj_read_splits(text);
  // On one core a second thread only costs.
  if (!splits.empty() && std::thread::hardware_concurrency() == 1) splits.clear();
  return detail::read_obj_split(text, source, report, splits, nullptr);
}

QuadMesh read_off(std::string_view text, std::string_view source, ReadReport* report) {
  ReadReport local;
  ReadReport& r = report ? *report : local;
  r = ReadReport{};
  return OffReader(text, source, r).run();
}

}  // namespace qsp
