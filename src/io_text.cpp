// OBJ and OFF readers: strict single-pass parsers over an in-memory buffer. No iostreams, no
// per-line allocation; numbers are split into digits and exponent once (io_numbers.h) and round
// exactly as std::from_chars rounds them. Each reader has two modes, one parser: exact (a Mesh with
// everything the file carries) and quads (the QuadMesh readers: float32 positions, quads only,
// everything else counted, and the refusals they always had).
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
#include <unordered_map>
#include <vector>

#include "beside.h"
#include "io_numbers.h"
#include "non_quads.h"
#include "plural.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/polymesh.h"

namespace qsp {
namespace {

using detail::corners_name;
using detail::NonQuads;
using detail::NumberStatus;
using detail::plural;
using detail::TextNumber;

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

  [[gnu::always_inline]] void skip_blank() {
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
  [[gnu::always_inline]] bool at_eol() const {
    return p_ == end_ || *p_ == '\n' || *p_ == '#' || lone_cr(p_);
  }

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
  // At a '#': the comment's text after it, without the line end (CR of a CRLF included).
  std::string_view comment_text() const {
    const char* e = p_;
    while (e < end_ && *e != '\n' && !lone_cr(e)) ++e;
    const char* s = p_ + 1;
    if (e > s && e < end_ && e[-1] == '\r') --e;
    return {s, static_cast<std::size_t>(std::max(e, s) - s)};
  }
  // Skips the rest of a statement whose content qsp only counts or keeps as text (honours
  // continuations).
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
  [[gnu::always_inline]] bool token_ends_at(const char* s) const {
    return s == end_ || is_blank(*s) || *s == '\n' || (*s == '\\' && continuation_at(s));
  }

  [[noreturn, gnu::noinline, gnu::cold]] void fail(ErrorCode code, std::uint64_t line,
                                                   const std::string& what) const {
    throw Error(code, std::string(source_) + ":" + std::to_string(line) + ": " + what);
  }
  [[noreturn, gnu::noinline, gnu::cold]] void fail(ErrorCode code, const std::string& what) const {
    fail(code, line_, what);
  }

  // A finite number token: its float32 exactly as std::from_chars rounds it. In quads mode a value
  // float32 cannot hold is refused; in exact mode one float64 cannot hold (the parts keep the rest).
  template <bool kExact>
  [[gnu::always_inline]] const TextNumber& number(const char* context) {
    const char* s = skip_plus();
    NumberStatus st = NumberStatus::kMalformed;
    if (s == p_ || *s != '-')
      st = detail::read_number(
          s, end_, [this](const char* e) { return token_ends_at(e); }, num_);
    if (st != NumberStatus::kOk) [[unlikely]]
      not_ok(st, kExact, context);
    p_ = num_.end;
    return num_;
  }
  // A number that did not read as a float32: refused, or (exact) a float64 beyond float32's range.
  [[gnu::noinline, gnu::cold]] void not_ok(NumberStatus st, bool exact, const char* context) {
    if (st == NumberStatus::kMalformed) {
      fail(ErrorCode::kParse, "malformed number " + quote_token(token_at(p_)) + " in " + context);
    }
    if (st == NumberStatus::kFloatRange) {
      double d = 0;
      if (!exact || !detail::text_double(num_, d)) {
        fail(ErrorCode::kBadNumber,
             "number " + quote_token(token_at(p_)) + " in " + context +
                 (exact ? " is outside the float64 range (it does not round to a finite "
                          "nonzero double)"
                        : " is outside the float32 range (it does not round to a finite "
                          "nonzero float)"));
      }
      num_.f = static_cast<float>(d);
      return;
    }
    fail(ErrorCode::kBadNumber, "number " + quote_token(token_at(p_)) + " in " + context +
                                    " is not finite (NaN and infinity are not valid mesh data)");
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
  [[gnu::always_inline]] bool index(std::uint32_t& magnitude, bool& negative, const char* context,
                                    bool allow_slash) {
    const char* s = p_;
    negative = false;
    if (s < end_ && (*s == '-' || *s == '+')) {
      negative = *s == '-';
      ++s;
    }
    // std::from_chars<uint32>'s grammar, without its cost (it was a sixth of reading a large file).
    const char* q = s;
    std::uint64_t v = 0;
    for (; q < end_; ++q) {
      const std::uint64_t d = static_cast<unsigned char>(*q) - std::uint64_t{'0'};
      if (d > 9) break;
      v = std::min<std::uint64_t>(v * 10 + d, std::uint64_t{1} << 33);  // saturates beyond uint32
    }
    const bool ends = token_ends_at(q) || (allow_slash && q < end_ && *q == '/');
    if (q == s || !ends) [[unlikely]]
      malformed_integer(context);
    p_ = q;
    if (v > 0xFFFFFFFFu) return false;
    magnitude = static_cast<std::uint32_t>(v);
    return true;
  }
  [[noreturn, gnu::noinline, gnu::cold]] void malformed_integer(const char* context) const {
    fail(ErrorCode::kParse, "malformed integer " + quote_token(token_at(token_start_)) + " in " + context);
  }
  // The statement's text from `start` to here, each continuation it went on over joined into one
  // blank: written back on one line it reads as the same statement (kept with its line ends, a
  // continuation that joined an empty line would leave a backslash the writer must end with " #", which
  // makes it a token). A backslash before the line end that ended the statement stays, as the reader
  // took it. `start` is after the keyword: word() does not look for continuations.
  std::string joined_text(const char* start) const {
    std::string out;
    for (const char* s = start; s < p_; ++s) {
      const char* t = s + 1;
      while (t < p_ && blank_at(t)) ++t;
      const bool joined = *s == '\\' && continuation_at(s) && (t < p_ || t == end_);
      if (!joined) {
        out += *s;
        continue;
      }
      out += ' ';
      s = t;  // at the line end, stepped over by ++s; or at the end of the text
    }
    return out;
  }
  void mark_token() { token_start_ = p_; }
  // Past the LF at `lf`, as finish_line() goes past it, after a statement a fast path read up to it
  // (the last token it read starting at `token`).
  void next_line(const char* token, const char* lf) {
    token_start_ = token;
    p_ = lf + 1;
    ++line_;
  }
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
  TextNumber num_;
};

// push_back inlines; vector::insert of a range does not (measured ~2% on large OBJ files).
template <typename T, std::size_t N>
inline void append(std::vector<T>& v, const T (&a)[N]) {
  for (std::size_t i = 0; i < N; ++i) v.push_back(a[i]);
}

// A std::vector appended to through an inlined store (GCC does not inline push_back in the large
// reader functions: ~15 instructions a call on every coordinate and corner). Grown in chunks, the
// vector holds spare elements at its end until finish() trims it; read it only after that.
template <class T>
class Tail {
 public:
  explicit Tail(std::vector<T>& v) : v_(&v), n_(v.size()) {}
  [[gnu::always_inline]] void push(T x) {
    if (n_ == v_->size()) [[unlikely]]
      grow();
    (*v_)[n_++] = x;
  }
  std::size_t size() const { return n_; }
  std::span<const T> view(std::size_t from) const { return {v_->data() + from, n_ - from}; }
  void finish() { v_->resize(n_); }

 private:
  [[gnu::noinline]] void grow() { v_->resize(std::max<std::size_t>(1024, 2 * n_)); }
  std::vector<T>* v_;
  std::size_t n_;
};

std::uint32_t clamp_line(std::uint64_t line) {
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(line, 0xFFFFFFFFu));
}

// The first two corners of `c` with the same vertex (i < j), or false. Pairwise for small faces,
// sorted for large ones so a hostile face of a million corners is not quadratic.
bool repeated_corner_slow(std::span<const std::uint32_t> c, std::vector<std::uint32_t>& scratch,
                          std::size_t& i, std::size_t& j);
inline bool repeated_corner(std::span<const std::uint32_t> c, std::vector<std::uint32_t>& scratch,
                            std::size_t& i, std::size_t& j) {
  if (c.size() == 4) {  // the common case, inline
    const std::uint32_t a = c[0], b = c[1], d = c[2], e = c[3];
    if (a != b && a != d && a != e && b != d && b != e && d != e) return false;
  }
  return repeated_corner_slow(c, scratch, i, j);
}
bool repeated_corner_slow(std::span<const std::uint32_t> c, std::vector<std::uint32_t>& scratch,
                          std::size_t& i, std::size_t& j) {
  const std::size_t n = c.size();
  if (n <= 16) {
    for (i = 0; i < n; ++i) {
      for (j = i + 1; j < n; ++j) {
        if (c[i] == c[j]) return true;
      }
    }
    return false;
  }
  scratch.assign(c.begin(), c.end());
  std::sort(scratch.begin(), scratch.end());
  const auto dup = std::adjacent_find(scratch.begin(), scratch.end());
  if (dup == scratch.end()) return false;
  i = static_cast<std::size_t>(std::find(c.begin(), c.end(), *dup) - c.begin());
  j = static_cast<std::size_t>(std::find(c.begin() + static_cast<std::ptrdiff_t>(i) + 1, c.end(), *dup) -
                               c.begin());
  return true;
}

// "face repeats vertex 3 (corners 1 and 3); ..." with 1-based vertex (OBJ) or 0-based (OFF).
std::string repeat_message(std::uint64_t vertex, std::size_t i, std::size_t j, std::size_t degree) {
  return "face repeats vertex " + std::to_string(vertex) + " (corners " + std::to_string(i + 1) + " and " +
         std::to_string(j + 1) + "); " +
         (degree == 4 ? std::string("a quad needs 4 distinct vertices")
                      : std::string("a face needs distinct vertices"));
}

// Numbers on the rest of a statement (validated, not kept).
std::uint64_t skip_numbers(Scanner& in, const char* context) {
  std::uint64_t n = 0;
  for (;;) {
    in.skip_blank();
    if (in.at_eol()) return n;
    (void)in.number<false>(context);
    ++n;
  }
}

// Up to N numbers of the rest of a statement kept in `out`, all of them counted and validated.
template <bool kExact, std::size_t N>
std::uint64_t read_numbers(Scanner& in, TextNumber (&out)[N], const char* context) {
  std::uint64_t n = 0;
  for (;;) {
    in.skip_blank();
    if (in.at_eol()) return n;
    const TextNumber& t = in.number<kExact>(context);
    if (n < N) out[n] = t;
    ++n;
  }
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (is_blank(s.front()) || s.front() == '\n')) s.remove_prefix(1);
  while (!s.empty() && (is_blank(s.back()) || s.back() == '\n')) s.remove_suffix(1);
  return s;
}

// The blank-separated words of `s` (a backslash continuation counts as a blank).
std::vector<std::string_view> words(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  const auto sep = [&](std::size_t k) { return is_blank(s[k]) || s[k] == '\n' || s[k] == '\\'; };
  while (i < s.size()) {
    while (i < s.size() && sep(i)) ++i;
    const std::size_t b = i;
    while (i < s.size() && !sep(i)) ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

// An OpenSubdiv tag's arguments after `t` (OpenSubdiv's regression/common/shape_utils.cpp grammar:
// name, nint/nfloat/nstring, then the arguments); false when they do not parse exactly, or a
// crease has an odd number of indices.
bool parse_tag(std::string_view body, Tag& tag) {
  const std::vector<std::string_view> w = words(body);
  if (w.size() < 2) return false;
  std::uint64_t counts[3] = {};
  std::string_view c = w[1];
  for (int k = 0; k < 3; ++k) {
    const auto [ptr, ec] = std::from_chars(c.data(), c.data() + c.size(), counts[k]);
    if (ec != std::errc() || ptr == c.data()) return false;
    c.remove_prefix(static_cast<std::size_t>(ptr - c.data()));
    if (k < 2) {
      if (c.empty() || c.front() != '/') return false;
      c.remove_prefix(1);
    }
  }
  if (!c.empty() || counts[0] + counts[1] + counts[2] != w.size() - 2) return false;
  tag.name = std::string(w[0]);
  std::size_t at = 2;
  for (std::uint64_t i = 0; i < counts[0]; ++i, ++at) {
    std::int64_t v = 0;
    const auto [ptr, ec] = std::from_chars(w[at].data(), w[at].data() + w[at].size(), v);
    if (ec != std::errc() || ptr != w[at].data() + w[at].size()) return false;
    tag.ints.push_back(v);
  }
  for (std::uint64_t i = 0; i < counts[1]; ++i, ++at) {
    const char* s = w[at].data();
    const char* e = s + w[at].size();
    if (e - s > 1 && *s == '+' && s[1] != '-') ++s;
    TextNumber t;
    const NumberStatus st = detail::read_number(
        s, e, [e](const char* p) { return p == e; }, t);
    double d = 0;
    if (st == NumberStatus::kFloatRange && detail::text_double(t, d)) {
      t.f = static_cast<float>(d);
    } else if (st != NumberStatus::kOk) {
      return false;
    }
    detail::push_text(tag.floats, t);
  }
  for (std::uint64_t i = 0; i < counts[2]; ++i, ++at) tag.strings.emplace_back(w[at]);
  return tag_indices(tag.name) != TagIndices::kEdges || tag.ints.size() % 2 == 0;
}

// The corners of face f: from the offsets (exact mode) or four per face (quads mode).
std::span<std::uint32_t> face_corners(Mesh& m, std::size_t f) {
  if (m.face_offsets.empty()) return {m.corner_vertices.data() + 4 * f, 4};
  return {m.corner_vertices.data() + m.face_offsets[f], m.face_offsets[f + 1] - m.face_offsets[f]};
}

// Appends one statement to the file order, joining runs.
void add_run(std::vector<Statement>& st, ObjStatement kind, std::uint32_t n = 1) {
  if (!st.empty() && st.back().kind == kind) {
    st.back().value += n;
  } else {
    st.push_back({kind, n});
  }
}

bool is_run(ObjStatement k) {
  return k != ObjStatement::kObject && k != ObjStatement::kGroup && k != ObjStatement::kMaterial &&
         k != ObjStatement::kSmoothing;
}

// The state of a later part before its first statement of a kind: the previous part's, known at the merge.
constexpr std::uint32_t kInherit = 0xFFFFFFFEu;

// o, g, usemtl, s in Mesh order and ObjStatement order.
constexpr ObjStatement kLabelStatements[4] = {ObjStatement::kObject, ObjStatement::kGroup,
                                              ObjStatement::kMaterial, ObjStatement::kSmoothing};
FaceLabels& label_array(Mesh& m, int k) {
  return k == 0 ? m.objects : k == 1 ? m.groups : k == 2 ? m.materials : m.smoothing;
}

// One kind of per-face label while reading: the current value and the names seen.
struct LabelReader {
  std::unordered_map<std::string, std::uint32_t> index;
  std::uint32_t current = kInvalid;  // kInherit in a later part
  bool seen = false;                 // a statement of this kind in the text read
};

void add_warning(std::vector<ReadWarning>& w, std::uint64_t& count, std::uint64_t line, std::string message) {
  if (w.size() < ReadNotes::kMaxWarnings) w.push_back({line, std::move(message)});
  ++count;
}

// ----------------------------------------------------------------------------------------------
// OBJ

// What one reader made of its text: the whole file, or one part of a split read.
struct ObjPart {
  Mesh mesh;
  ReadReport report;
  std::vector<ReadWarning> warnings;
  std::uint64_t warning_count = 0;
  std::uint64_t vertex_count = 0, face_count = 0, texcoord_count = 0, normal_count = 0;
  std::uint64_t end_line = 1;                                     // the scanner's line at the end of the part
  std::uint32_t max_index = 0, max_texcoord = 0, max_normal = 0;  // largest absolute 0-based indices
  bool any_texcoord_ref = false, any_normal_ref = false;
  NonQuads non_quads;
  int vertex_extras = -1;                // numbers after x y z on every `v` (-1: no `v`)
  std::uint64_t extras_line = 0;         // of the first `v`
  std::uint8_t texcoord_components = 0;  // 0: no `vt`
  std::vector<std::uint64_t> tag_line;   // per tag
  LabelReader labels[4];
  // Later part only. Relative indices count back from the part's own vertices (texture coordinates,
  // normals): `missing` is how far the deepest reaches before the part; the corners listed hold
  // indices that still lack the earlier count; `relative_faces` have a relative vertex corner, their
  // repeated-vertex check waits for the merge.
  std::uint64_t missing = 0, missing_texcoords = 0, missing_normals = 0;
  std::vector<std::uint32_t> relative_vertex, relative_texcoord, relative_normal, relative_faces;
  bool ok = false;  // read without error
};

template <bool kExact>
class ObjReader {
 public:
  // `later_part`: the text starts mid-file at a line start (read_obj_parts), so vertices before
  // it are unknown; relative indices are recorded for the merge instead of checked.
  ObjReader(std::string_view text, std::string_view source, ObjPart& out, bool later_part = false)
      : in_(text, source, !later_part),
        source_(source),
        out_(out),
        mesh_(out.mesh),
        report_(out.report),
        later_part_(later_part) {
    if (later_part) {
      for (LabelReader& l : out_.labels) l.current = kInherit;
    }
  }

  // The whole file, with the checks that need all of it.
  void run() {
    parse();
    if constexpr (!kExact) non_quads_.throw_if_any(source_);
    check_forward_indices();
    check_tags();
    finish_part();
  }

  // A part, without the checks that need the whole file (non-quads, forward indices, tags).
  void run_part() {
    parse();
    finish_part();
  }

 private:
  void finish_part() {
    out_.vertex_count = vertex_count_;
    out_.face_count = face_count_;
    out_.texcoord_count = texcoord_count_;
    out_.normal_count = normal_count_;
    out_.end_line = in_.line();
    out_.max_index = max_index_;
    out_.max_texcoord = max_texcoord_;
    out_.max_normal = max_normal_;
    out_.non_quads = non_quads_;
  }

  void parse() {
    if constexpr (kExact) offsets_.push(0);
    parse_statements();
    positions_.finish();
    corners_out_.finish();
    offsets_.finish();
    face_line_.finish();
  }

  void parse_statements() {
    while (!in_.done()) {
      if (plain_line()) [[likely]]
        continue;
      in_.skip_blank();
      if (in_.at_eol()) {
        if constexpr (kExact) {
          if (in_.peek() == '#') {
            mesh_.comments.emplace_back(in_.comment_text());
            run(ObjStatement::kComment);
          }
        }
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
    const char* start = in_.pos();
    const std::string_view k = in_.word();
    keyword_ = k;
    if (k.size() == 1) {
      switch (k[0]) {
        case 'v':
          return vertex(line);
        case 'f':
          return face(line);
        case 'g':
          return label(1, report_.groups);
        case 'o':
          return label(0, report_.groups);
        case 's':
          return label(3, report_.smoothing);
        case 't':
          return tag(line, start);  // OpenSubdiv tags: `t crease 2/1/0 1 2 4.0`
        default:
          break;
      }
    } else if (k.size() == 2 && k[0] == 'v') {
      if (k[1] == 't') return texcoord();
      if (k[1] == 'n') return normal();
    } else if (k == "usemtl") {
      return label(2, report_.materials);
    } else if (k == "mtllib") {
      return material_library();
    }
    other_statement(line, start, k);
  }

  // The statements that are rare in large files, out of the hot path.
  [[gnu::noinline]] void other_statement(std::uint64_t line, const char* start, std::string_view k) {
    if (k == "vp") {
      check_count(skip_numbers(in_, "`vp` statement"), 1, 3, "`vp` statement");
      return keep_text(line, start, "`vp` (parameter-space vertex)");
    }
    if (k == "usemap" || k == "maplib") {
      in_.skip_statement();
      return keep_text(line, start, "`" + std::string(k) + "` (old texture map statement)");
    }
    if (k == "l" || k == "p") {
      in_.fail(ErrorCode::kUnsupported, line,
               std::string("`") + std::string(k) + "` (" + (k == "l" ? "polyline" : "point") +
                   ") elements are not supported; qsp stores quad meshes only");
    }
    // Free-form geometry: the elements would change the mesh; the rest only describes them.
    static constexpr std::string_view kFreeFormElements[] = {"curv", "curv2", "surf"};
    static constexpr std::string_view kFreeForm[] = {
        "cstype",   "deg", "bmat",       "step",      "parm",  "trim",  "hole",
        "scrv",     "sp",  "end",        "con",       "mg",    "bevel", "c_interp",
        "d_interp", "lod", "shadow_obj", "trace_obj", "ctech", "stech"};
    const bool element = std::find(std::begin(kFreeFormElements), std::end(kFreeFormElements), k) !=
                         std::end(kFreeFormElements);
    const bool attribute = std::find(std::begin(kFreeForm), std::end(kFreeForm), k) != std::end(kFreeForm);
    if (element) {
      in_.fail(ErrorCode::kUnsupported, line,
               "`" + std::string(k) + "` (free-form geometry) is not supported; qsp stores quad meshes only");
    }
    in_.skip_statement();
    keep_text(line, start,
              attribute ? "`" + std::string(k) + "` (free-form or display attribute, no geometry)"
                        : "unknown statement " + quote_token(k));
  }

  // One more statement of a run kind (v, vt, vn, f, ...) in the file order.
  [[gnu::always_inline]] void run(ObjStatement kind) {
    std::vector<Statement>& st = mesh_.statements;
    if (!st.empty() && st.back().kind == kind) [[likely]] {
      ++st.back().value;
    } else {
      st.push_back({kind, 1});
    }
  }

  // A statement qsp keeps as text: [start, the end of the statement), in place, with a warning (quads
  // mode counts it, as both modes count everything else).
  [[gnu::noinline]] void keep_text(std::uint64_t line, const char* start, const std::string& what) {
    // Prose is kept; a NUL byte says the file is not text at all (a binary file read as OBJ).
    if (std::memchr(start, '\0', static_cast<std::size_t>(in_.pos() - start)))
      in_.fail(ErrorCode::kParse, line, "binary data (a NUL byte) where a statement should be: not OBJ text");
    report_.note_kept(line, what);
    if constexpr (kExact) {
      // The keyword as word() took it (a backslash in it is never a continuation), then the rest joined.
      mesh_.verbatim.emplace_back(trim(std::string(keyword_) + in_.joined_text(start + keyword_.size())));
      run(ObjStatement::kVerbatim);
      add_warning(out_.warnings, out_.warning_count, line,
                  "kept as text and written back unchanged: " + what);
    } else {
      (void)start;
    }
  }

  void vertex(std::uint64_t line) {
    for (int i = 0; i < 3; ++i) {
      in_.skip_blank();
      if (in_.at_eol()) {
        in_.fail(ErrorCode::kParse, "`v` needs 3 coordinates, found " + std::to_string(i));
      }
      const TextNumber& t = in_.template number<kExact>("`v` statement");
      if constexpr (kExact) {
        if (mesh_.positions.precision == Precision::kFloat32 && detail::float32_by_digits(t)) [[likely]] {
          positions_.push(t.f);
        } else {
          positions_.push(detail::push_text_at(mesh_.positions, positions_.size(), t));
        }
      } else {
        positions_.push(t.f);
        if (!detail::float32_by_digits(t)) [[unlikely]]
          check_rounded(line, t);
      }
    }
    if (vertex_count_ >= kMaxVertices) {
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxVertices) + " vertices");
    }
    ++vertex_count_;
    in_.skip_blank();
    if (in_.at_eol()) [[likely]] {
      if constexpr (kExact) {
        run(ObjStatement::kVertex);
        if (out_.vertex_extras != 0) vertex_shape(line, 0);
      }
      return;
    }
    vertex_extras(line);
  }

  // Quads mode: a coordinate whose digits float32 may not hold is counted when it does not.
  [[gnu::noinline]] void check_rounded(std::uint64_t line, const TextNumber& t) {
    if (!detail::float32_holds(t))
      report_.note_rounded(line, vertex_count_,
                           std::string_view(t.begin, static_cast<std::size_t>(t.end - t.begin)), t.f);
  }

  // A `v` with numbers after x y z: w, or a colour.
  [[gnu::noinline]] void vertex_extras(std::uint64_t line) {
    std::uint64_t extra = 0;
    TextNumber ex[4];
    {
      // Optional w, or r g b (some exporters write x y z r g b, a few x y z w r g b / r g b a).
      extra = read_numbers<kExact>(in_, ex, "`v` statement");
      if (extra != 1 && extra != 3 && extra != 4) {
        in_.fail(ErrorCode::kParse, "`v` has " + std::to_string(3 + extra) +
                                        " numbers; expected x y z, optionally followed by w or r g b");
      }
      ++(extra == 1 ? report_.vertex_weights : report_.vertex_colors);
    }
    if constexpr (kExact) {
      run(ObjStatement::kVertex);
      if (out_.vertex_extras != static_cast<int>(extra)) vertex_shape(line, static_cast<int>(extra));
      if (extra == 1) detail::push_text(mesh_.vertex_weights, ex[0]);
      for (std::uint64_t i = 0; i < extra && extra >= 3; ++i) detail::push_text(mesh_.vertex_colors, ex[i]);
    }
  }

  // The first `v` sets how many numbers follow x y z; every other one must have as many.
  [[gnu::noinline]] void vertex_shape(std::uint64_t line, int extra) {
    if (out_.vertex_extras < 0) {
      out_.vertex_extras = extra;
      out_.extras_line = line;
      mesh_.vertex_color_components = extra >= 3 ? static_cast<std::uint8_t>(extra) : 0;
      return;
    }
    in_.fail(ErrorCode::kUnsupported,
             "`v` has " + std::to_string(3 + extra) + " numbers but the first vertex (line " +
                 std::to_string(out_.extras_line) + ") has " + std::to_string(3 + out_.vertex_extras) +
                 "; qsp keeps vertex colours or weights only when every vertex has them");
  }

  [[gnu::noinline]] void texcoord() {
    if constexpr (!kExact) return count_numbers(report_.texcoords, 1, 3, "`vt` statement");
    TextNumber t[3];
    const std::uint64_t n = read_numbers<kExact>(in_, t, "`vt` statement");
    check_count(n, 1, 3, "`vt` statement");
    add_texcoord(t, n);
  }

  // Exact mode: a `vt` of n (1 to 3) numbers read.
  void add_texcoord(const TextNumber* t, std::uint64_t n) {
    ++report_.texcoords;
    std::uint8_t& comps = out_.texcoord_components;
    if (comps == 0) {
      comps = static_cast<std::uint8_t>(n);
    } else if (n > comps) {  // a longer one: the earlier ones get OBJ's default 0
      detail::widen_groups(mesh_.texcoords, comps, n, 0.0f);
      comps = static_cast<std::uint8_t>(n);
    }
    mesh_.texcoord_components = comps;
    for (std::uint64_t i = 0; i < n; ++i) detail::push_text(mesh_.texcoords, t[i]);
    detail::push_small(mesh_.texcoords, 0.0f, comps - n);
    ++texcoord_count_;
    run(ObjStatement::kTexcoord);
  }

  [[gnu::noinline]] void normal() {
    if constexpr (!kExact) return count_numbers(report_.normals, 3, 3, "`vn` statement");
    TextNumber t[3];
    const std::uint64_t n = read_numbers<kExact>(in_, t, "`vn` statement");
    check_count(n, 3, 3, "`vn` statement");
    add_normal(t);
  }

  // Exact mode: a `vn` read.
  void add_normal(const TextNumber (&t)[3]) {
    ++report_.normals;
    for (const TextNumber& x : t) detail::push_text(mesh_.normals, x);
    ++normal_count_;
    run(ObjStatement::kNormal);
  }

  void face(std::uint64_t line) {
    if constexpr (!kExact) return quad(line);
    bool attributes = false, any_t = false, any_n = false, relative = false;
    const std::size_t base = corners_out_.size();
    std::uint32_t magnitude = 0;
    bool negative = false, in_range = false;
    while (next_corner(magnitude, negative, in_range)) {
      if (in_.peek() == '/') {  // v/vt, v//vn or v/vt/vn
        if (!attributes) {      // the corners before had none
          attributes = true;
          texcoords_.assign(corners_out_.size() - base, kInvalid);
          normals_.assign(corners_out_.size() - base, kInvalid);
        }
        std::uint32_t t = kInvalid, n = kInvalid;
        in_.advance();
        if (in_.peek() != '/') {
          t = attribute(false, corners_out_.size());
          any_t = true;
        }
        if (in_.peek() == '/') {
          in_.advance();
          n = attribute(true, corners_out_.size());
          any_n = true;
        }
        if (!in_.token_ends_at(in_.pos())) {
          in_.fail(ErrorCode::kParse,
                   "malformed vertex reference " + quote_token(in_.token_at(in_.token_start())));
        }
        texcoords_.push_back(t);
        normals_.push_back(n);
      } else if (attributes) {
        texcoords_.push_back(kInvalid);
        normals_.push_back(kInvalid);
      }
      const std::uint32_t index = resolve(magnitude, negative, in_range);
      if (negative && later_part_) {
        out_.relative_vertex.push_back(static_cast<std::uint32_t>(corners_out_.size()));
        relative = true;
      }
      corners_out_.push(index);
    }
    if (any_t) ++report_.faces_with_texcoords;
    if (any_n) ++report_.faces_with_normals;
    const std::size_t degree = corners_out_.size() - base;
    if (degree < 3) {
      in_.fail(ErrorCode::kDegenerateFace, line,
               "face has " + corners_name(degree) + "; a face needs at least 3 distinct vertices");
    }
    // A later part cannot compare a relative corner with an absolute one before the merge does.
    std::size_t i = 0, j = 0;
    if (!(later_part_ && relative) && repeated_corner(corners_out_.view(base), scratch_, i, j)) {
      in_.fail(ErrorCode::kDegenerateFace, line,
               repeat_message(std::uint64_t{corners_out_.view(base)[i]} + 1, i, j, degree));
    }
    if (face_count_ >= kMaxFaces)
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxFaces) + " faces");
    if (base + degree > kMaxCorners)
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxCorners) + " face corners");
    if (relative) out_.relative_faces.push_back(static_cast<std::uint32_t>(face_count_));
    ++face_count_;
    offsets_.push(static_cast<std::uint32_t>(base + degree));
    if (any_t || !mesh_.corner_texcoords.empty())
      add_corner_attribute(mesh_.corner_texcoords, texcoords_, any_t, base, degree);
    if (any_n || !mesh_.corner_normals.empty())
      add_corner_attribute(mesh_.corner_normals, normals_, any_n, base, degree);
    add_face_labels();
    run(ObjStatement::kFace);
    face_line_.push(clamp_line(line));
  }

  // The current o, g, usemtl and s of a face read (those the file has so far).
  void add_face_labels() {
    if (active_labels_) {
      for (int k = 0; k < 4; ++k) {
        if (out_.labels[k].seen) label_array(mesh_, k).face.push_back(out_.labels[k].current);
      }
    }
  }

  // Per-corner indices of one kind: created (kInvalid for earlier corners) by the first face with one;
  // `face` is empty when this face has none.
  static void add_corner_attribute(std::vector<std::uint32_t>& to, std::span<const std::uint32_t> face,
                                   bool any, std::size_t base, std::size_t degree) {
    to.resize(base, kInvalid);
    if (any) {
      to.insert(to.end(), face.begin(), face.end());
    } else {
      to.resize(base + degree, kInvalid);
    }
  }

  // The vertex index of a face's next corner (its token's start marked); false at the statement's end.
  [[gnu::always_inline]] bool next_corner(std::uint32_t& magnitude, bool& negative, bool& in_range) {
    in_.skip_blank();
    if (in_.at_eol()) return false;
    in_.mark_token();
    magnitude = 0;
    in_range = in_.index(magnitude, negative, "`f` statement", true);
    return true;
  }

  // Quads mode: quads kept, other faces counted for the message and skipped.
  void quad(std::uint64_t line) {
    std::uint32_t q[4];
    std::uint64_t corners = 0;
    bool any_t = false, any_n = false;
    bool relative = false;
    const std::size_t base = corners_out_.size();
    std::uint32_t magnitude = 0;
    bool negative = false, in_range = false;
    while (next_corner(magnitude, negative, in_range)) {
      if (in_.peek() == '/') {  // v/vt, v//vn or v/vt/vn: checked for syntax only
        in_.advance();
        if (in_.peek() != '/') {
          attribute_syntax("texture coordinate");
          any_t = true;
        }
        if (in_.peek() == '/') {
          in_.advance();
          attribute_syntax("normal");
          any_n = true;
        }
        if (!in_.token_ends_at(in_.pos())) {
          in_.fail(ErrorCode::kParse,
                   "malformed vertex reference " + quote_token(in_.token_at(in_.token_start())));
        }
      }
      const std::uint32_t index = resolve(magnitude, negative, in_range);
      if (corners < 4) {
        q[corners] = index;
        if (negative && later_part_) {
          out_.relative_vertex.push_back(static_cast<std::uint32_t>(base + corners));
          relative = true;
        }
      }
      ++corners;
    }
    if (any_t) ++report_.faces_with_texcoords;
    if (any_n) ++report_.faces_with_normals;
    if (corners != 4) {
      // Its relative corners are not stored.
      while (!out_.relative_vertex.empty() && out_.relative_vertex.back() >= base)
        out_.relative_vertex.pop_back();
      non_quads_.add(line, corners);
      return;
    }
    std::size_t i = 0, j = 0;
    if (!(later_part_ && relative) && repeated_corner(q, scratch_, i, j)) {
      in_.fail(ErrorCode::kDegenerateFace, line, repeat_message(std::uint64_t{q[i]} + 1, i, j, 4));
    }
    if (face_count_ >= kMaxFaces)
      in_.fail(ErrorCode::kLimit, "more than " + std::to_string(kMaxFaces) + " faces");
    if (relative) out_.relative_faces.push_back(static_cast<std::uint32_t>(face_count_));
    ++face_count_;
    for (const std::uint32_t c : q) corners_out_.push(c);
    face_line_.push(clamp_line(line));
  }

  // The fast path for the common lines, a `v` of three numbers, a `vt` or `vn` of numbers and an `f` of
  // corners of plain indices (v, v/vt, v//vn, v/vt/vn; quads mode: four), each item after spaces and the last
  // one right before the LF: read as statement() and finish_line() read them, with the same effects, without
  // their general checks per character (continuations, lone CRs, comments, signs). Anything else, errors
  // included, is left to them: false, nothing done. Half of parse_statements' own instructions on mh_base; a
  // third of both reads of mh_female_generic (`vt`, v/vt corners), which compress reads twice (quads, then
  // exact).
  bool plain_line() {
    const char* const p = in_.pos();
    if (in_.end() - p < 3) return false;
    if (p[1] == ' ') {
      if (p[0] == 'v') return plain_vertex(p + 1);
      if constexpr (kExact) return p[0] == 'f' && plain_face(p + 1);
      return p[0] == 'f' && plain_quad(p + 1);
    }
    if (p[0] != 'v' || p[2] != ' ') return false;
    if (p[1] == 't') {
      if constexpr (kExact) return plain_texcoord(p + 2);
      return plain_counted(p + 2, 1, 3, report_.texcoords);
    }
    if constexpr (kExact) return p[1] == 'n' && plain_normal(p + 2);
    return p[1] == 'n' && plain_counted(p + 2, 3, 3, report_.normals);
  }

  // A `vt` or `vn` of `min` to `max` numbers, which quads mode validates and counts (count_numbers).
  bool plain_counted(const char* p, unsigned min, unsigned max, std::uint64_t& counter) {
    const char* const end = in_.end();
    const auto ends = [end](const char* e) { return e < end && (*e == ' ' || *e == '\n'); };
    TextNumber x;
    unsigned n = 0;
    do {
      if (p == end || *p != ' ') return false;
      do ++p;
      while (p < end && *p == ' ');
      if (p == end) return false;
      if (const char* e = detail::plain_number_end(p, end, ends)) {
        p = e;
      } else {
        if (!plain_number(p, end, ends, x)) return false;
        p = x.end;
      }
      ++n;
    } while (*p != '\n' && n < max);  // p < end: ends() took it
    if (*p != '\n' || n < min) return false;
    ++counter;
    in_.next_line(in_.token_start(), p);
    return true;
  }

  // Exact mode: `min` to `max` (at most 3) plain numbers float32 reads into t, p moved to the line's end;
  // their count, or 0 where the line is not that (the general path then reads it).
  unsigned plain_numbers(const char*& p, TextNumber (&t)[3], unsigned min, unsigned max) {
    const char* const end = in_.end();
    const auto ends = [end](const char* e) { return e < end && (*e == ' ' || *e == '\n'); };
    unsigned n = 0;
    do {
      if (p == end || *p != ' ') return 0;
      do ++p;
      while (p < end && *p == ' ');
      if (p == end || !plain_number(p, end, ends, t[n])) return 0;
      p = t[n++].end;
    } while (*p != '\n' && n < max);  // p < end: ends() took it
    return *p == '\n' && n >= min ? n : 0;
  }

  // Exact mode: a `vt` of 1 to 3 numbers float32 reads (texcoord()).
  bool plain_texcoord(const char* p) {
    TextNumber t[3];
    const unsigned n = plain_numbers(p, t, 1, 3);
    if (n == 0) return false;
    add_texcoord(t, n);
    in_.next_line(in_.token_start(), p);
    return true;
  }

  // Exact mode: a `vn` of 3 numbers float32 reads (normal()).
  bool plain_normal(const char* p) {
    TextNumber t[3];
    if (plain_numbers(p, t, 3, 3) == 0) return false;
    add_normal(t);
    in_.next_line(in_.token_start(), p);
    return true;
  }

  // Exact mode: a face of 3 to 8 corners of plain indices (v, v/vt, v//vn, v/vt/vn), as face() reads it.
  bool plain_face(const char* p) {
    constexpr std::size_t kMaxPlain = 8;
    const char *const end = in_.end(), *token = p;
    std::uint32_t v[kMaxPlain], t[kMaxPlain], n[kMaxPlain];
    bool any_t = false, any_n = false;
    std::size_t degree = 0;
    do {
      if (degree == kMaxPlain || p == end || *p != ' ') return false;
      do ++p;
      while (p < end && *p == ' ');
      token = p;
      std::uint32_t x = 0;
      if (!plain_index(p, end, x) || x > kMaxVertices) return false;
      v[degree] = x - 1;
      t[degree] = n[degree] = kInvalid;
      if (*p == '/') {
        if (++p < end && *p != '/') {
          if (!plain_index(p, end, x)) return false;
          t[degree] = x - 1;
          any_t = true;
        }
        if (p < end && *p == '/') {
          if (!plain_index(++p, end, x)) return false;
          n[degree] = x - 1;
          any_n = true;
        }
      }
      if (p == end || (*p != ' ' && *p != '\n')) return false;
      ++degree;
    } while (*p != '\n');
    const std::size_t base = corners_out_.size();
    std::size_t i = 0, j = 0;
    if (degree < 3 || repeated_corner({v, degree}, scratch_, i, j) || face_count_ >= kMaxFaces ||
        base + degree > kMaxCorners)
      return false;
    for (std::size_t k = 0; k < degree; ++k) {
      max_index_ = std::max(max_index_, v[k]);
      corners_out_.push(v[k]);
    }
    const auto refs = [degree](const std::uint32_t* a, bool& any_ref, std::uint32_t& most) {
      any_ref = true;
      for (std::size_t k = 0; k < degree; ++k) {
        if (a[k] != kInvalid) most = std::max(most, a[k]);
      }
    };
    if (any_t) {
      refs(t, out_.any_texcoord_ref, max_texcoord_);
      ++report_.faces_with_texcoords;
    }
    if (any_n) {
      refs(n, out_.any_normal_ref, max_normal_);
      ++report_.faces_with_normals;
    }
    ++face_count_;
    offsets_.push(static_cast<std::uint32_t>(base + degree));
    if (any_t || !mesh_.corner_texcoords.empty())
      add_corner_attribute(mesh_.corner_texcoords, {t, degree}, any_t, base, degree);
    if (any_n || !mesh_.corner_normals.empty())
      add_corner_attribute(mesh_.corner_normals, {n, degree}, any_n, base, degree);
    add_face_labels();
    run(ObjStatement::kFace);
    face_line_.push(clamp_line(in_.line()));
    in_.next_line(token, p);
    return true;
  }

  // The number at p (p < end), as Scanner::number() reads it without a '+' and when it is kOk: false
  // otherwise.
  template <class Ends>
  [[gnu::always_inline]] static bool plain_number(const char* p, const char* end, Ends ends, TextNumber& x) {
    return *p != '+' && (detail::read_plain_number(p, end, ends, x) ||
                         detail::read_number(p, end, ends, x) == NumberStatus::kOk);
  }

  bool plain_vertex(const char* p) {
    const char* const end = in_.end();
    TextNumber t[3];
    const auto ends = [end](const char* e) { return e < end && (*e == ' ' || *e == '\n'); };
    for (TextNumber& x : t) {
      if (p == end || *p != ' ') return false;
      do ++p;
      while (p < end && *p == ' ');
      if (p == end || !plain_number(p, end, ends, x)) return false;
      p = x.end;
    }
    if (*p != '\n' || vertex_count_ >= kMaxVertices) return false;  // p < end: ends() took it
    const std::uint64_t line = in_.line();
    if constexpr (kExact) {
      if (out_.vertex_extras > 0) return false;  // vertex_shape() refuses it
      for (const TextNumber& x : t) {
        if (mesh_.positions.precision == Precision::kFloat32 && detail::float32_by_digits(x)) [[likely]] {
          positions_.push(x.f);
        } else {
          positions_.push(detail::push_text_at(mesh_.positions, positions_.size(), x));
        }
      }
      ++vertex_count_;
      run(ObjStatement::kVertex);
      if (out_.vertex_extras != 0) vertex_shape(line, 0);
      in_.next_line(in_.token_start(), p);
      return true;
    }
    for (const TextNumber& x : t) {
      positions_.push(x.f);
      if (!detail::float32_by_digits(x)) [[unlikely]]
        check_rounded(line, x);
    }
    ++vertex_count_;
    in_.next_line(in_.token_start(), p);
    return true;
  }

  // 1 to 9 digits at p (9 stay below 2^32), not 0 and not the text's end after them: their value.
  static bool plain_index(const char*& p, const char* end, std::uint32_t& v) {
    const char* const first = p;
    const char* const last = end - p > 9 ? p + 9 : end;
    v = 0;
    for (; p < last; ++p) {
      const auto d = static_cast<std::uint32_t>(static_cast<unsigned char>(*p)) - '0';
      if (d > 9) break;
      v = v * 10 + d;
    }
    return p != first && p != end && v != 0;
  }

  bool plain_quad(const char* p) {
    const char *const end = in_.end(), *token = p;
    std::uint32_t q[4];
    bool any_t = false, any_n = false;
    for (std::uint32_t& index : q) {
      if (p == end || *p != ' ') return false;
      do ++p;
      while (p < end && *p == ' ');
      token = p;
      std::uint32_t v = 0;
      if (!plain_index(p, end, v) || v > kMaxVertices) return false;
      if (*p == '/') {  // v/vt, v//vn or v/vt/vn: checked for syntax only, as attribute_syntax does
        std::uint32_t a = 0;
        if (++p < end && *p != '/') {
          if (!plain_index(p, end, a)) return false;
          any_t = true;
        }
        if (p < end && *p == '/') {
          if (!plain_index(++p, end, a)) return false;
          any_n = true;
        }
      }
      if (p == end || (*p != ' ' && *p != '\n')) return false;
      index = v - 1;
    }
    std::size_t i = 0, j = 0;
    if (*p != '\n' || repeated_corner(q, scratch_, i, j) || face_count_ >= kMaxFaces) return false;
    if (any_t) ++report_.faces_with_texcoords;
    if (any_n) ++report_.faces_with_normals;
    for (const std::uint32_t c : q) max_index_ = std::max(max_index_, c);
    ++face_count_;
    for (const std::uint32_t c : q) corners_out_.push(c);
    face_line_.push(clamp_line(in_.line()));
    in_.next_line(token, p);
    return true;
  }

  // Quads mode: vt/vn indices are checked for syntax only.
  void attribute_syntax(const char* what) {
    std::uint32_t magnitude = 0;
    bool negative = false;
    if (!in_.index(magnitude, negative, "`f` statement", true) || magnitude == 0) {
      in_.fail(ErrorCode::kParse,
               std::string("invalid ") + what + " index in " + quote_token(in_.token_at(in_.token_start())));
    }
  }

  // A texture coordinate or normal index (1-based, or negative = relative to those so far) to 0-based.
  // Positive indices may refer to ones defined later; they are range-checked at the end.
  std::uint32_t attribute(bool normal, std::size_t corner) {
    const char* what = normal ? "normal" : "texture coordinate";
    std::uint32_t magnitude = 0;
    bool negative = false;
    if (!in_.index(magnitude, negative, "`f` statement", true) || magnitude == 0) {
      in_.fail(ErrorCode::kParse,
               std::string("invalid ") + what + " index in " + quote_token(in_.token_at(in_.token_start())));
    }
    const std::uint64_t count = normal ? normal_count_ : texcoord_count_;
    if (negative) {
      if (magnitude > count && !later_part_) {
        in_.fail(ErrorCode::kBadIndex, std::string(what) + " index in " +
                                           quote_token(in_.token_at(in_.token_start())) +
                                           " is out of range (" +
                                           plural(count, normal ? "normal" : "texture coordinate",
                                                  normal ? "normals" : "texture coordinates") +
                                           " defined before this line)");
      }
      if (later_part_) {
        (normal ? out_.relative_normal : out_.relative_texcoord)
            .push_back(static_cast<std::uint32_t>(corner));
        if (magnitude > count) {
          std::uint64_t& missing = normal ? out_.missing_normals : out_.missing_texcoords;
          missing = std::max<std::uint64_t>(missing, magnitude - count);
        }
      }
      return static_cast<std::uint32_t>(count - magnitude);
    }
    (normal ? out_.any_normal_ref : out_.any_texcoord_ref) = true;
    std::uint32_t& most = normal ? max_normal_ : max_texcoord_;
    most = std::max(most, magnitude - 1);
    return magnitude - 1;
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
      if (magnitude > vertex_count_) out_.missing = std::max(out_.missing, magnitude - vertex_count_);
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
    check_forward(mesh_.corner_vertices, face_count_ > 0 && max_index_ >= vertex_count_, vertex_count_,
                  [](std::uint64_t i, std::uint64_t n) {
                    return "vertex index " + std::to_string(i + 1) + " is out of range (the file has " +
                           plural(n, "vertex", "vertices") + ")";
                  });
    if constexpr (kExact) {
      check_forward(mesh_.corner_texcoords, out_.any_texcoord_ref && max_texcoord_ >= texcoord_count_,
                    texcoord_count_, [](std::uint64_t i, std::uint64_t n) {
                      return "texture coordinate index " + std::to_string(i + 1) +
                             " is out of range (the file has " +
                             plural(n, "texture coordinate", "texture coordinates") + ")";
                    });
      check_forward(mesh_.corner_normals, out_.any_normal_ref && max_normal_ >= normal_count_, normal_count_,
                    [](std::uint64_t i, std::uint64_t n) {
                      return "normal index " + std::to_string(i + 1) + " is out of range (the file has " +
                             plural(n, "normal", "normals") + ")";
                    });
    }
  }

  // The first corner whose index is `count` or more, reported at its face's line.
  template <class Message>
  void check_forward(const std::vector<std::uint32_t>& corners, bool suspect, std::uint64_t count,
                     Message message) {
    if (!suspect) return;
    for (std::size_t f = 0; f < face_count_; ++f) {
      const std::span<std::uint32_t> c = face_corners(mesh_, f);
      const std::size_t at = static_cast<std::size_t>(c.data() - mesh_.corner_vertices.data());
      for (std::size_t i = 0; i < c.size(); ++i) {
        const std::uint32_t index = corners[at + i];
        if (index != kInvalid && index >= count)
          in_.fail(ErrorCode::kBadIndex, report_.face_line[f], message(index, count));
      }
    }
  }

  // Tag indices must name vertices and faces of the file.
  void check_tags() {
    for (std::size_t i = 0; i < mesh_.tags.size(); ++i) {
      const Tag& t = mesh_.tags[i];
      const TagIndices kind = tag_indices(t.name);
      if (kind == TagIndices::kNone || kind == TagIndices::kUnknown) continue;
      const bool faces = kind == TagIndices::kFaces;
      const std::uint64_t n = faces ? face_count_ : vertex_count_;
      for (const std::int64_t x : t.ints) {
        if (x < 0 || static_cast<std::uint64_t>(x) >= n) {
          in_.fail(ErrorCode::kBadIndex, out_.tag_line[i],
                   "`t " + t.name + "` refers to " + (faces ? "face " : "vertex ") + std::to_string(x) +
                       "; the file has " +
                       (faces ? plural(n, "face", "faces") : plural(n, "vertex", "vertices")) +
                       " (tags number them from 0)");
        }
      }
    }
  }

  void check_count(std::uint64_t n, std::uint64_t min, std::uint64_t max, const char* context) {
    if (n < min || n > max) {
      std::string want =
          min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max);
      in_.fail(ErrorCode::kParse,
               std::string(context) + " has " + std::to_string(n) + " numbers, expected " + want);
    }
  }
  void count_numbers(std::uint64_t& counter, std::uint64_t min, std::uint64_t max, const char* context) {
    check_count(skip_numbers(in_, context), min, max, context);
    ++counter;
  }

  // o, g, usemtl, s: the value from here on (quads mode counts them).
  [[gnu::noinline]] void label(int kind, std::uint64_t& counter) {
    ++counter;
    if constexpr (!kExact) return in_.skip_statement();
    const char* s = in_.pos();
    in_.skip_statement();
    const std::string_view text = trim(std::string_view(s, static_cast<std::size_t>(in_.pos() - s)));
    std::string name;
    if (kind == 1) {  // g: several names
      for (const std::string_view w : words(text)) {
        if (!name.empty()) name += ' ';
        name += w;
      }
    } else {
      name = text;
    }
    LabelReader& l = out_.labels[kind];
    FaceLabels& labels = label_array(mesh_, kind);
    const auto [it, added] = l.index.try_emplace(name, static_cast<std::uint32_t>(labels.names.size()));
    if (added) labels.names.push_back(std::move(name));
    if (!l.seen) {
      l.seen = true;
      labels.face.assign(face_count_, l.current);
      active_labels_ |= 1u << kind;
    }
    l.current = it->second;
    mesh_.statements.push_back({kLabelStatements[kind], it->second});
  }

  [[gnu::noinline]] void material_library() {
    ++report_.materials;
    if constexpr (!kExact) return in_.skip_statement();
    const char* s = in_.pos();
    in_.skip_statement();
    mesh_.material_libraries.emplace_back(trim(std::string_view(s, static_cast<std::size_t>(in_.pos() - s))));
    run(ObjStatement::kMaterialLibrary);
  }

  // Both modes parse a tag: one that does not parse is kept as text, not a tag (`--drop extra`).
  [[gnu::noinline]] void tag(std::uint64_t line, const char* start) {
    const char* s = in_.pos();
    in_.skip_statement();
    Tag t;
    if (!parse_tag(std::string_view(s, static_cast<std::size_t>(in_.pos() - s)), t))
      return keep_text(line, start, "malformed OpenSubdiv tag");
    ++report_.tags;
    if constexpr (kExact) {
      mesh_.tags.push_back(std::move(t));
      out_.tag_line.push_back(line);
      run(ObjStatement::kTag);
    }
  }

  static constexpr std::uint64_t kMaxCorners = 0xFFFFFFFEu;

  Scanner in_;
  std::string_view source_;
  ObjPart& out_;
  Mesh& mesh_;
  ReadReport& report_;
  std::string_view keyword_;
  std::uint64_t vertex_count_ = 0, face_count_ = 0, texcoord_count_ = 0, normal_count_ = 0;
  std::uint32_t max_index_ = 0, max_texcoord_ = 0, max_normal_ = 0;
  NonQuads non_quads_;
  const bool later_part_;
  unsigned active_labels_ = 0;                                // bit per kind with a statement so far
  std::vector<std::uint32_t> texcoords_, normals_, scratch_;  // of the current face
  Tail<float> positions_{mesh_.positions.f32};
  Tail<std::uint32_t> corners_out_{mesh_.corner_vertices}, offsets_{mesh_.face_offsets};
  Tail<std::uint32_t> face_line_{report_.face_line};
};

