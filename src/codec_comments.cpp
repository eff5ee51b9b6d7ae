// The comments and kept lines sections (format-spec/qsp_format.md, "Comments section", "Kept lines
// section"): the leading comment block of the mesh file a .qsp was made from, kept so that licence and
// copyright lines survive a round trip, and the OBJ lines qsp keeps only as text. Both are a list of lines.
#include <algorithm>
#include <string>
#include <vector>

#include "bytes.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp {
namespace {

bool breaks_line(char c) { return c == '\n' || c == '\r'; }

std::string lines_payload(const std::vector<std::string>& lines) {
  std::string payload;
  put_varint(payload, lines.size());
  for (const std::string& line : lines) {
    put_varint(payload, line.size());
    payload += line;
  }
  return payload;
}

// The lines of a section's payload, each checked by `problem` (empty when fine): `what` names one line.
std::vector<std::string> read_lines(std::string_view payload, std::uint64_t offset, const char* section,
                                    const std::string& what, std::string (*problem)(std::string_view line)) {
  ByteReader in(payload, offset, section);
  const std::uint64_t count = in.varint("line count");
  // Every line costs at least its length byte: a count past the bytes left is refused unallocated.
  if (count == 0 || count > in.left())
    in.fail("line count " + std::to_string(count) + " is not 1 to the " + std::to_string(in.left()) +
            " bytes left");
  std::vector<std::string> lines;
  lines.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t at = in.offset();
    const std::string_view line = in.take(in.varint("line length"), what.c_str());
    if (const std::string why = problem(line); !why.empty())
      in.fail_at(what + " " + std::to_string(i) + " " + why, at);
    lines.emplace_back(line);
  }
  if (in.left() != 0) in.fail(std::to_string(in.left()) + " bytes after the last line");
  return lines;
}

std::string comment_problem(std::string_view line) {
  return std::any_of(line.begin(), line.end(), breaks_line) ? "holds a line break" : "";
}

// lines_payload of lines `problem` accepts; Error(kUsage) naming the first it does not (`what` names one).
std::string checked_payload(const std::vector<std::string>& lines, const char* what,
                            std::string (*problem)(std::string_view line)) {
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (const std::string why = problem(lines[i]); !why.empty())
      throw Error(ErrorCode::kUsage, "encode: " + std::string(what) + " " + std::to_string(i) + " " + why);
  return lines_payload(lines);
}

}  // namespace

std::string kept_line_problem(std::string_view line) {
  if (line.empty()) return "is empty";
  if (std::any_of(line.begin(), line.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20 && c != '\t'; }))
    return "holds a control byte";
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  if (blank(line.front()) || line.front() == '#') return "starts with a space, a tab or '#'";
  if (blank(line.back()) || line.back() == '\\') return "ends with a space, a tab or a backslash";
  const std::string_view word =
      line.substr(0, static_cast<std::size_t>(std::find_if(line.begin(), line.end(), blank) - line.begin()));
  for (const std::string_view k :
       {"v", "vt", "vn", "f", "l", "p", "o", "g", "s", "t", "usemtl", "mtllib", "curv", "curv2", "surf"})
    if (word == k) return "reads as a `" + std::string(k) + "` statement";
  return "";
}

std::string with_comments(std::string_view file, const std::vector<std::string>& lines) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (!comment_problem(lines[i]).empty())
      throw Error(ErrorCode::kUsage, "comment line " + std::to_string(i) + " holds a line break");
  }
  if (!lines.empty()) return container::with_section(file, container::kTagComments, lines_payload(lines), 1);
  const container::File f = container::parse(file);
  std::string body;
  for (const container::Section& s : f.sections)
    if (s.tag != container::kTagComments) container::put_section(body, s.tag, s.payload);
  return container::seal(f.major, f.minor, f.level, body);
}

std::vector<std::string> file_comments(std::string_view bytes) {
  const container::File f = container::parse(bytes);
  const container::Section* s = f.find(container::kTagComments);
  if (s == nullptr) return {};
  return read_lines(s->payload, s->payload_offset, "comments section", "comment line", comment_problem);
}

std::string encode_kept_lines_section(const std::vector<std::string>& lines) {
  return checked_payload(lines, "kept line", kept_line_problem);
}

std::vector<std::string> decode_kept_lines_section(std::string_view payload, std::uint64_t offset) {
  return read_lines(payload, offset, "kept lines section", "kept line", kept_line_problem);
}

std::string encode_ply_info_section(const std::vector<std::string>& lines) {
  return checked_payload(lines, "PLY obj_info line", comment_problem);
}

std::vector<std::string> decode_ply_info_section(std::string_view payload, std::uint64_t offset) {
  return read_lines(payload, offset, "PLY obj_info lines section", "obj_info line", comment_problem);
}

}  // namespace qsp
