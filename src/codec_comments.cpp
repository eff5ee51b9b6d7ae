// The comments, coded comments and kept lines sections (format-spec/qsp_format.md, "Comments section",
// "Coded comments section", "Kept lines section"): the leading comment block of the mesh file a .qsp was
// made from, kept so that licence and copyright lines survive a round trip, as plain lines or through a
// text model and the range coder, whichever is smaller; and the OBJ lines qsp keeps only as text.
#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "container.h"
#include "entropy.h"
#include "geometry_model.h"
#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp {
namespace {

bool breaks_line(char c) { return c == '\n' || c == '\r'; }

// ---- The coded comments section's text model ("Coded comments section"): each byte of the lines joined
// by LF as 8 logistic decisions (the geometry section's mixer, rate 10), most significant bit first down
// a binary tree (node 1, then 2 * node + bit), mixing the models of the previous byte, the previous two
// (hashed) and three (hashed), and either the byte the match model expects or, without one, order 0.
class TextModel {
 public:
  // For a text of `length` bytes.
  explicit TextModel(std::size_t length) : order1_(8 * length), order2_(8 * length), order3_(8 * length) {
    for (MixWeights& w : weights_) w.w = {32768, 32768, 32768, 32768, 0};
  }

  // Codes (RangeEncoder) or decodes (RangeDecoder) text[i] (written there by a decoder, which has
  // resized `text` to its length), text[0..i) known.
  template <typename Coder>
  void code_byte(Coder& rc, std::string& text, std::size_t i) {
    const auto at = [&](std::size_t back) -> std::uint32_t {
      return i >= back ? static_cast<std::uint8_t>(text[i - back]) : 0u;
    };
    const std::uint32_t x1 = at(1), x2 = x1 | (at(2) << 8), x3 = x2 | (at(3) << 16);
    const std::uint32_t expected = length_ > 0 ? static_cast<std::uint8_t>(text[pointer_]) : 0u;
    const unsigned byte = static_cast<std::uint8_t>(text[i]);  // the encoder's; a decoder's is 0 so far
    std::uint32_t node = 1;
    for (int b = 7; b >= 0; --b) {
      BitModel* m1 = &order1_.at((x1 << 8) | node);
      BitModel* m2 = &order2_.at(slot((x2 << 8) | node));
      BitModel* m3 = &order3_.at(slot((x3 << 8) | node));
      // The match model speaks while the expected byte agrees with the bits coded so far.
      const bool hit = length_ > 0 && (expected | 256u) >> (b + 1) == node;
      BitModel* m0 = hit ? &match_[16 * ((expected >> b) & 1u) + length_] : &order0_[node];
      const std::size_t set =
          2 * static_cast<std::size_t>((m1->seen > 0) + (m2->seen > 0) + (m3->seen > 0)) + hit;
      unsigned bit = (byte >> b) & 1u;
      code_logistic<kRate>(rc, bit, {m0, m1, m2, m3}, weights_[set]);
      node = 2 * node + bit;
    }
    if constexpr (std::is_same_v<Coder, RangeDecoder>) text[i] = static_cast<char>(node & 255u);
    follow(text, i + 1);
  }

 private:
  static constexpr int kRate = 10;
  static constexpr std::size_t kTable = std::size_t{1} << 16;
  static constexpr std::uint32_t kMaxLength = 15;

  // The models of a table's kTable slots, made as they are first used where the text uses few: a short
  // text touches a few thousand slots, and making all three tables' 65,536 models each was a millisecond
  // of compressing a small mesh with its licence lines (1.2 MB of fresh pages). `most`: the most slots
  // the text can use (8 a byte); below a quarter of the table, open addressing at half load at most.
  class Table {
   public:
    explicit Table(std::size_t most) {
      if (most >= kTable / 4) {
        dense_.resize(kTable);
        return;
      }
      std::size_t capacity = 16;
      while (capacity < 2 * most) capacity <<= 1;
      keys_.assign(capacity, kFree);
      models_.resize(capacity);
    }
    BitModel& at(std::uint32_t slot) {
      if (!dense_.empty()) return dense_[slot];
      const std::size_t mask = keys_.size() - 1;
      std::size_t i = (slot * 0x9E3779B1u) & mask;
      while (keys_[i] != slot) {
        if (keys_[i] == kFree) {
          keys_[i] = slot;
          break;
        }
        i = (i + 1) & mask;
      }
      return models_[i];
    }