// Adds a part's counters; face lines are merged separately.
void add_counts(ReadReport& to, const ReadReport& from) {
  // A new ReadReport member must be merged here too.
  // (The leading comments are the whole text's: read_obj sets them after the parts are merged.)
  static_assert(sizeof(ReadReport) == 16 * sizeof(std::uint64_t) + sizeof(ReadWarning) +
                                          sizeof(std::vector<std::uint32_t>) + sizeof(RoundedCoordinate) +
                                          sizeof(std::vector<std::string>));
  if (to.rounded_coordinates == 0) to.first_rounded = from.first_rounded;  // parts come in file order
  to.rounded_coordinates += from.rounded_coordinates;
  if (to.kept_lines == 0) to.first_kept = from.first_kept;
  to.kept_lines += from.kept_lines;
  to.texcoords += from.texcoords;
  to.faces_with_texcoords += from.faces_with_texcoords;
  to.normals += from.normals;
  to.faces_with_normals += from.faces_with_normals;
  to.groups += from.groups;
  to.materials += from.materials;
  to.smoothing += from.smoothing;
  to.tags += from.tags;
  to.vertex_colors += from.vertex_colors;
  to.face_colors += from.face_colors;
  to.vertex_weights += from.vertex_weights;
  to.other_properties += from.other_properties;
  to.obj_info += from.obj_info;
}

