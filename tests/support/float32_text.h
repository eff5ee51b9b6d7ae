// Which coordinates of an OBJ or OFF file float32 cannot keep, found without qsp's number reading:
// a token's digits are compared with those of its float32's shortest text (std::to_chars).
#pragma once

#include <cctype>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>

#include "files.h"

namespace qsp::testing {

// A decimal token's value as "[-]DIGITS e EXP" with no leading or trailing zero digit ("0" for zero),
// so two spellings of one value ("1.50", "15e-1") give one key.
inline std::string decimal_key(std::string_view s) {
  bool negative = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) negative = s[0] == '-', s.remove_prefix(1);
  std::string digits;
  long exponent = 0;  // of the last digit kept in `digits`
  bool point = false;
  std::size_t i = 0;
  for (; i < s.size() && (std::isdigit(static_cast<unsigned char>(s[i])) || s[i] == '.'); ++i) {
    if (s[i] == '.') {
      point = true;
    } else {
      digits += s[i];
      if (point) --exponent;
    }
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) exponent += std::stol(std::string(s.substr(i + 1)));
  const std::size_t first = digits.find_first_not_of('0');
  if (first == std::string::npos) return "0";
  digits.erase(0, first);
  while (digits.back() == '0') digits.pop_back(), ++exponent;
  return (negative ? "-" : "") + digits + "e" + std::to_string(exponent);
}

// Whether float32 keeps `token`'s decimal value: the nearest float32's shortest text has that value.
// A 16- or 17-digit token is a float64's print (docs/mesh_model.md): it is kept when the float32 of that
// float64 prints as text that reads back as the same float64.
inline bool float32_keeps(std::string_view token) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  float f = 0;
  std::from_chars(token.data(), token.data() + token.size(), f);
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof buf, f).ptr;
  const std::string key = decimal_key(token);
  if (key == decimal_key(std::string_view(buf, static_cast<std::size_t>(end - buf)))) return true;
  const std::size_t digits = key.find('e') - (key[0] == '-' ? 1 : 0);
  if (digits != 16 && digits != 17) return false;
  double d = 0, back = 0;
  std::from_chars(token.data(), token.data() + token.size(), d);
  std::from_chars(buf, end, back);
  return static_cast<float>(d) == f && back == d;
}

struct RoundedCount {
  std::uint64_t count = 0;
  std::uint64_t first_line = 0, first_vertex = 0;  // of the first one (1-based line, 0-based vertex)
  std::string first_token;
};

// The x y z of every OBJ `v` line, or of an OFF file's vertex lines (the first three numbers of each),
// that float32 does not keep. Plain line splitting: enough for the corpus files, not a reader.
inline RoundedCount count_rounded_coordinates(const std::filesystem::path& path) {
  RoundedCount out;
  if (path.extension() != ".obj" && path.extension() != ".off") {
    ADD_FAILURE() << path << ": count_rounded_coordinates reads OBJ and OFF only; extend it for this file";
    return out;
  }
  std::istringstream in(slurp(path));
  const bool off = path.extension() == ".off";
  std::uint64_t line_no = 0, vertex = 0, vertices = 0;
  int header = off ? 2 : 0;  // OFF: the "OFF" line, then the counts
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string w;
    if (!(words >> w)) continue;
    if (off && header == 2) {
      header = words >> vertices ? 0 : 1;  // "OFF", which the counts may follow on its line
      continue;
    }
    if (off && header == 1) {
      vertices = std::stoull(w);
      header = 0;
      continue;
    }
    if (off ? vertex >= vertices : w != "v") continue;
    for (int k = 0; k < 3; ++k) {
      std::string t;
      if (off && k == 0)
        t = w;
      else
        words >> t;
      if (!float32_keeps(t) && out.count++ == 0)
        out.first_line = line_no, out.first_vertex = vertex, out.first_token = t;
    }
    ++vertex;
  }
  return out;
}

}  // namespace qsp::testing
