// Compression levels: what each one searches, decided here and nowhere else.
#include <array>
#include <string>

#include "geometry_coder.h"
#include "qsp/codec.h"
#include "qsp/error.h"

namespace qsp {
namespace {

// Headers chosen on a prefix of this many vertices: enough for the estimate to pick what full trials
// pick on nearly every mesh, a fraction of one pass on meshes of 10k vertices and more.
constexpr std::uint32_t kSample = 4096, kSmallSample = 1024;

// Levels 1-3 code each mesh once in one partition (the motorcycle graph), without the costly geometry
// tools: the decoder then runs the cheaper model. 4 adds the second coding order, 5-6 try every header
// in full, 7 adds the cell shapes and logistic mixing tools (a few percent smaller, twice the decode
// time), 8-9 every partition. What --help and stats say of each is written from these fields.
constexpr std::array<Effort, kMaxLevel> kLevels = {{
    {false, false, kSmallSample, false, false, true},
    {false, false, kSmallSample, true, false, true},
    {false, false, kSample, true, false},
    {false, true, kSample, true, false},
    {false, false, 0, true, false},
    {false, true, 0, true, false},
    {false, true, 0, true, true},
    {true, false, 0, true, true},
    {true, true, 0, true, true},
}};

const Effort& level_entry(int level) {
  if (level < kMinLevel || level > kMaxLevel) {
    throw Error(ErrorCode::kUsage, "compression level " + std::to_string(level) + " is not between " +
                                       std::to_string(kMinLevel) + " and " + std::to_string(kMaxLevel));
  }
  return kLevels[static_cast<std::size_t>(level - kMinLevel)];
}

}  // namespace

Effort level_effort(int level, std::uint64_t vertex_count) {
  Effort e = level_entry(level);
  if (vertex_count > kSearchVertexLimit) {
    // The mirror search too: its adjacency, centres and maps made cc2's compress (221,858 vertices)
    // 16 MB larger at its peak than draco_encoder's, and 0.1 s slower.
    e.all_partitions = e.both_orders = e.try_costly_tools = e.try_mirror = false;
    if (e.header_sample == 0) e.header_sample = kSample;
  }
  return e;
}

std::string level_description(int level) {
  const Effort& e = level_entry(level);
  std::string d = e.all_partitions ? "the smallest of the motorcycle, greedy and merge partitions"
                                   : "the motorcycle graph";
  d += e.both_orders ? ", in both coding orders (the smaller kept)" : ", in patch order";
  if (e.header_sample) {
    const std::string n = std::to_string(e.header_sample);
    d += ", header and texture coordinate and normal predictions chosen on the first " + n + " values";
  } else {
    d += ", every header and prediction coded in full (texture coordinates from their mirror images too)";
  }
  if (e.repeats_must_pay) d += ", value repeats only where they save 1/" + std::to_string(kRepeatsMustSave);
  d += e.try_chaining ? ", the normal-chaining trial" : ", no normal-chaining trial";
  if (e.try_costly_tools)
    d += ", the cell shapes and logistic mixing tools where smaller (about twice the decode time)";
  // What the search limit takes away (level_effort), said as the level that searches that much.
  Effort big = level_effort(level, kSearchVertexLimit + 1);
  std::string limited;
  if (big != e) {
    big.try_mirror = true;  // no level leaves it out: said on its own
    for (int l = kMinLevel; l <= kMaxLevel && limited.empty() && big != e; ++l)
      if (level_entry(l) == big) limited = "as " + std::to_string(l) + ", ";
    if (limited.empty() && big != e) limited = "with less search, ";
    limited = "; above " + std::to_string(kSearchVertexLimit) + " vertices " + limited +
              "without the mirror search";
  }
  return d + (level == kDefaultLevel ? " (the default)" : "") + limited;
}

}  // namespace qsp
