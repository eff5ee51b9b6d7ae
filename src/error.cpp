#include "qsp/error.h"

namespace qsp {

const char* error_name(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::kIo:
      return "io";
    case ErrorCode::kParse:
      return "parse";
    case ErrorCode::kNotQuad:
      return "not-quad";
    case ErrorCode::kBadIndex:
      return "bad-index";
    case ErrorCode::kDegenerateFace:
      return "degenerate-face";
    case ErrorCode::kNonManifold:
      return "non-manifold";
    case ErrorCode::kOrientation:
      return "orientation";
    case ErrorCode::kBadNumber:
      return "bad-number";
    case ErrorCode::kUnsupported:
      return "unsupported";
    case ErrorCode::kLimit:
      return "limit";
    case ErrorCode::kFormat:
      return "format";
    case ErrorCode::kVersion:
      return "version";
    case ErrorCode::kChecksum:
      return "checksum";
    case ErrorCode::kInternal:
      return "internal";
    case ErrorCode::kUsage:
      return "usage";
  }
  return "unknown";
}

}  // namespace qsp
