// src/io_text.h (internal): the seams of the OBJ readers' two-thread read, declared for tests.
#pragma once

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "qsp/io.h"
#include "qsp/mesh.h"
#include "qsp/polymesh.h"

namespace qsp::detail {

// read_obj reads text of at least this size on two threads, in this many parts. With the other core
// idle, two threads read 0.6 MB in about half the time; near 0.3 MB the gain is lost in the thread's
// start and the noise. From 512 KiB, not 1 MiB: reading is a fifth of compress's main thread on
// meshes of 14-19k vertices (mh_female_generic 0.65 MB, mh_base 0.9 MB), and it halves there.
inline constexpr std::size_t kParallelObjBytes = std::size_t{1} << 19;
inline constexpr std::size_t kParallelObjParts = 8;

// The first offset after `from` where a split leaves both parts starting where the sequential
// reader starts a line: just after a LF that does not end a backslash continuation, with text after
// it. npos if there is none.
std::size_t obj_split_point(std::string_view text, std::size_t from);

// Where read_obj splits `text`: none below kParallelObjBytes, else near every 1/kParallelObjParts.
std::vector<std::size_t> obj_read_splits(std::string_view text);

// read_obj split at `splits` (none: sequential), which must be increasing obj_split_points, else
// the read is sequential. When a part fails or the merge sees a problem only the whole file shows,
// the text is re-read sequentially, so mesh, report and error are always the sequential read's.
// *parallel (may be null) says whether the two-thread result (mesh, or non-quads error) was used.
QuadMesh read_obj_split(std::string_view text, std::string_view source, ReadReport* report,
                        std::span<const std::size_t> splits, bool* parallel);

// read_obj_mesh split at `splits`, with the same guarantees: mesh, notes and error are always the
// sequential read's.
Mesh read_obj_mesh_split(std::string_view text, std::string_view source, ReadNotes* notes,
                         std::span<const std::size_t> splits, bool* parallel);

}  // namespace qsp::detail
