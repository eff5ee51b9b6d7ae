// qsp/version.h: which qsp this is.
#pragma once

namespace qsp {

// The library's version, "MAJOR.MINOR.PATCH" (what `qsp --version` prints). Never fails. The .qsp
// format versions are codec.h's: it writes kFormatMajor.kFormatMinor or lower (the lowest whose sections
// a file holds) and reads every kFormatMajor.x file; another major (1.x and 2.x were development
// versions), or a required section a newer minor added, is refused with Error(kVersion)
// (format-spec/qsp_format.md, "Version").
const char* version() noexcept;

}  // namespace qsp
