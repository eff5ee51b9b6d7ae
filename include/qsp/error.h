// qsp/error.h: the one typed error every stage throws.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace qsp {

// Fixed values: they are part of the CLI contract (exit codes are derived from them in tools/qsp/main.cpp).
enum class ErrorCode : std::uint8_t {
  kIo = 1,              // file cannot be opened, read or written
  kParse = 2,           // malformed text (number, keyword, index syntax)
  kNotQuad = 3,         // a face that is not a quadrilateral
  kBadIndex = 4,        // vertex index out of range or zero
  kDegenerateFace = 5,  // a face repeats a vertex
  kNonManifold = 6,     // an edge with 3+ faces, or a vertex with more than one fan
  kOrientation = 7,     // neighbouring faces disagree on orientation
  kBadNumber = 8,       // NaN or infinite coordinate
  kUnsupported = 9,     // data qsp cannot store (normals, texcoords, ...) unless told to drop it
  kLimit = 10,          // input exceeds a documented limit
  kFormat = 11,         // a .qsp that is truncated, corrupt or otherwise invalid
  kVersion = 12,        // a .qsp written by a newer major format version
  kChecksum = 13,       // a .qsp whose checksum does not match
  kInternal = 14,       // an invariant of qsp itself failed (a bug): never a wrong result
  kUsage = 15,          // a caller passed an argument outside its contract (a level of 12, 31 bits, ...)
};

// What went wrong, where. `what()` is the full human message, already carrying the location.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message, std::int64_t face = -1)
      : std::runtime_error(message), code_(code), face_(face) {}
  ErrorCode code() const noexcept { return code_; }
  // The 0-based face the problem was found at, or -1; lets a caller holding line numbers say file:line.
  std::int64_t face() const noexcept { return face_; }

 private:
  ErrorCode code_;
  std::int64_t face_;
};

// Short stable name of a code ("parse", "non-manifold", ...), for messages and JSON.
const char* error_name(ErrorCode code) noexcept;

}  // namespace qsp
