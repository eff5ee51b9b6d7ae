// src/polymesh_check.h (internal): check_mesh without the distinct-vertices rule, for writers (a
// file can hold a face that repeats a vertex; only readers refuse one).
#pragma once

#include "qsp/polymesh.h"

namespace qsp::detail {

// Every check of check_mesh except "no face repeats a vertex". Throws Error(kUsage).
void check_mesh_arrays(const Mesh& mesh);

}  // namespace qsp::detail