// Appends `from` and frees it at once.
template <typename T>
void append_and_free(std::vector<T>& to, std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
  std::vector<T>().swap(from);
}
void append_and_free(Numbers& to, Numbers& from) {
  detail::append_numbers(to, from);
  from = Numbers{};
}

// Per-corner indices of parts, of which only some may have any: kInvalid for the others' corners.
void merge_corner_attribute(std::vector<ObjPart>& parts, std::vector<std::uint32_t>& (*array)(Mesh&)) {
  bool any = false;
  for (ObjPart& p : parts) any = any || !array(p.mesh).empty();
  if (!any) return;
  std::vector<std::uint32_t>& to = array(parts[0].mesh);
  to.resize(parts[0].mesh.corner_vertices.size(), kInvalid);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    std::vector<std::uint32_t>& from = array(parts[i].mesh);
    from.resize(parts[i].mesh.corner_vertices.size(), kInvalid);
    append_and_free(to, from);
  }
}

// The per-face labels of one kind over all parts: part-local names to the file's, inherited values
// resolved. `remap[i]` receives part i's name map for its statements.
void merge_labels(std::vector<ObjPart>& parts, int kind, std::vector<std::vector<std::uint32_t>>& remap) {
  remap.assign(parts.size(), {});
  bool any = false;
  for (const ObjPart& p : parts) any = any || p.labels[kind].seen;
  if (!any) return;
  FaceLabels merged;
  std::unordered_map<std::string, std::uint32_t> index;
  std::uint32_t running = kInvalid;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    FaceLabels& part = label_array(parts[i].mesh, kind);
    for (std::string& name : part.names) {
      const auto [it, added] = index.try_emplace(name, static_cast<std::uint32_t>(merged.names.size()));
      if (added) merged.names.push_back(std::move(name));
      remap[i].push_back(it->second);
    }
    if (part.face.empty()) {
      merged.face.insert(merged.face.end(), parts[i].face_count, running);
    } else {
      for (const std::uint32_t v : part.face)
        merged.face.push_back(v == kInherit ? running : v == kInvalid ? v : remap[i][v]);
    }
    const LabelReader& l = parts[i].labels[kind];
    if (l.seen && l.current != kInherit) running = remap[i][l.current];
    part = FaceLabels{};
  }
  label_array(parts[0].mesh, kind) = std::move(merged);
}

