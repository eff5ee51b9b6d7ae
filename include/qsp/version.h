// qsp/version.h: which qsp this is.
#pragma once

namespace qsp {

// The library's version, "MAJOR.MINOR.PATCH" (what `qsp --version` prints). Never fails. The .qsp
// format versions it writes and reads are codec.h's kFormatMajor/kFormatMinor and kOldestMajor.
const char* version() noexcept;

}  // namespace qsp