   private:
    static constexpr std::uint32_t kFree = ~std::uint32_t{0};
    std::vector<BitModel> dense_, models_;
    std::vector<std::uint32_t> keys_;
  };

  // A context's table index: the top 16 bits of its product with 0x9E3779B1, modulo 2^32.
  static std::size_t slot(std::uint32_t key) { return (key * 0x9E3779B1u) >> 16; }

  // After text[0..n) is known: extends the match or drops it, and where there is none, finds the latest
  // earlier place the last 4 bytes were seen, its length the bytes that agree backwards, at most 15.
  void follow(const std::string& text, std::size_t n) {
    const char c = text[n - 1];
    if (length_ > 0 && text[pointer_] == c) {
      length_ = std::min(length_ + 1, kMaxLength);
      ++pointer_;
    } else {
      length_ = 0;
    }
    if (n < 4) return;
    std::uint32_t key = 0;
    for (std::size_t k = n - 4; k < n; ++k) key = (key << 8) | static_cast<std::uint8_t>(text[k]);
    const auto [seen, fresh] = last_.try_emplace(key, n);
    if (fresh) return;
    if (length_ == 0) {
      pointer_ = seen->second;
      while (length_ < kMaxLength && length_ < pointer_ &&
             text[pointer_ - 1 - length_] == text[n - 1 - length_])
        ++length_;
    }
    seen->second = n;
  }

  std::array<BitModel, 256> order0_{};
  Table order1_, order2_, order3_;
  std::array<BitModel, 32> match_{};                     // [expected bit][length]
  std::array<MixWeights, 8> weights_;                    // [2 * contexts seen before + hit]
  std::unordered_map<std::uint32_t, std::size_t> last_;  // 4 bytes -> the latest end of them
  std::size_t pointer_ = 0;                              // the expected byte's position
  std::uint32_t length_ = 0;                             // 0: no match
};

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i > 0) text += '\n';
    text += lines[i];
  }
  return text;
}

}  // namespace

bool codable_comments(const std::vector<std::string>& lines) {
  std::uint64_t size = lines.empty() ? 0 : lines.size() - 1;
  for (const std::string& line : lines) size += line.size();
  return lines.size() <= kCodedCommentsMaxLines && size <= kCodedCommentsMaxText;
}

std::string encode_coded_comments_section(const std::vector<std::string>& lines) {
  std::string text = joined(lines);
  std::string payload;
  put_varint(payload, text.size());
  RangeEncoder rc(payload);
  TextModel model(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) model.code_byte(rc, text, i);
  rc.finish();
  return payload;
}