// Reads the parts between `splits` on this thread and one more, each taking the next unread part,
// and merges them in file order. Several parts rather than two halves: when the other core is busy,
// this thread reads most parts itself instead of waiting for half the file. Throws the sequential
// read's error for non-quads (quads mode; the common refusal: triangle meshes). nullopt when a part
// fails or the merge finds another problem only the whole file shows (a relative index reaching too
// far back, a repeated vertex, vertices disagreeing on colours, limits, forward indices or tag indices
// out of range): the caller re-reads sequentially, which throws the error that comes first in the
// file, with its message.
template <bool kExact>
std::optional<ObjPart> read_obj_parts(std::string_view text, std::string_view source,
                                      std::span<const std::size_t> splits) {
  const std::size_t n = splits.size() + 1;
  std::vector<ObjPart> parts(n);
  std::atomic<std::size_t> next{0};
  const auto work = [&]() noexcept {
    for (std::size_t i; (i = next.fetch_add(1)) < n;) {
      const std::size_t begin = i == 0 ? 0 : splits[i - 1];
      const std::size_t end = i + 1 == n ? text.size() : splits[i];
      try {
        ObjReader<kExact>(text.substr(begin, end - begin), source, parts[i], i != 0).run_part();
        parts[i].ok = true;
      } catch (...) {  // the sequential read decides; no need to read further
        next = n;
      }
    }
  };
  Helper worker;
  try {
    worker = start_beside(work);
  } catch (const std::system_error&) {
    return std::nullopt;  // no thread to be had: read sequentially
  }
  work();
  worker.join();

  std::uint64_t vertex_count = 0, face_count = 0, texcoord_count = 0, normal_count = 0, corner_count = 0;
  std::uint64_t line = 1;  // before the current part
  std::uint32_t max_index = 0, max_texcoord = 0, max_normal = 0;
  bool any_texcoord_ref = false, any_normal_ref = false;
  NonQuads non_quads;
  ObjPart& first = parts[0];
  std::vector<std::uint32_t> scratch;
  for (ObjPart& part : parts) {
    if (!part.ok || part.missing > vertex_count || part.missing_texcoords > texcoord_count ||
        part.missing_normals > normal_count)
      return std::nullopt;
    // Relative corners: add what came before (modulo 2^32, undoing any wrap).
    const auto add = [](std::vector<std::uint32_t>& to, const std::vector<std::uint32_t>& corners,
                        std::uint64_t base) {
      for (const std::uint32_t c : corners) to[c] += static_cast<std::uint32_t>(base);
    };
    add(part.mesh.corner_vertices, part.relative_vertex, vertex_count);
    add(part.mesh.corner_texcoords, part.relative_texcoord, texcoord_count);
    add(part.mesh.corner_normals, part.relative_normal, normal_count);
    for (const std::uint32_t f : part.relative_faces) {
      std::size_t i = 0, j = 0;
      if (repeated_corner(face_corners(part.mesh, f), scratch, i, j)) return std::nullopt;
    }
    if (&part != &first) {
      if (part.report.rounded_coordinates) part.report.first_rounded.vertex += vertex_count;
      if (line != 1) {
        for (std::uint32_t& l : part.report.face_line) l = clamp_line(l + line - 1);
        if (part.report.rounded_coordinates) part.report.first_rounded.line += line - 1;
        if (part.report.kept_lines) part.report.first_kept.line += line - 1;
        for (ReadWarning& w : part.warnings) w.line += line - 1;
        for (std::uint64_t& l : part.tag_line) l += line - 1;
      }
      if (part.vertex_extras >= 0) {
        if (first.vertex_extras >= 0 && first.vertex_extras != part.vertex_extras) return std::nullopt;
        if (first.vertex_extras < 0) {
          first.vertex_extras = part.vertex_extras;
          first.mesh.vertex_color_components = part.mesh.vertex_color_components;
        }
      }
    }
    non_quads.merge(part.non_quads, line - 1);
    vertex_count += part.vertex_count;
    face_count += part.face_count;
    texcoord_count += part.texcoord_count;
    normal_count += part.normal_count;
    corner_count += part.mesh.corner_vertices.size();
    line += part.end_line - 1;
    max_index = std::max(max_index, part.max_index);
    max_texcoord = std::max(max_texcoord, part.max_texcoord);
    max_normal = std::max(max_normal, part.max_normal);
    any_texcoord_ref = any_texcoord_ref || part.any_texcoord_ref;
    any_normal_ref = any_normal_ref || part.any_normal_ref;
  }
  if (vertex_count > kMaxVertices || face_count > kMaxFaces || corner_count > 0xFFFFFFFEu)
    return std::nullopt;

  // Texture coordinates of different lengths: all get the longest (OBJ's default 0 fills).
  std::uint8_t comps = 0;
  for (const ObjPart& p : parts) comps = std::max(comps, p.texcoord_components);
  for (ObjPart& p : parts) {
    if (p.texcoord_components != 0 && p.texcoord_components < comps)
      detail::widen_groups(p.mesh.texcoords, p.texcoord_components, comps, 0.0f);
  }
  std::vector<std::vector<std::uint32_t>> remap[4];
  for (int k = 0; k < 4; ++k) merge_labels(parts, k, remap[k]);

  // One array at a time, each part's freed as it is copied: the parts and one merged array at most
  // (reserving all three first held 45 MB more than the sequential read on a 99 MB file).
  Mesh& mesh = first.mesh;
  const auto merge = [&](auto array) {
    for (std::size_t i = 1; i < n; ++i) append_and_free(array(parts[0]), array(parts[i]));
  };
  merge([](ObjPart& p) -> Numbers& { return p.mesh.positions; });
  merge([](ObjPart& p) -> Numbers& { return p.mesh.vertex_colors; });
  merge([](ObjPart& p) -> Numbers& { return p.mesh.vertex_weights; });
  merge([](ObjPart& p) -> Numbers& { return p.mesh.texcoords; });
  merge([](ObjPart& p) -> Numbers& { return p.mesh.normals; });
  merge_corner_attribute(parts, [](Mesh& m) -> std::vector<std::uint32_t>& { return m.corner_texcoords; });
  merge_corner_attribute(parts, [](Mesh& m) -> std::vector<std::uint32_t>& { return m.corner_normals; });
  if constexpr (kExact) {
    std::uint64_t corners = mesh.corner_vertices.size();
    for (std::size_t i = 1; i < n; ++i) {
      const std::vector<std::uint32_t>& from = parts[i].mesh.face_offsets;
      for (std::size_t f = 1; f < from.size(); ++f)
        mesh.face_offsets.push_back(static_cast<std::uint32_t>(corners + from[f]));
      corners += parts[i].mesh.corner_vertices.size();
      std::vector<std::uint32_t>().swap(parts[i].mesh.face_offsets);
    }
  }
  merge([](ObjPart& p) -> std::vector<std::uint32_t>& { return p.mesh.corner_vertices; });
  merge([](ObjPart& p) -> std::vector<std::uint32_t>& { return p.report.face_line; });
  merge([](ObjPart& p) -> std::vector<std::string>& { return p.mesh.comments; });
  merge([](ObjPart& p) -> std::vector<std::string>& { return p.mesh.verbatim; });
  merge([](ObjPart& p) -> std::vector<std::string>& { return p.mesh.material_libraries; });
  merge([](ObjPart& p) -> std::vector<Tag>& { return p.mesh.tags; });
  merge([](ObjPart& p) -> std::vector<std::uint64_t>& { return p.tag_line; });
  std::vector<Statement> statements;
  for (std::size_t i = 0; i < n; ++i) {
    for (Statement s : parts[i].mesh.statements) {
      if (!is_run(s.kind)) {
        const int k = static_cast<int>(s.kind) - static_cast<int>(ObjStatement::kObject);
        s.value = remap[k][i][s.value];
        statements.push_back(s);
      } else {
        add_run(statements, s.kind, s.value);
      }
    }
  }
  mesh.statements = std::move(statements);
  mesh.texcoord_components = comps ? comps : 2;
  first.texcoord_components = comps;
  for (std::size_t i = 1; i < n; ++i) {
    add_counts(first.report, parts[i].report);
    for (ReadWarning& w : parts[i].warnings) {
      if (first.warnings.size() < ReadNotes::kMaxWarnings) first.warnings.push_back(std::move(w));
    }
    first.warning_count += parts[i].warning_count;
  }
  if constexpr (!kExact) {
    // Nothing above failed, so the sequential read would reach its end and refuse non-quads there,
    // with the report complete.
    non_quads.throw_if_any(source);
  }
  if (face_count != 0 && max_index >= vertex_count) return std::nullopt;
  if (any_texcoord_ref && max_texcoord >= texcoord_count) return std::nullopt;
  if (any_normal_ref && max_normal >= normal_count) return std::nullopt;
  for (std::size_t i = 0; i < mesh.tags.size(); ++i) {
    const TagIndices kind = tag_indices(mesh.tags[i].name);
    const std::uint64_t limit = kind == TagIndices::kFaces ? face_count : vertex_count;
    if (kind == TagIndices::kNone || kind == TagIndices::kUnknown) continue;
    for (const std::int64_t x : mesh.tags[i].ints) {
      if (x < 0 || static_cast<std::uint64_t>(x) >= limit) return std::nullopt;
    }
  }
  first.vertex_count = vertex_count;
  first.face_count = face_count;
  return std::move(first);
}

