// The format minor version a file should say (qsp_format.md, "Sections": the lowest whose sections it
// holds) when it holds a section of `minor`: 3.12 where it also has an interior positions section (a
// polygon mesh with vertices in no quad), whose presence the polygon tests check on their own, and 3.16
// where it has a coded comments section (a leading comment block coded smaller than as plain lines) or
// its texture coordinates section has hints from the faces across (flag bit 7, where they are smaller), 3.17
// with a symmetry section and 3.18 where its texture coordinates are predicted from their mirror images'.
#pragma once

#include <algorithm>
#include <string_view>

#include "container.h"
#include "qsp/codec.h"

namespace qsp::testing {

inline int minor_of_file_with(std::string_view bytes, int minor) {
  const container::File file = container::parse(bytes);
  if (file.find(container::kTagInterior)) minor = std::max<int>(minor, kFormatMinorInterior);
  if (const container::Section* uv = file.find(container::kTagTexcoords);
      uv && !uv->payload.empty() && (static_cast<std::uint8_t>(uv->payload[0]) & 0x80))
    minor = std::max<int>(minor, kFormatMinorSeamHints);
  if (file.find(container::kTagCodedComments)) minor = std::max<int>(minor, kFormatMinorCodedComments);
  if (file.find(container::kTagSymmetry)) minor = std::max<int>(minor, kFormatMinorMirror);
  if (const container::Section* uv = file.find(container::kTagTexcoords);
      uv && !uv->payload.empty() && (static_cast<std::uint8_t>(uv->payload[0]) & 0x20))
    minor = std::max<int>(minor, kFormatMinorTexcoordMirror);
  return minor;
}

}  // namespace qsp::testing