std::vector<std::string> decode_coded_comments_section(std::string_view payload, std::uint64_t offset) {
  ByteReader in(payload, offset, "coded comments section");
  const std::uint64_t size = in.varint("text length");
  if (size > kCodedCommentsMaxText)
    in.fail("text length " + std::to_string(size) + " is more than the format's " +
            std::to_string(kCodedCommentsMaxText) + " bytes");
  // No decision costs less than log2(65536 / 65465) bits, so a byte (8 of them) at least 1/80 bit, and a
  // stream of s bytes holds at most 8 * (s + 5) bits: a length past 1024 * (s + 8) is refused unallocated.
  const std::uint64_t most = 1024 * (std::uint64_t{in.left()} + 8);
  if (size > most)
    in.fail("text length " + std::to_string(size) + " is more than the " + std::to_string(most) +
            " bytes a stream of " + std::to_string(in.left()) + " bytes can hold");
  const std::uint64_t at = in.offset();
  RangeDecoder rc(in.rest(), at, "coded comments section");
  std::string text(size, '\0');
  TextModel model(text.size());
  std::uint64_t breaks = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    model.code_byte(rc, text, i);
    // A CR would end the comment when written back, and put the rest into the mesh text.
    if (text[i] == '\r') in.fail_at("the text's byte " + std::to_string(i) + " is a CR", rc.offset());
    // Each line is a string of its own: their count is bounded as the text's bytes are.
    if (text[i] == '\n' && ++breaks == kCodedCommentsMaxLines)
      in.fail_at("the text's byte " + std::to_string(i) + " begins line " + std::to_string(breaks + 1) +
                     ", past the format's " + std::to_string(kCodedCommentsMaxLines) + " lines",
                 rc.offset());
  }
  rc.finish();
  std::vector<std::string> lines(1);
  lines.reserve(breaks + 1);
  for (const char c : text) {
    if (c == '\n')
      lines.emplace_back();
    else
      lines.back().push_back(c);
  }
  return lines;
}

namespace {

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

// The lowest minor version the sections of `f` need: each one's row in container::kSections, or what
// its payload's flags need. f.minor where that is not known: a file newer than this qsp, or a section it
// does not know.
std::uint8_t needed_minor(const container::File& f) {
  if (f.minor > kFormatMinor) return f.minor;
  std::uint8_t minor = kFormatMinorQuads;
  for (const container::Section& s : f.sections) {
    const auto kind = std::find_if(std::begin(container::kSections), std::end(container::kSections),
                                   [&](const container::SectionKind& k) { return k.tag == s.tag; });
    if (kind == std::end(container::kSections)) return f.minor;
    const std::uint8_t need = s.tag == container::kTagTexcoords ? texcoords_section_minor(s.payload)
                              : s.tag == container::kTagNormals ? normals_section_minor(s.payload)
                              : s.tag == container::kTagLabels  ? labels_section_minor(s.payload)
                                                                : kind->minor;
    minor = std::max(minor, need);
  }
  return minor;
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
  container::File f = container::parse(file);
  std::erase_if(f.sections, [](const container::Section& s) {
    return s.tag == container::kTagComments || s.tag == container::kTagCodedComments;
  });
  std::string body;
  for (const container::Section& s : f.sections) container::put_section(body, s.tag, s.payload);
  // The minor version the file's other sections need (never more than it said): one the comments
  // needed, 3.16's for a coded comments section, is not kept once they are replaced or gone.
  const std::string bare = container::seal(f.major, std::min(f.minor, needed_minor(f)), f.level, body);
  if (lines.empty()) return bare;
  // The smaller section, the comments section on a tie (a section's tag and length count too), and the
  // comments section for a text past the coded section's limits.
  const std::string plain = lines_payload(lines);
  if (codable_comments(lines)) {
    const std::string coded = encode_coded_comments_section(lines);
    if (varint_size(coded.size()) + coded.size() < varint_size(plain.size()) + plain.size())
      return container::with_section(bare, container::kTagCodedComments, coded, kFormatMinorCodedComments);
  }
  return container::with_section(bare, container::kTagComments, plain, kFormatMinorPolygons);
}

std::vector<std::string> file_comments(std::string_view bytes) {
  const container::File f = container::parse(bytes);
  const container::Section* plain = f.find(container::kTagComments);
  const container::Section* coded = f.find(container::kTagCodedComments);  // never both: parse() refuses
  if (coded != nullptr) return decode_coded_comments_section(coded->payload, coded->payload_offset);
  if (plain == nullptr) return {};
  return read_lines(plain->payload, plain->payload_offset, "comments section", "comment line",
                    comment_problem);
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