// The file read sequentially, or split at `splits` (see read_obj_split).
template <bool kExact>
ObjPart read_obj_text(std::string_view text, std::string_view source, std::span<const std::size_t> splits,
                      bool* parallel) {
  std::size_t previous = 0;
  bool valid = !splits.empty();
  for (const std::size_t split : splits) {
    valid = valid && split > previous && detail::obj_split_point(text, split - 1) == split;
    previous = split;
  }
  if (parallel) *parallel = valid;  // also when read_obj_parts throws
  if (valid) {
    if (std::optional<ObjPart> part = read_obj_parts<kExact>(text, source, splits)) return std::move(*part);
    if (parallel) *parallel = false;
  }
  ObjPart part;
  ObjReader<kExact>(text, source, part).run();
  return part;
}

// ----------------------------------------------------------------------------------------------
// OFF

template <bool kExact>
class OffReader {
 public:
  OffReader(std::string_view text, std::string_view source, ReadReport& report)
      : in_(text, source), source_(source), report_(report) {}

  Mesh run() {
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
    if constexpr (!kExact) non_quads_.throw_if_any(source_);
    if constexpr (kExact) {
      // Per-vertex normals and texture coordinates: each corner has its vertex's.
      if (has_normals_) mesh_.corner_normals = mesh_.corner_vertices;
      if (has_texcoords_) mesh_.corner_texcoords = mesh_.corner_vertices;
      if (mesh_.face_offsets.empty()) mesh_.face_offsets.push_back(0);
    }
    return std::move(mesh_);
  }

