// The comments section (0x81, format 3.1): the leading comment block of the mesh file, kept in the
// .qsp and given back; hostile sections refused with kFormat, never a line break written into text.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"

namespace qsp {
namespace {

QuadMesh square() {
  QuadMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.quads = {0, 1, 2, 3};
  return m;
}

// `payload` as the comments section of the square's file.
std::string with_section(const std::string& payload) {
  const std::string bare = encode(square());
  const container::File f = container::parse(bare);
  std::string body;
  for (const container::Section& s : f.sections) container::put_section(body, s.tag, s.payload);
  container::put_section(body, container::kTagComments, payload);
  return container::seal(f.major, 1, f.level, body);
}

ErrorCode refusal(const std::string& bytes) {
  try {
    (void)file_comments(bytes);
  } catch (const Error& e) {
    return e.code();
  }
  return ErrorCode::kInternal;  // not refused
}

TEST(Comments, KeptBesideTheMeshWhichDecodesAsBefore) {
  const std::string bare = encode(square());
  const std::vector<std::string> lines{" licence: CC0", "", "\tCopyright (C) 2020 \xC3\xA9"};
  const std::string file = with_comments(bare, lines);
  EXPECT_EQ(file_comments(file), lines);
  EXPECT_EQ(file_comments(bare), std::vector<std::string>{});
  EXPECT_EQ(decode(file).quads, decode(bare).quads);
  EXPECT_EQ(decode(file).positions, decode(bare).positions);
  EXPECT_EQ(inspect(file).version_minor, 1);
  EXPECT_EQ(inspect(bare).version_minor, 0);
  EXPECT_EQ(file_comments(with_comments(file, {})), std::vector<std::string>{});  // replaced: none left
  EXPECT_EQ(decode(with_comments(file, {})).quads, decode(bare).quads);
  EXPECT_EQ(file_comments(with_comments(file, {"x"})), std::vector<std::string>{"x"});
  EXPECT_EQ(write_obj(decode(file), file_comments(file)).rfind("# licence: CC0\n#\n#\tCopyright", 0), 0u);
}

TEST(Comments, ALineBreakIsNeverStoredNorRead) {
  const std::string bare = encode(square());
  for (const std::string bad : {"a\nv 9 9 9", "a\r", "\n"}) {
    EXPECT_THROW((void)with_comments(bare, {"ok", bad}), Error);
    // Crafted: one line holding a line break would write a statement into the decompressed OBJ.
    std::string payload = "\x01";
    payload += static_cast<char>(bad.size());
    payload += bad;
    EXPECT_EQ(refusal(with_section(payload)), ErrorCode::kFormat) << bad;
  }
}

TEST(Comments, CountsAndLengthsAreCheckedAgainstTheBytesLeft) {
  EXPECT_EQ(refusal(with_section(std::string("\x00", 1))), ErrorCode::kFormat);  // no lines: never written
  EXPECT_EQ(refusal(with_section("\x05"
                                 "ab")),
            ErrorCode::kFormat);                                                 // 5 lines in 2 bytes
  EXPECT_EQ(refusal(with_section("\xFF\xFF\xFF\xFF\x0F")), ErrorCode::kFormat);  // a huge count, unallocated
  EXPECT_EQ(refusal(with_section("\x01\x09"
                                 "abc")),
            ErrorCode::kFormat);  // a line past the end
  EXPECT_EQ(refusal(with_section("\x01\x01"
                                 "ab")),
            ErrorCode::kFormat);  // a byte left over
  EXPECT_EQ(file_comments(with_section(std::string("\x02\x01"
                                                   "a\x00",
                                                   4))),
            (std::vector<std::string>{"a", ""}));
}

// Every bit flip and every cut of a commented file's comments section, resealed so the checksum
// does not hide it: refused with kFormat, or read as lines without a line break. Every prefix of the
// whole file is refused.
TEST(Comments, EveryFlipAndCutIsRefusedOrClean) {
  const std::string file = with_comments(encode(square()), {" licence", "more", ""});
  const container::File parsed = container::parse(file);  // its sections point into `file`
  const container::Section* s = parsed.find(container::kTagComments);
  ASSERT_NE(s, nullptr);
  const std::string payload(s->payload);
  auto check = [](const std::string& bytes) {
    try {
      for (const std::string& line : file_comments(bytes))
        EXPECT_EQ(line.find_first_of("\r\n"), std::string::npos);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat) << e.what();
    }
  };
  for (std::size_t i = 0; i < payload.size() * 8; ++i) {
    std::string p = payload;
    p[i / 8] = static_cast<char>(p[i / 8] ^ (1 << (i % 8)));
    check(with_section(p));
  }
  for (std::size_t n = 0; n < payload.size(); ++n) check(with_section(payload.substr(0, n)));
  for (std::size_t n = 0; n < file.size(); ++n) EXPECT_THROW((void)file_comments(file.substr(0, n)), Error);
}

TEST(Comments, TheLeadingBlockOfText) {
  EXPECT_EQ(leading_comments("\xEF\xBB\xBF# a\r\n\n  #b\r# c\nv 0 0 0\n# later\n"),
            (std::vector<std::string>{" a", "b", " c"}));
  EXPECT_EQ(leading_comments("OFF\n# tool\n3 1 0\n"), std::vector<std::string>{" tool"});
  EXPECT_EQ(leading_comments("v 0 0 0\n# later\n"), std::vector<std::string>{});
  EXPECT_EQ(leading_comments("OFF 3 1 0\n# x\n"), std::vector<std::string>{});  // not a keyword line
  EXPECT_EQ(leading_comments(""), std::vector<std::string>{});
}

}  // namespace
}  // namespace qsp
