// The format minor version a file should say (qsp_format.md, "Sections": the lowest whose sections it
// holds) when it holds a section of `minor`: 3.12 where it also has an interior positions section (a
// polygon mesh with vertices in no quad), whose presence the polygon tests check on their own.
#pragma once

#include <algorithm>
#include <string_view>

#include "container.h"
#include "qsp/codec.h"

namespace qsp::testing {

inline int minor_of_file_with(std::string_view bytes, int minor) {
  return container::parse(bytes).find(container::kTagInterior) ? std::max<int>(minor, kFormatMinorInterior)
                                                               : minor;
}

}  // namespace qsp::testing