 private:
  // Skips blank lines and comment lines (and blanks at the current position), keeping comments.
  void skip_empty() {
    for (;;) {
      in_.skip_blank();
      if (in_.done() || !in_.at_eol()) return;
      if constexpr (kExact) {
        if (in_.peek() == '#') mesh_.comments.emplace_back(in_.comment_text());
      }
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
    mesh_.positions.f32.reserve(3 * vertex_count_);
    mesh_.corner_vertices.reserve(4 * face_count_);
    report_.face_line.reserve(face_count_);
    if constexpr (kExact) {
      mesh_.face_offsets.reserve(face_count_ + 1);
      mesh_.face_offsets.push_back(0);
      if (has_texcoords_) mesh_.texcoord_components = 2;
    }
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
      TextNumber x[12];
      const std::uint64_t n = read_numbers<kExact>(in_, x, "an OFF vertex");
      if (n < base || n > most) {
        const std::string want =
            base == most ? std::to_string(base) : std::to_string(base) + " or " + std::to_string(most);
        in_.fail(ErrorCode::kParse, "vertex " + std::to_string(v) + " has " + plural(n, "number", "numbers") +
                                        ", expected " + want + counts_hint());
      }
      if constexpr (kExact) {
        for (int i = 0; i < 3; ++i) detail::push_text(mesh_.positions, x[i]);
        std::size_t at = 3;
        if (has_normals_) {
          for (int i = 0; i < 3; ++i) detail::push_text(mesh_.normals, x[at++]);
        }
        if (has_colors_) {
          const auto c = static_cast<std::uint8_t>(n - base + 3);
          if (mesh_.vertex_color_components != c && v > 0) {
            in_.fail(ErrorCode::kUnsupported,
                     "vertex " + std::to_string(v) + " has " + std::to_string(c) +
                         " colour components, vertex 0 " + std::to_string(mesh_.vertex_color_components) +
                         "; qsp keeps vertex colours only when every vertex has the same number");
          }
          mesh_.vertex_color_components = c;
          for (int i = 0; i < c; ++i) detail::push_text(mesh_.vertex_colors, x[at++]);
        }
        if (has_texcoords_) {
          for (int i = 0; i < 2; ++i) detail::push_text(mesh_.texcoords, x[at++]);
        }
      } else {
        for (int i = 0; i < 3; ++i) {
          mesh_.positions.f32.push_back(x[i].f);
          if (!detail::float32_by_digits(x[i]) && !detail::float32_holds(x[i])) [[unlikely]]
            report_.note_rounded(
                in_.line(), v, std::string_view(x[i].begin, static_cast<std::size_t>(x[i].end - x[i].begin)),
                x[i].f);
        }
      }
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
      corners_.clear();
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
        if (kExact || i < 4) corners_.push_back(index);
      }
      in_.skip_blank();
      std::uint64_t c = 0;
      TextNumber color[4];
      if (!in_.at_eol()) {
        c = read_numbers<kExact>(in_, color, "an OFF face colour");
        if (c != 1 && c != 3 && c != 4) {
          in_.fail(ErrorCode::kParse, "face " + std::to_string(f) + " has " + plural(c, "number", "numbers") +
                                          " after its indices; expected a colour (1, 3 or 4 numbers)" +
                                          counts_hint());
        }
        ++report_.face_colors;
      }
      in_.finish_line();
      if (!kExact && n != 4) {
        non_quads_.add(line, static_cast<std::uint64_t>(n));
        continue;
      }
      if (kExact && n < 3) {
        in_.fail(ErrorCode::kDegenerateFace, line,
                 "face has " + corners_name(static_cast<std::uint64_t>(n)) +
                     "; a face needs at least 3 distinct vertices");
      }
      std::size_t i = 0, j = 0;
      if (repeated_corner(corners_, scratch_, i, j)) {
        in_.fail(ErrorCode::kDegenerateFace, line, repeat_message(corners_[i], i, j, corners_.size()));
      }
      if constexpr (kExact) {
        if (mesh_.corner_vertices.size() + corners_.size() > 0xFFFFFFFEu)
          in_.fail(ErrorCode::kLimit, line, "more than 2^32 - 2 face corners");
        if (f > 0 && c != mesh_.face_color_components) {
          in_.fail(ErrorCode::kUnsupported, line,
                   "face " + std::to_string(f) + " has " + plural(c, "colour number", "colour numbers") +
                       ", face 0 " + std::to_string(mesh_.face_color_components) +
                       "; qsp keeps face colours only when every face has the same number");
        }
        mesh_.face_color_components = static_cast<std::uint8_t>(c);
        for (std::uint64_t k = 0; k < c; ++k) detail::push_text(mesh_.face_colors, color[k]);
        mesh_.corner_vertices.insert(mesh_.corner_vertices.end(), corners_.begin(), corners_.end());
        mesh_.face_offsets.push_back(static_cast<std::uint32_t>(mesh_.corner_vertices.size()));
      } else {
        mesh_.corner_vertices.insert(mesh_.corner_vertices.end(), corners_.begin(), corners_.end());
      }
      report_.face_line.push_back(clamp_line(line));
    }
  }

 private:
  Scanner in_;
  std::string_view source_;
  ReadReport& report_;
  Mesh mesh_;
  NonQuads non_quads_;
  bool has_normals_ = false, has_colors_ = false, has_texcoords_ = false;
  std::uint64_t vertex_count_ = 0, face_count_ = 0, counts_line_ = 0;
  std::vector<std::uint32_t> corners_, scratch_;
};

