// An independent reader of OBJ, OFF and PLY for the round-trip tests, written from the formats'
// descriptions and sharing no code with src/: slow, simple, exact. Numbers are kept as their value
// (number_value): the float64 for a text of up to 17 significant digits (a float64 print), the
// decimal itself beyond; binary PLY values by their shortest text. A file and qsp's rewrite of it
// compare value for value whatever their spelling.
#pragma once

#include <array>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace qsp::testing {

// "-123e-5" for -0.00123 (sign, significant digits, exponent of the last one), "0" for any zero.
// Throws std::runtime_error for text that is not a plain decimal number.
inline std::string canonical_decimal(std::string_view t) {
  std::size_t i = 0;
  bool negative = false;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) negative = t[i++] == '-';
  std::string digits;
  long exponent = 0;
  bool point = false, any = false;
  for (; i < t.size(); ++i) {
    const char c = t[i];
    if (c >= '0' && c <= '9') {
      any = true;
      if (!(digits.empty() && c == '0')) digits += c;
      if (point) --exponent;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      break;
    }
  }
  if (!any) throw std::runtime_error("not a number: '" + std::string(t) + "'");
  if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) eneg = t[i++] == '-';
    if (i == t.size()) throw std::runtime_error("bad exponent: '" + std::string(t) + "'");
    long e = 0;
    for (; i < t.size() && t[i] >= '0' && t[i] <= '9'; ++i) e = e * 10 + (t[i] - '0');
    exponent += eneg ? -e : e;
  }
  if (i != t.size()) throw std::runtime_error("not a number: '" + std::string(t) + "'");
  while (!digits.empty() && digits.back() == '0') {
    digits.pop_back();
    ++exponent;
  }
  if (digits.empty()) return "0";
  std::string out = negative ? "-" : "";
  out += digits;
  out += 'e';
  out += std::to_string(exponent);
  return out;
}

template <class T>
std::string decimal_of(T value) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  return canonical_decimal(std::string_view(buf, static_cast<std::size_t>(r.ptr - buf)));
}

// A number's value as a canonical decimal: the shortest text of its float64 when the text has at
// most 17 significant digits (any float64 print; "0.10000000000000001" is 0.1), else the decimal.
inline std::string number_value(std::string_view text) {
  const std::string d = canonical_decimal(text);
  const std::size_t digits = d == "0" ? 0 : d.find('e') - (d[0] == '-' ? 1 : 0);
  if (digits > 17) return d;
  double x = 0;
  std::from_chars(d.data(), d.data() + d.size(), x);
  return decimal_of(x);
}

// The integer a canonical decimal denotes ("12e1" is 120); throws for a fraction.
inline long integer_of(const std::string& d) {
  if (d == "0") return 0;
  const auto e = d.find('e');
  long v = std::stol(d.substr(0, e));
  long k = std::stol(d.substr(e + 1));
  if (k < 0) throw std::runtime_error("not an integer: " + d);
  for (; k > 0; --k) v *= 10;
  return v;
}

using Values = std::vector<std::string>;  // number_value of each

struct TextTag {
  std::string name;
  std::vector<long long> ints;
  Values floats;
  std::vector<std::string> strings;
  bool operator==(const TextTag&) const = default;
};

// What any of the three formats says, as plain lists.
struct TextMesh {
  std::vector<Values> vertices;            // per vertex: x y z and whatever follows on its line (OBJ, OFF)
  std::vector<Values> texcoords, normals;  // OBJ vt, vn
  std::vector<std::vector<long>> faces;    // 0-based vertex indices
  std::vector<std::vector<long>> face_texcoords, face_normals;  // per face, per corner: index or -1
  std::vector<std::string> object, group, material, smoothing;  // per face ("" before any)
  std::vector<Values> face_extra;                               // OFF: numbers after a face's indices
  std::vector<TextTag> tags;
  std::vector<std::string> other_lines;  // OBJ lines of unknown statements, as written
  // PLY: element -> property -> per element, its values (one, or a list's).
  std::map<std::string, std::map<std::string, std::vector<Values>>> ply;
};

inline std::vector<std::string> split_words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

