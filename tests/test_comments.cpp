// The comments section (0x81, format 3.1) and the coded comments section (0x85, format 3.16): the
// leading comment block of the mesh file, kept in the .qsp (in whichever is smaller) and given back;
// hostile sections refused with kFormat, never a line break written into text.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"
#include "qsp/io.h"
#include "qsp/polymesh.h"
#include "support/corpus.h"
#include "support/files.h"

namespace qsp {
namespace {

QuadMesh square() {
  QuadMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  m.quads = {0, 1, 2, 3};
  return m;
}

// `payload` as the comments section (or `tag`'s) of the square's file, of minor version `minor`.
std::string with_section(const std::string& payload, std::uint8_t tag = container::kTagComments,
                         std::uint8_t minor = 1) {
  const std::string bare = encode(square());
  const container::File f = container::parse(bare);
  std::string body;
  for (const container::Section& s : f.sections) container::put_section(body, s.tag, s.payload);
  container::put_section(body, tag, payload);
  return container::seal(f.major, minor, f.level, body);
}

std::string with_coded(const std::string& payload) {
  return with_section(payload, container::kTagCodedComments, kFormatMinorCodedComments);
}

// A file with the coded comments section `payload` and, before it, a comments section of one line.
std::string beside_comments(const std::string& payload) {
  const std::string coded = with_coded(payload);  // the sections' payloads are views into it
  const container::File f = container::parse(coded);
  std::string body;
  for (const container::Section& s : f.sections) {
    if (s.tag == container::kTagCodedComments)
      container::put_section(body, container::kTagComments, "\x01\x01x");
    container::put_section(body, s.tag, s.payload);
  }
  return container::seal(f.major, f.minor, f.level, body);
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
  // Whichever section is smaller: 3.1's plain lines or 3.16's coded ones.
  EXPECT_EQ(inspect(file).version_minor,
            container::parse(file).find(container::kTagCodedComments) ? kFormatMinorCodedComments : 1);
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
  const std::string payload("\x03\x08 licence\x04more\x00", 16);
  const std::string file = with_section(payload);
  ASSERT_EQ(file_comments(file), (std::vector<std::string>{" licence", "more", ""}));
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

namespace qsp {
namespace {

// The leading comment block of an OBJ or OFF text, read here without qsp's reader: the text after '#'
// of each comment line (a CR before the LF dropped) from the start, after an OFF keyword line, skipping
// blank lines, up to the first other line.
std::vector<std::string> leading_block(const std::string& text) {
  std::vector<std::string> out;
  std::size_t at = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  bool first = true;
  while (at < text.size()) {
    std::size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    at = end + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t lead = line.find_first_not_of(" \t");
    const bool keyword = first && lead != std::string::npos && line.find_last_not_of(" \t") - lead + 1 >= 3 &&
                         line.substr(line.find_last_not_of(" \t") - 2, 3) == "OFF" &&
                         line.find_first_of(" \t0123456789", lead) == std::string::npos;
    first = false;
    if (keyword || lead == std::string::npos) continue;
    if (line[lead] != '#') break;
    out.push_back(line.substr(lead + 1));
  }
  return out;
}

bool breaks(char c) { return c == '\n' || c == '\r'; }

// Every leading comment block of testdata's and the shared meshes' OBJ and OFF files, read here: the
// same lines back through the coded section alone, and through with_comments (one section of the two).
TEST(CodedComments, EveryLeadingBlockOfTheCorpusRoundTrips) {
  const std::string bare = encode(square());
  int blocks = 0, coded = 0;
  for (const std::filesystem::path& path : testing::corpus()) {
    const std::string ext = path.extension().string();
    if (ext != ".obj" && ext != ".off") continue;
    const std::vector<std::string> lines = leading_block(testing::slurp(path.string()));
    if (lines.empty()) continue;
    SCOPED_TRACE(path.string());
    ++blocks;
    EXPECT_EQ(decode_coded_comments_section(encode_coded_comments_section(lines), 0), lines);
    const std::string file = with_comments(bare, lines);
    EXPECT_EQ(file_comments(file), lines);
    const container::File f = container::parse(file);
    EXPECT_NE((f.find(container::kTagComments) != nullptr),
              (f.find(container::kTagCodedComments) != nullptr));
    coded += f.find(container::kTagCodedComments) != nullptr;
  }
  EXPECT_GE(blocks, 1);
  if (testing::shared_present()) {
    EXPECT_GE(blocks, 40);
    EXPECT_GE(coded, 40);
  }
}

// MakeHuman's licence block: the coded section, and it is much smaller than the plain lines.
TEST(CodedComments, TheSmallerSectionIsWrittenNeverBoth) {
  QSP_NEEDS_SHARED();
  const std::vector<std::string> licence =
      leading_block(testing::slurp((testing::shared_dir() / "meshes" / "mh_fedora.obj").string()));
  ASSERT_EQ(licence.size(), 16u);
  const std::string bare = encode(square());
  const std::string file = with_comments(bare, licence);
  const container::File f = container::parse(file);
  ASSERT_NE(f.find(container::kTagCodedComments), nullptr);
  EXPECT_EQ(f.find(container::kTagComments), nullptr);
  EXPECT_EQ(inspect(file).version_minor, kFormatMinorCodedComments);
  EXPECT_LE(file.size() - bare.size(), 280u) << "527 text bytes; deflate -9 gives 301";
  EXPECT_EQ(inspect(file).comment_bytes, f.find(container::kTagCodedComments)->size());
  EXPECT_EQ(inspect(file).other_bytes, 0u);
  EXPECT_EQ(decode(file).quads, decode(bare).quads);
  // Replacing: bytes without a pattern go plain (coded, each costs more than its 8 bits while the
  // models learn), and the coded section is gone.
  std::string noise;
  for (std::uint32_t x = 1; noise.size() < 200; x = x * 1103515245u + 12345u)
    if (const char c = static_cast<char>(x >> 23); !breaks(c)) noise += c;
  const std::string plain = with_comments(file, {noise});
  EXPECT_EQ(container::parse(plain).find(container::kTagCodedComments), nullptr);
  EXPECT_EQ(file_comments(plain), std::vector<std::string>{noise});
  EXPECT_EQ(inspect(plain).version_minor, kFormatMinorPolygons) << "3.16 was the coded section's";
  EXPECT_EQ(file_comments(with_comments(file, {})), std::vector<std::string>{});
  EXPECT_EQ(inspect(with_comments(file, {})).version_minor, kFormatMinorQuads);
  EXPECT_EQ(container::parse(with_comments(file, {})).sections.size(),
            container::parse(bare).sections.size());
}

TEST(CodedComments, EmptyLinesAndOneEmptyLine) {
  for (const std::vector<std::string>& lines :
       {std::vector<std::string>{""}, std::vector<std::string>{"", ""},
        std::vector<std::string>{"a", "", "b"}}) {
    EXPECT_EQ(decode_coded_comments_section(encode_coded_comments_section(lines), 0), lines);
    EXPECT_EQ(file_comments(with_coded(encode_coded_comments_section(lines))), lines);
  }
}

TEST(CodedComments, HostileSectionsAreRefused) {
  const std::vector<std::string> lines{" Copyright (C) 2020 somebody", " Copyright (C) 2021 somebody else"};
  const std::string payload = encode_coded_comments_section(lines);
  ASSERT_EQ(file_comments(with_coded(payload)), lines);
  // A stream cut short (refused, or other symbols: a shorter stream may be another text's), or one
  // byte longer.
  for (std::size_t n = 0; n < payload.size(); ++n) {
    try {
      EXPECT_NE(file_comments(with_coded(payload.substr(0, n))), lines) << n;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat) << e.what();
    }
  }
  EXPECT_EQ(refusal(with_coded(payload.substr(0, payload.size() - 3))), ErrorCode::kFormat);
  EXPECT_EQ(refusal(with_coded(payload + '\x01')), ErrorCode::kFormat);
  // A text length past what the stream can hold: refused before the text is allocated.
  std::string huge;
  put_varint(huge, std::uint64_t{1} << 40);
  EXPECT_EQ(refusal(with_coded(huge + payload.substr(1))), ErrorCode::kFormat);
  // A CR (which the encoder codes as any byte) decoded inside a line.
  EXPECT_EQ(refusal(with_coded(encode_coded_comments_section({"a\rb"}))), ErrorCode::kFormat);
  // In a file of 3.15, and beside a comments section.
  EXPECT_EQ(refusal(with_section(payload, container::kTagCodedComments, 15)), ErrorCode::kFormat);
  EXPECT_EQ(refusal(beside_comments(payload)), ErrorCode::kFormat);
}

// `run` throws Error(kFormat) whose message holds `message` and ends at byte offset `at`.
template <typename Run>
void expect_refused(Run run, const std::string& message, std::uint64_t at) {
  try {
    run();
    ADD_FAILURE() << "not refused: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    const std::string what = e.what();
    EXPECT_NE(what.find(message), std::string::npos) << what;
    EXPECT_NE(what.find("(at byte offset " + std::to_string(at) + ")"), std::string::npos) << what;
  }
}

// The text's limits (2^20 bytes, 2^16 lines): lines within them are coded, lines past them go to the
// comments section, and a coded section past them is refused, its length before anything is allocated.
TEST(CodedComments, LimitsBoundTheTextAndItsLines) {
  const std::string bare = encode(square());
  const auto kept_in = [&](const std::vector<std::string>& lines, std::uint8_t tag) {
    const std::string file = with_comments(bare, lines);
    EXPECT_NE(container::parse(file).find(tag), nullptr);
    EXPECT_EQ(file_comments(file), lines);
  };
  const std::size_t most_lines = kCodedCommentsMaxLines, most_bytes = kCodedCommentsMaxText;
  kept_in(std::vector<std::string>(most_lines), container::kTagCodedComments);
  kept_in(std::vector<std::string>(most_lines + 1), container::kTagComments);
  kept_in({std::string(most_bytes - 1, 'a'), ""}, container::kTagCodedComments);
  kept_in({std::string(most_bytes / 2, 'a'), std::string(most_bytes / 2, 'a')}, container::kTagComments);
  kept_in({std::string(most_bytes + 1, 'a')}, container::kTagComments);

  // Refused: 2^16 + 1 lines, at the LF that begins the last (the stream decoded so far), and a text
  // length past 2^20, after it.
  const std::string many = encode_coded_comments_section(std::vector<std::string>(most_lines + 1));
  try {
    (void)decode_coded_comments_section(many, 1000);
    ADD_FAILURE() << "2^16 + 1 lines not refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kFormat);
    const std::string what = e.what();
    EXPECT_NE(what.find("the text's byte 65535 begins line 65537, past the format's 65536 lines"),
              std::string::npos)
        << what;
    const std::size_t at = what.find("(at byte offset ");
    ASSERT_NE(at, std::string::npos) << what;
    const std::uint64_t offset = std::stoull(what.substr(at + 16));
    EXPECT_GE(offset, 1000u) << what;
    // Where the range decoder has read to, which counts the (up to 4) bytes it reads past a compact end.
    EXPECT_LE(offset, 1000u + many.size() + 4) << what;
  }
  EXPECT_EQ(refusal(with_coded(many)), ErrorCode::kFormat);
  // A text length past 2^20 with a stream that could hold it (past 1016 bytes): refused after the length.
  std::string past;
  put_varint(past, kCodedCommentsMaxText + 1);
  const std::string stream = encode_coded_comments_section({" licence"}).substr(1) + std::string(2000, 'x');
  const std::string message = "text length 1048577 is more than the format's 1048576 bytes";
  expect_refused([&] { (void)decode_coded_comments_section(past + stream, 100); }, message,
                 100 + past.size());
  const std::string file = with_coded(past + stream);
  expect_refused([&] { (void)file_comments(file); }, message,
                 file.size() - container::kChecksumBytes - stream.size());
}

// A file holding both comments sections is refused wherever the container is read, at the coded one.
TEST(CodedComments, BothSectionsAreRefusedByEveryReader) {
  const std::string payload = encode_coded_comments_section({" Copyright (C) 2020 somebody"});
  const std::string both = beside_comments(payload);
  // The coded section is the last: its tag, length and payload before the checksum.
  const std::uint64_t at =
      both.size() - container::kChecksumBytes - (1 + varint_size(payload.size()) + payload.size());
  const std::string message = "section 0x85 (coded comments) beside section 0x81 (comments)";
  expect_refused([&] { (void)container::parse(both); }, message, at);
  expect_refused([&] { (void)decode(both); }, message, at);
  expect_refused([&] { (void)inspect(both); }, message, at);
  expect_refused([&] { (void)file_comments(both); }, message, at);
  expect_refused([&] { (void)with_comments(both, {}); }, message, at);
}

// with_comments writes the lowest minor version the file's sections need: 3.16 only with the coded
// section, and never more than the file said (nor less than a file of a later minor, or one holding a
// section this qsp does not know, said).
TEST(CodedComments, TheMinorVersionIsTheSectionsOwn) {
  const std::vector<std::string> licence(20, " Copyright (C) 2020 somebody, all rights reserved");
  const std::string bare = encode(square());
  ASSERT_EQ(inspect(bare).version_minor, kFormatMinorQuads);
  const std::string coded = with_comments(bare, licence);
  ASSERT_NE(container::parse(coded).find(container::kTagCodedComments), nullptr);
  EXPECT_EQ(inspect(coded).version_minor, kFormatMinorCodedComments);
  EXPECT_EQ(inspect(with_comments(coded, {})).version_minor, kFormatMinorQuads);
  EXPECT_EQ(with_comments(coded, {}), bare);
  // Bytes without a pattern go plain (coded, each costs more than its 8 bits while the models learn).
  std::string noise;
  for (std::uint32_t x = 1; noise.size() < 200; x = x * 1103515245u + 12345u)
    if (const char c = static_cast<char>(x >> 23); c != '\n' && c != '\r') noise += c;
  ASSERT_NE(container::parse(with_comments(coded, {noise})).find(container::kTagComments), nullptr);
  EXPECT_EQ(inspect(with_comments(coded, {noise})).version_minor, kFormatMinorPolygons);
  EXPECT_EQ(inspect(with_comments(bare, {noise})).version_minor, kFormatMinorPolygons);
  // A polygon file keeps the minor its sections need.
  PolygonMesh m;
  m.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0};
  m.face_offsets = {0, 4, 7, 10};
  m.corners = {0, 1, 4, 3, 1, 2, 5, 1, 5, 4};
  const std::string poly = encode_polygons(m);
  const std::uint8_t poly_minor = inspect(poly).version_minor;
  EXPECT_GE(poly_minor, kFormatMinorPolygons);
  EXPECT_EQ(with_comments(with_comments(poly, licence), {}), poly);
  // Kept as it was: a minor newer than this qsp's, and a section it does not know.
  const container::File f = container::parse(coded);
  std::string body;
  for (const container::Section& s : f.sections) container::put_section(body, s.tag, s.payload);
  const std::string newer = container::seal(f.major, kFormatMinor + 1, f.level, body);
  EXPECT_EQ(inspect(with_comments(newer, {})).version_minor, kFormatMinor + 1);
  container::put_section(body, 0x86, "x");
  const std::string unknown = container::seal(f.major, f.minor, f.level, body);
  EXPECT_EQ(inspect(with_comments(unknown, {})).version_minor, f.minor);
}

// Every bit flip of a coded section, resealed so the checksum does not hide it: refused with kFormat,
// or read as lines without a line break. Every prefix of the whole file is refused.
TEST(CodedComments, EveryFlipIsRefusedOrClean) {
  const std::string payload = encode_coded_comments_section({" licence", "more", ""});
  for (std::size_t i = 0; i < payload.size() * 8; ++i) {
    std::string p = payload;
    p[i / 8] = static_cast<char>(p[i / 8] ^ (1 << (i % 8)));
    try {
      for (const std::string& line : file_comments(with_coded(p)))
        EXPECT_EQ(line.find_first_of("\r\n"), std::string::npos);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kFormat) << e.what();
    }
  }
  const std::string file = with_coded(payload);
  for (std::size_t n = 0; n < file.size(); ++n) EXPECT_THROW((void)file_comments(file.substr(0, n)), Error);
}

}  // namespace
}  // namespace qsp