// The QuadMesh of a quads-mode read (positions are float32 only, faces quads only).
QuadMesh quad_mesh(Mesh&& m) {
  QuadMesh q;
  q.positions = std::move(m.positions.f32);
  q.quads = std::move(m.corner_vertices);
  return q;
}

void set_notes(ReadNotes* notes, ReadReport& report, std::vector<ReadWarning>&& warnings,
               std::uint64_t count) {
  if (!notes) return;
  notes->face_line = std::move(report.face_line);
  notes->warnings = std::move(warnings);
  notes->warning_count = count;
  notes->counts = std::move(report);
  notes->counts.face_line = {};
  notes->has_counts = true;
}

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
  r = ReadReport{};
  ObjPart part = read_obj_text<false>(text, source, splits, parallel);
  r = std::move(part.report);
  return quad_mesh(std::move(part.mesh));
}

Mesh read_obj_mesh_split(std::string_view text, std::string_view source, ReadNotes* notes,
                         std::span<const std::size_t> splits, bool* parallel) {
  if (notes) *notes = ReadNotes{};
  ObjPart part = read_obj_text<true>(text, source, splits, parallel);
  set_notes(notes, part.report, std::move(part.warnings), part.warning_count);
  if (part.mesh.face_offsets.empty()) part.mesh.face_offsets.push_back(0);
  return std::move(part.mesh);
}

}  // namespace detail