inline std::string trimmed(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// Logical lines: LF, CRLF or CR end a line; a backslash at the end joins the next (not in comments).
inline std::vector<std::pair<long, std::string>> logical_lines(const std::string& text) {
  std::vector<std::pair<long, std::string>> out;
  std::string cur;
  long line = 1, start = 1;
  std::size_t i = 0;
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) i = 3;
  const auto end_line = [&] {
    const std::string t = trimmed(cur);
    const bool comment = !t.empty() && t[0] == '#';
    if (!comment && !t.empty() && t.back() == '\\') {
      cur = t.substr(0, t.size() - 1) + " ";
    } else {
      out.push_back({start, cur});
      cur.clear();
      start = line + 1;
    }
    ++line;
  };
  for (; i < text.size(); ++i) {
    if (text[i] == '\n') {
      end_line();
    } else if (text[i] == '\r') {
      if (i + 1 < text.size() && text[i + 1] == '\n') ++i;
      end_line();
    } else {
      cur += text[i];
    }
  }
  if (!cur.empty()) out.push_back({start, cur});
  return out;
}

inline long obj_index(const std::string& token, std::size_t count) {
  const long i = std::stol(token);
  if (i < 0) return static_cast<long>(count) + i;
  return i - 1;
}

inline TextMesh parse_obj_text(const std::string& text) {
  TextMesh m;
  std::string object, group, material, smoothing;
  for (auto& [number, raw] : logical_lines(text)) {
    std::string line = raw;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    const std::vector<std::string> w = split_words(line);
    if (w.empty()) continue;
    const std::string& k = w[0];
    const std::string rest = trimmed(line.substr(line.find(k) + k.size()));
    if (k == "v" || k == "vt" || k == "vn") {
      Values v;
      for (std::size_t i = 1; i < w.size(); ++i) v.push_back(number_value(w[i]));
      (k == "v" ? m.vertices : k == "vt" ? m.texcoords : m.normals).push_back(v);
    } else if (k == "f") {
      std::vector<long> f, t, n;
      for (std::size_t i = 1; i < w.size(); ++i) {
        const std::string& c = w[i];
        const auto s1 = c.find('/');
        f.push_back(obj_index(c.substr(0, s1), m.vertices.size()));
        long ti = -1, ni = -1;
        if (s1 != std::string::npos) {
          const auto s2 = c.find('/', s1 + 1);
          const std::string ts = c.substr(s1 + 1, s2 == std::string::npos ? std::string::npos : s2 - s1 - 1);
          if (!ts.empty()) ti = obj_index(ts, m.texcoords.size());
          if (s2 != std::string::npos) ni = obj_index(c.substr(s2 + 1), m.normals.size());
        }
        t.push_back(ti);
        n.push_back(ni);
      }
      m.faces.push_back(f);
      m.face_texcoords.push_back(t);
      m.face_normals.push_back(n);
      m.object.push_back(object);
      m.group.push_back(group);
      m.material.push_back(material);
      m.smoothing.push_back(smoothing);
    } else if (k == "o") {
      object = std::string("o:").append(rest);
    } else if (k == "g") {
      group = "g:";
      for (std::size_t i = 1; i < w.size(); ++i) group.append(i > 1 ? " " : "").append(w[i]);
    } else if (k == "usemtl") {
      material = std::string("usemtl:").append(rest);
    } else if (k == "s") {
      smoothing = std::string("s:").append(rest);
    } else if (k == "t" && w.size() >= 3) {
      TextTag tag;
      tag.name = w[1];
      long counts[3] = {};
      if (std::sscanf(w[2].c_str(), "%ld/%ld/%ld", &counts[0], &counts[1], &counts[2]) == 3 &&
          static_cast<std::size_t>(counts[0] + counts[1] + counts[2]) + 3 == w.size()) {
        std::size_t at = 3;
        for (long i = 0; i < counts[0]; ++i) tag.ints.push_back(std::stoll(w[at++]));
        for (long i = 0; i < counts[1]; ++i) tag.floats.push_back(number_value(w[at++]));
        for (long i = 0; i < counts[2]; ++i) tag.strings.push_back(w[at++]);
        m.tags.push_back(tag);
      } else {
        m.other_lines.push_back(trimmed(line));
      }
    } else if (k != "mtllib") {
      m.other_lines.push_back(trimmed(line));
    }
  }
  return m;
}

