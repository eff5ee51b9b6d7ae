// One sweep over a .qsp's section for the hostile tests of each section: every prefix and bit flip of
// the file refused (the checksum), then every bit flip and cut of the section's payload, the file
// resealed, refused as a format (or limit) error naming a byte offset, or decoded to a mesh the
// caller's check accepts.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "container.h"
#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp::testing {

// Returns how many changed payloads decoded.
inline int sweep_section(const std::string& good, std::uint8_t tag, std::uint8_t minor,
                         const std::function<void(const PolygonMesh&)>& valid) {
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_THROW(decode_polygons(std::string_view(good).substr(0, n)), Error) << n;
  for (std::size_t bit = 0; bit < 8 * good.size(); ++bit) {
    std::string bad = good;
    bad[bit / 8] = static_cast<char>(bad[bit / 8] ^ (1 << (bit % 8)));
    EXPECT_THROW(decode_polygons(bad), Error) << "bit " << bit << " decoded (the checksum should refuse it)";
  }
  const container::File file = container::parse(good);
  const container::Section* s = file.find(tag);
  EXPECT_NE(s, nullptr);
  if (s == nullptr) return 0;
  const std::string payload(s->payload);
  int decoded = 0;
  const auto check = [&](const std::string& changed, const std::string& what) {
    SCOPED_TRACE(what);
    try {
      valid(decode_polygons(container::with_section(good, tag, changed, minor)));
      ++decoded;
    } catch (const Error& e) {
      EXPECT_TRUE(e.code() == ErrorCode::kFormat || e.code() == ErrorCode::kLimit) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte offset"), std::string::npos) << e.what();
    }
  };
  for (std::size_t bit = 0; bit < 8 * payload.size(); ++bit) {
    std::string bad = payload;
    bad[bit / 8] = static_cast<char>(bad[bit / 8] ^ (1 << (bit % 8)));
    check(bad, "bit " + std::to_string(bit));
  }
  for (std::size_t n = 0; n < payload.size(); ++n) check(payload.substr(0, n), "cut at " + std::to_string(n));
  check(payload + std::string(1, '\0'), "a byte more");
  return decoded;
}

}  // namespace qsp::testing