namespace {
// read_obj's splits: none on one core, where a second thread only costs.
std::vector<std::size_t> splits_for(std::string_view text) {
  std::vector<std::size_t> splits = detail::obj_read_splits(text);
  if (!splits.empty() && !threads_allowed()) splits.clear();
  return splits;
}
}  // namespace

namespace {
// The leading comment block, for a report (read_obj, read_off).
void note_leading_comments(std::string_view text, ReadReport* report) {
  if (report == nullptr) return;
  report->leading_comments = leading_comments(text);
  report->comments = report->leading_comments.size();
}
}  // namespace

QuadMesh read_obj(std::string_view text, std::string_view source, ReadReport* report) {
  QuadMesh m = detail::read_obj_split(text, source, report, splits_for(text), nullptr);
  note_leading_comments(text, report);
  return m;
}

Mesh read_obj_mesh(std::string_view text, std::string_view source, ReadNotes* notes) {
  return detail::read_obj_mesh_split(text, source, notes, splits_for(text), nullptr);
}

QuadMesh read_off(std::string_view text, std::string_view source, ReadReport* report) {
  ReadReport local;
  ReadReport& r = report ? *report : local;
  r = ReadReport{};
  QuadMesh m = quad_mesh(OffReader<false>(text, source, r).run());
  note_leading_comments(text, report);
  return m;
}

Mesh read_off_mesh(std::string_view text, std::string_view source, ReadNotes* notes) {
  ReadReport r;
  Mesh m = OffReader<true>(text, source, r).run();
  set_notes(notes, r, {}, 0);
  return m;
}

std::string ReadNotes::describe_warnings(std::string_view source) const {
  std::string out;
  for (const ReadWarning& w : warnings) {
    out += std::string(source) + ":" + std::to_string(w.line) + ": " + w.message + "\n";
  }
  if (warning_count > warnings.size())
    out += std::string(source) + ": (and " + std::to_string(warning_count - warnings.size()) + " more)\n";
  return out;
}

}  // namespace qsp