// OFF: numbers as a token stream after the header (comments removed), faces possibly over several
// lines; what follows a face's indices on its last line is its colour.
inline TextMesh parse_off_text(const std::string& text) {
  TextMesh m;
  std::vector<std::pair<long, std::vector<std::string>>> lines;
  for (auto& [number, raw] : logical_lines(text)) {
    std::string line = raw;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line = line.substr(0, hash);
    const auto w = split_words(line);
    if (!w.empty()) lines.push_back({number, w});
  }
  if (lines.empty()) throw std::runtime_error("empty OFF");
  std::size_t li = 0;
  std::vector<std::string> head = lines[li++].second;
  const std::string key = head[0];
  head.erase(head.begin());
  if (head.empty()) head = lines[li++].second;
  const long nv = std::stol(head[0]), nf = std::stol(head[1]);
  for (long v = 0; v < nv; ++v) {
    Values vals;
    for (const std::string& s : lines[li++].second) vals.push_back(number_value(s));
    m.vertices.push_back(vals);
  }
  for (long f = 0; f < nf; ++f) {
    std::vector<std::string> tokens = lines[li++].second;
    const long n = std::stol(tokens[0]);
    while (static_cast<long>(tokens.size()) < n + 1) {
      const auto& more = lines[li++].second;
      tokens.insert(tokens.end(), more.begin(), more.end());
    }
    std::vector<long> face;
    for (long i = 1; i <= n; ++i) face.push_back(std::stol(tokens[i]));
    Values extra;
    for (std::size_t i = static_cast<std::size_t>(n) + 1; i < tokens.size(); ++i)
      extra.push_back(number_value(tokens[i]));
    m.faces.push_back(face);
    m.face_extra.push_back(extra);
  }
  return m;
}

// PLY, ASCII or binary: every element and property by name.
inline TextMesh parse_ply_bytes(const std::string& bytes) {
  struct Prop {
    std::string name, type, count_type;
  };
  struct Element {
    std::string name;
    long count = 0;
    std::vector<Prop> props;
  };
  std::vector<Element> elements;
  std::string format;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string::npos) throw std::runtime_error("no end_header");
    const std::string line = trimmed(bytes.substr(pos, nl - pos));
    pos = nl + 1;
    const auto w = split_words(line);
    if (w.empty()) continue;
    if (w[0] == "end_header") break;
    if (w[0] == "format") format = w[1];
    if (w[0] == "element") elements.push_back({w[1], std::stol(w[2]), {}});
    if (w[0] == "property") {
      if (w[1] == "list") {
        elements.back().props.push_back({w[4], w[3], w[2]});
      } else {
        elements.back().props.push_back({w[2], w[1], ""});
      }
    }
  }
  const bool ascii = format == "ascii", little = format == "binary_little_endian";
  std::istringstream text(ascii ? bytes.substr(pos) : std::string());
  const auto size_of = [](const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "double" || t == "float64") return 8;
    return 4;
  };
  const auto next = [&](const std::string& t) -> std::string {
    if (ascii) {
      std::string s;
      if (!(text >> s)) throw std::runtime_error("ASCII PLY ends early");
      return number_value(s);
    }
    const int n = size_of(t);
    if (pos + n > bytes.size()) throw std::runtime_error("binary PLY ends early");
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) {
      const std::uint64_t b = static_cast<unsigned char>(bytes[pos + i]);
      v |= little ? b << (8 * i) : b << (8 * (n - 1 - i));
    }
    pos += n;
    if (t == "float" || t == "float32")
      return decimal_of(std::bit_cast<float>(static_cast<std::uint32_t>(v)));
    if (t == "double" || t == "float64") return decimal_of(std::bit_cast<double>(v));
    const bool is_signed =
        t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
    if (is_signed) {
      const std::int64_t s = static_cast<std::int64_t>(v << (64 - 8 * n)) >> (64 - 8 * n);
      return canonical_decimal(std::to_string(s));
    }
    return canonical_decimal(std::to_string(v));
  };
  TextMesh m;
  for (const Element& e : elements) {
    auto& table = m.ply[e.name];
    for (long i = 0; i < e.count; ++i) {
      for (const Prop& p : e.props) {
        Values vals;
        if (p.count_type.empty()) {
          vals.push_back(next(p.type));
        } else {
          const long count = integer_of(next(p.count_type));
          for (long k = 0; k < count; ++k) vals.push_back(next(p.type));
        }
        table[p.name].push_back(vals);
      }
    }
  }
  // Faces and positions in the common shape.
  const auto& vertex = m.ply["vertex"];
  if (vertex.count("x")) {
    for (std::size_t i = 0; i < vertex.at("x").size(); ++i)
      m.vertices.push_back({vertex.at("x")[i][0], vertex.at("y")[i][0], vertex.at("z")[i][0]});
  }
  const auto& face = m.ply["face"];
  const std::string list = face.count("vertex_indices") ? "vertex_indices" : "vertex_index";
  if (face.count(list)) {
    for (const Values& f : face.at(list)) {
      std::vector<long> idx;
      for (const std::string& d : f) idx.push_back(integer_of(d));
      m.faces.push_back(idx);
    }
  }
  return m;
}

}  // namespace qsp::testing
