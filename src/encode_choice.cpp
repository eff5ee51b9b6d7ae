// The encoder's choice among partitions (format-spec/qsp_format.md, "What a compliant encoder must
// do"): the level's search over the motorcycle graph and the smaller partitions, each coded by
// encode_partition (codec_encode.cpp) on its own thread where that pays, the smallest file kept.
#include <array>
#include <future>
#include <string>
#include <system_error>

#include "beside.h"
#include "codec_encode.h"
#include "qsp/error.h"
#include "qsp/partition.h"

namespace qsp {

std::string encode_tuned(const QuadMesh& mesh, const EncodeOptions& options, const EncodeTuning& tuning,
                         OrderMap* order_out) {
  const std::uint64_t nv = mesh.vertex_count(), nf = mesh.face_count();
  if (mesh.positions.size() % 3 != 0 || mesh.quads.size() % 4 != 0) {
    throw Error(ErrorCode::kUsage, "encode: positions or quads array has a partial element");
  }
  if (options.quantize_bits > 30) {
    throw Error(ErrorCode::kUsage, "encode: quantize_bits " + std::to_string(options.quantize_bits) +
                                       " is not 0 (lossless) to 30");
  }
  if (nv > kMaxVertices) throw Error(ErrorCode::kLimit, "mesh has more than 2^31 - 1 vertices");
  if (nf > kMaxFaces) throw Error(ErrorCode::kLimit, "mesh has more than 2^29 - 1 faces");
  const OneThread one_thread(options.threads == 1);
  const Effort effort = level_effort(options.level, nv);
  const Adjacency adj = build_adjacency(mesh);
  // Smaller partitions usually give smaller files (fewer schematic edges, longer patch rows), but not
  // always (mh_fedora, osd_catmark_car, igl_teddy at 14 bits): the highest levels try all three.
  if (options.partition || !effort.all_partitions) {
    const PartitionMode mode = options.partition.value_or(PartitionMode::kMotorcycle);
    // The partition's tiling is not checked here: encode_canonical checks the canonical layouts, the
    // same patches, as maps onto every vertex and face one-to-one and quad by quad (a quarter of the
    // partition's instructions on mh_base).
    return encode_partition(mesh, adj, qsp::partition(adj, mode, mesh.positions, false), options, effort,
                            tuning, order_out);
  }
  // The three encodes are independent whole pipelines over read-only inputs: greedy runs on another
  // thread while this one does the motorcycle graph and merge (the heuristics take longer).
  struct Result {
    std::string bytes;
    OrderMap order;
  };
  EncodeTuning each = tuning;
  each.order_known = nullptr;  // which order is kept is known only at the end
  auto run = [&](PartitionMode mode, ChoiceRole role) {
    Result r;
    r.bytes = encode_partition(mesh, adj, qsp::partition(adj, mode, mesh.positions, false), options, effort,
                               each, order_out ? &r.order : nullptr, std::move(role));
    return r;
  };
  // The motorcycle pipeline chooses the geometry header; the heuristics' pipelines wait for it.
  SharedChoice shared;
  // A heuristic's pipeline that trips an internal check only loses its candidacy (partition() already
  // falls back the same way for an invalid cut set): the motorcycle file is always there.
  auto candidate = [&](PartitionMode mode, ChoiceRole role) {
    try {
      return run(mode, std::move(role));
    } catch (const Error& e) {
      if (e.code() != ErrorCode::kInternal) throw;
      return Result{};
    }
  };
  const ChoiceRole waits{nullptr, shared.future};  // copied here, on this thread
  // Below ~1000 vertices the three take well under a millisecond each and starting a thread costs more
  // than it saves (much more under sanitizers: the fuzzers encode thousands of tiny meshes a second).
  constexpr std::uint64_t kThreadFrom = 1024;
  // (Deferred where no thread is to be had: greedy then runs below, on this one.)
  auto greedy = beside(nv >= kThreadFrom && options.threads != 1,
                       [&candidate, &waits] { return candidate(PartitionMode::kGreedy, waits); });
  std::array<Result, 3> results;  // motorcycle, greedy, merge: the first smallest wins
  try {
    results[0] = run(PartitionMode::kMotorcycle, ChoiceRole{&shared, std::nullopt});
  } catch (...) {
    // Wake the waiting pipeline with the same failure; then the future's destructor waits for it.
    if (!shared.set) shared.chosen.set_exception(std::current_exception());
    throw;
  }
  results[2] = candidate(PartitionMode::kMerge, waits);
  results[1] = greedy.get();
  Result* best = &results[0];
  for (Result& r : results)
    if (!r.bytes.empty() && r.bytes.size() < best->bytes.size()) best = &r;
  if (order_out) *order_out = std::move(best->order);
  return std::move(best->bytes);
}

std::string encode(const QuadMesh& mesh, const EncodeOptions& options, OrderMap* order) {
  return encode_tuned(mesh, options, {}, order);
}

}  // namespace qsp
