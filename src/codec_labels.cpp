// The face labels section (format 3.3; format-spec/qsp_format.md, "Face labels section"): each face's
// object, groups, material and smoothing group as runs along the output face order, their names, and
// the material libraries.
#include <algorithm>
#include <string>
#include <unordered_set>
#include <vector>

#include "bytes.h"
#include "codec_sections.h"
#include "entropy.h"
#include "qsp/error.h"

namespace qsp {
namespace {

constexpr const char* kSection = "face labels section";
constexpr unsigned kKinds = 4, kLibrariesBit = 1u << 4, kFrontCodedBit = 1u << 5, kReservedBits = 0xC0;
// Front-coded names may share long prefixes; their total length stays below this many bytes a payload
// byte (the encoder writes them plainly past it), so a hostile file cannot grow quadratically.
constexpr std::uint64_t kMaxTextPerByte = 64;

// The label kinds in the section's order: objects, groups, materials, smoothing groups.
const FaceLabels& kind_of(const PolygonMesh& m, unsigned k) {
  return k == 0 ? m.objects : k == 1 ? m.groups : k == 2 ? m.materials : m.smoothing;
}
FaceLabels& kind_of(DecodedLabels& d, unsigned k) {
  return k == 0 ? d.objects : k == 1 ? d.groups : k == 2 ? d.materials : d.smoothing;
}

bool breaks_line(char c) { return c == '\n' || c == '\r'; }

// One kind's models, fresh for each kind.
struct Models {
  BitModel same[2], is_new, is_none;
  IntModel earlier;
};

// A list's texts (one kind's names, the libraries) as lengths and bytes, or front-coded: each as the bytes
// it shares with the one before, the length of the rest and the rest.
struct TextWriter {
  bool front = false;
  std::string_view previous;
  void put(std::string& out, std::string_view text, const char* what, std::size_t index) {
    if (std::any_of(text.begin(), text.end(), breaks_line))
      throw Error(ErrorCode::kUsage,
                  std::string("encode: ") + what + " " + std::to_string(index) + " holds a line break");
    std::size_t shared = 0;
    if (front) {
      while (shared < text.size() && shared < previous.size() && text[shared] == previous[shared]) ++shared;
      put_varint(out, shared);
    }
    put_varint(out, text.size() - shared);
    out += text.substr(shared);
    previous = text;
  }
};

}  // namespace

namespace {

std::string labels_section(const PolygonMesh& mesh, std::span<const std::uint32_t> input_face, bool front) {
  const std::size_t nf = input_face.size();
  std::uint8_t kinds = mesh.material_libraries.empty() ? 0 : kLibrariesBit;
  for (unsigned k = 0; k < kKinds; ++k) {
    const FaceLabels& l = kind_of(mesh, k);
    if (l.empty()) continue;
    if (!l.face.empty() && l.face.size() != nf)
      throw Error(ErrorCode::kUsage, "encode: a face label array has " + std::to_string(l.face.size()) +
                                         " entries for " + std::to_string(nf) + " faces");
    kinds |= static_cast<std::uint8_t>(1u << k);
  }
  if (front) kinds |= kFrontCodedBit;
  std::string out(1, static_cast<char>(kinds));
  std::string stream;
  RangeEncoder enc(stream);
  for (unsigned k = 0; k < kKinds; ++k) {
    if (!(kinds & (1u << k))) continue;
    const FaceLabels& l = kind_of(mesh, k);
    const std::vector<std::uint32_t> number = label_numbering(l, input_face);
    std::vector<std::uint32_t> order(number.size()), labels(nf, kInvalid);
    for (std::uint32_t i = 0; i < number.size(); ++i) order[number[i]] = i;
    std::size_t taken = 0;
    for (std::size_t g = 0; g < nf && !l.face.empty(); ++g) {
      const std::uint32_t name = l.face[input_face[g]];
      if (name == kInvalid) continue;
      labels[g] = number[name];
      taken = std::max<std::size_t>(taken, labels[g] + 1);
    }
    put_varint(out, order.size());
    TextWriter names{front, {}};
    for (const std::uint32_t i : order) names.put(out, l.names[i], "label name", i);

    Models m;
    std::uint32_t prev = kInvalid, seen = 0;
    unsigned c = 0;
    for (std::size_t g = 0; g < nf; ++g) {
      const std::uint32_t label = labels[g];
      enc.encode_bit(m.same[c], label == prev);
      c = label == prev;
      if (label == prev) continue;
      enc.encode_bit(m.is_new, label == seen);
      if (label == seen) {
        prev = seen++;
        continue;
      }
      if (prev != kInvalid) enc.encode_bit(m.is_none, label == kInvalid);
      if (label != kInvalid) m.earlier.encode(enc, prev != kInvalid && label > prev ? label - 1 : label);
      prev = label;
    }
    if (seen != taken) throw Error(ErrorCode::kInternal, "encode: face labels numbered out of order");
  }
  if (!mesh.material_libraries.empty()) {
    put_varint(out, mesh.material_libraries.size());
    TextWriter libraries{front, {}};
    for (std::size_t i = 0; i < mesh.material_libraries.size(); ++i)
      libraries.put(out, mesh.material_libraries[i], "material library", i);
  }
  enc.finish();
  return out + stream;
}

}  // namespace

std::vector<std::uint32_t> label_numbering(const FaceLabels& l, std::span<const std::uint32_t> input_face) {
  std::vector<std::uint32_t> number(l.names.size(), kInvalid);
  std::uint32_t next = 0;
  for (std::size_t g = 0; g < input_face.size() && !l.face.empty(); ++g) {
    const std::uint32_t name = l.face[input_face[g]];
    if (name == kInvalid) continue;
    if (name >= l.names.size())
      throw Error(ErrorCode::kUsage, "encode: face " + std::to_string(input_face[g]) + " has label " +
                                         std::to_string(name) + " of " + std::to_string(l.names.size()));
    if (number[name] == kInvalid) number[name] = next++;
  }
  for (std::uint32_t& n : number)
    if (n == kInvalid) n = next++;
  return number;
}

std::string encode_labels_section(const PolygonMesh& mesh, std::span<const std::uint32_t> input_face) {
  // Front-coded names (3.9) where smaller: MakeHuman's 139 group names share their prefixes (joint-l-toe-).
  std::string plain = labels_section(mesh, input_face, false), front = labels_section(mesh, input_face, true);
  std::uint64_t text = 0;
  for (unsigned k = 0; k < kKinds; ++k)
    for (const std::string& name : kind_of(mesh, k).names) text += name.size();
  for (const std::string& library : mesh.material_libraries) text += library.size();
  return front.size() < plain.size() && text <= kMaxTextPerByte * front.size() ? front : plain;
}

std::uint8_t labels_section_minor(std::string_view payload) {
  return !payload.empty() && (static_cast<std::uint8_t>(payload[0]) & kFrontCodedBit) ? kFormatMinorNames
                                                                                      : kFormatMinorLabels;
}

DecodedLabels decode_labels_section(std::string_view payload, std::uint64_t base_offset,
                                    std::uint32_t face_count, std::uint8_t minor) {
  ByteReader in(payload, base_offset, kSection);
  std::uint64_t at = in.offset();
  const std::uint8_t kinds = in.u8("kinds");
  if ((kinds & ~kFrontCodedBit) == 0) in.fail_at("no label kind and no material library", at);
  if (kinds & kReservedBits) in.fail_at("reserved kind bits are set (must be zero)", at);
  const bool front = (kinds & kFrontCodedBit) != 0;
  if (front && minor < kFormatMinorNames)
    in.fail_at("front-coded names are format 3." + std::to_string(kFormatMinorNames) +
                   "'s, and the file says it is 3." + std::to_string(minor),
               at);
  std::uint64_t text_bytes = 0;  // decoded so far, front coding's bound
  // Names and libraries: each costs at least its length byte, so counts past the bytes left are refused
  // before anything is allocated for them.
  const auto texts = [&](const char* count_what, const char* what, bool at_least_one) {
    const std::uint64_t from = in.offset();
    const std::uint64_t n = in.varint(count_what);
    if (n > in.left() || (at_least_one && n == 0))
      in.fail_at(std::string(count_what) + " " + std::to_string(n) + " is not " + (at_least_one ? "1" : "0") +
                     " to the " + std::to_string(in.left()) + " bytes left",
                 from);
    std::vector<std::string> out;
    out.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) {
      const std::uint64_t start = in.offset();
      const std::uint64_t shared = front ? in.varint("shared length") : 0;
      if (shared > (out.empty() ? 0 : out.back().size()))
        in.fail_at(std::string(what) + " " + std::to_string(i) + " shares " + std::to_string(shared) +
                       " bytes with a shorter one before it",
                   start);
      const std::string_view text = in.take(in.varint("text length"), what);
      text_bytes += shared + text.size();
      if (text_bytes > kMaxTextPerByte * payload.size())
        in.fail_at("names of more than " + std::to_string(kMaxTextPerByte) + " bytes a section byte", start);
      if (std::any_of(text.begin(), text.end(), breaks_line))
        in.fail_at(std::string(what) + " " + std::to_string(i) + " holds a line break", start);
      std::string whole = shared ? out.back().substr(0, shared) : std::string();
      whole += text;
      out.push_back(std::move(whole));
    }
    return out;
  };
  DecodedLabels out;
  for (unsigned k = 0; k < kKinds; ++k) {
    if (!(kinds & (1u << k))) continue;
    at = in.offset();
    FaceLabels& l = kind_of(out, k);
    l.names = texts("name count", "label name", false);
    std::unordered_set<std::string_view> distinct;
    for (const std::string& name : l.names)
      if (!distinct.insert(name).second) in.fail_at("label name '" + name + "' appears twice", at);
    l.face.assign(face_count, kInvalid);
  }
  if (kinds & kLibrariesBit)
    out.material_libraries = texts("material library count", "material library", true);

