// The comments section (format-spec/qsp_format.md, "Comments section"): the leading comment block of
// the mesh file a .qsp was made from, kept so that licence and copyright lines survive a round trip.
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

}  // namespace

std::string with_comments(std::string_view file, const std::vector<std::string>& lines) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (std::any_of(lines[i].begin(), lines[i].end(), breaks_line))
      throw Error(ErrorCode::kUsage, "comment line " + std::to_string(i) + " holds a line break");
  }
  const container::File f = container::parse(file);
  std::string body;
  for (const container::Section& s : f.sections)
    if (s.tag != container::kTagComments) container::put_section(body, s.tag, s.payload);
  std::uint8_t minor = f.minor;
  if (!lines.empty()) {
    std::string payload;
    put_varint(payload, lines.size());
    for (const std::string& line : lines) {
      put_varint(payload, line.size());
      payload += line;
    }
    container::put_section(body, container::kTagComments, payload);
    minor = std::max(minor, std::uint8_t{1});
  }
  return container::seal(f.major, minor, f.level, body);
}

std::vector<std::string> file_comments(std::string_view bytes) {
  const container::File f = container::parse(bytes);
  const container::Section* s = f.find(container::kTagComments);
  if (s == nullptr) return {};
  ByteReader in(s->payload, s->payload_offset, "comments section");
  const std::uint64_t count = in.varint("line count");
  // Every line costs at least its length byte: a count past the bytes left is refused unallocated.
  if (count == 0 || count > in.left())
    in.fail("line count " + std::to_string(count) + " is not 1 to the " + std::to_string(in.left()) +
            " bytes left");
  std::vector<std::string> lines;
  lines.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    const std::uint64_t at = in.offset();
    const std::string_view line = in.take(in.varint("line length"), "comment line");
    if (std::any_of(line.begin(), line.end(), breaks_line))
      in.fail_at("comment line " + std::to_string(i) + " holds a line break", at);
    lines.emplace_back(line);
  }
  if (in.left() != 0) in.fail(std::to_string(in.left()) + " bytes after the last comment line");
  return lines;
}

}  // namespace qsp
