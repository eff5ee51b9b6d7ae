// Compression levels: what each one searches, decided here and nowhere else.
#include <array>
#include <string>

#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// Headers chosen on a prefix of this many vertices: enough for the estimate to pick what full trials
// pick on nearly every mesh, a fraction of one pass on meshes of 10k vertices and more.
constexpr std::uint32_t kSample = 4096, kSmallSample = 1024;

struct Level {
  Effort effort;
  const char* description;
};

// Levels 1-3 code each mesh once in one partition (the motorcycle graph), without the costly geometry
// tools: the decoder then runs the cheaper model. 4 adds the second coding order, 5-6 try every header
// in full, 7 adds the cell shapes and logistic mixing tools (a few percent smaller, twice the decode
// time), 8-9 every partition.
constexpr std::array<Level, kMaxLevel> kLevels = {{
    {{false, false, kSmallSample, false, false, true},
     "motorcycle graph, patch order, header chosen on 1024 vertices (value repeats where they save 3%), "
     "texture coordinate and normal predictions on 1024 values, no chaining trial"},
    {{false, false, kSmallSample, true, false, true}, "as 1, with the normal-chaining trial"},
    {{false, false, kSample, true, false},
     "as 2, header and predictions chosen on 4096 (often no smaller than 2)"},
    {{false, true, kSample, true, false}, "as 3, in both coding orders (the smaller kept)"},
    {{false, false, 0, true, false},
     "motorcycle graph, patch order, every header and prediction coded in full"},
    {{false, true, 0, true, false}, "as 5, in both coding orders"},
    {{false, true, 0, true, true}, "as 6, and the cell shapes and logistic mixing tools where smaller"},
    {{true, false, 0, true, true},
     "as 7 in patch order, the smallest of the motorcycle, greedy and merge partitions"},
    {{true, true, 0, true, true}, "as 8, in both coding orders"},
}};

const Level& level_entry(int level) {
  if (level < kMinLevel || level > kMaxLevel) {
    throw Error(ErrorCode::kUsage, "compression level " + std::to_string(level) + " is not between " +
                                       std::to_string(kMinLevel) + " and " + std::to_string(kMaxLevel));
  }
  return kLevels[static_cast<std::size_t>(level - kMinLevel)];
}

}  // namespace

Effort level_effort(int level, std::uint64_t vertex_count) {
  Effort e = level_entry(level).effort;
  if (vertex_count > kSearchVertexLimit) {
    e.all_partitions = e.both_orders = e.try_costly_tools = false;
    if (e.header_sample == 0) e.header_sample = kSample;
  }
  return e;
}

std::string level_description(int level) {
  const Level& l = level_entry(level);
  // What the search limit takes away (level_effort): only levels that search more than level 3 change.
  const bool limited = l.effort.header_sample == 0 || l.effort.all_partitions || l.effort.both_orders;
  return std::string(l.description) + (level == kDefaultLevel ? " (the default)" : "") +
         (limited ? "; above " + std::to_string(kSearchVertexLimit) + " vertices as 3" : "");
}

}  // namespace qsp