  const std::uint64_t stream_offset = in.offset();
  RangeDecoder dec(in.rest(), stream_offset, kSection);
  for (unsigned k = 0; k < kKinds; ++k) {
    if (!(kinds & (1u << k))) continue;
    FaceLabels& l = kind_of(out, k);
    const auto N = static_cast<std::uint32_t>(l.names.size());
    Models m;
    std::uint32_t prev = kInvalid, seen = 0;
    unsigned c = 0;
    for (std::uint32_t f = 0; f < face_count; ++f) {
      c = dec.decode_bit(m.same[c]);
      if (c) {
        l.face[f] = prev;
        continue;
      }
      std::uint32_t label = kInvalid;
      if (dec.decode_bit(m.is_new)) {
        if (seen == N)
          throw Error(ErrorCode::kFormat, std::string(kSection) + ": face " + std::to_string(f) +
                                              " takes a new name but all " + std::to_string(N) +
                                              " are taken (at byte offset " + std::to_string(dec.offset()) +
                                              ")");
        label = seen++;
      } else if (prev == kInvalid || !dec.decode_bit(m.is_none)) {
        const std::uint32_t R = seen - (prev != kInvalid), r = m.earlier.decode(dec);
        if (r >= R)
          throw Error(ErrorCode::kFormat, std::string(kSection) + ": face " + std::to_string(f) +
                                              " takes earlier name " + std::to_string(r) + " of " +
                                              std::to_string(R) + " (at byte offset " +
                                              std::to_string(dec.offset()) + ")");
        label = prev != kInvalid && r >= prev ? r + 1 : r;
      }
      l.face[f] = prev = label;
    }
  }
  dec.finish();
  return out;
}

}  // namespace qsp
