// The geometry encoder's search: which header (value plans, value repeats) and which tools a section is
// coded with. Everything it chooses is written in the header, so the decoder needs none of it
// (format-spec/geometry_section.md, "Encoder choices").
#include <algorithm>
#include <future>
#include <limits>

#include "beside.h"
#include "geometry_coder.h"
#include "geometry_encoder.h"
#include "qsp/error.h"
#include "qsp/mesh.h"

namespace qsp {
namespace {

constexpr std::uint8_t kCostlyTools = geometry_tool::kCellShapes | geometry_tool::kLogisticMixing;

// f(i) for every i < n, every second one on another thread when `two` (and a thread is to be had): the
// header trials are independent whole loops, so choosing between two headers takes the time of one.
template <class F>
void alternate(std::size_t n, bool two, F&& f) {
  auto run = [&](std::size_t first) {
    for (std::size_t i = first; i < n; i += 2) f(i);
  };
  auto odd = beside(two && n > 1, [&run] { run(1); });
  run(0);
  odd.get();
}

// Header h with normal chaining, if its axes are all integer axes (else there is nothing to chain) and
// `cue`, from coding with h, says it may pay.
std::optional<Header> chained(const Header& h, const ChainCue& cue) {
  if (!h.integer_axes()) return std::nullopt;
  if (std::uint64_t{cue.anisotropic} * 5 <= cue.vertices) return std::nullopt;
  Header c = h;
  c.tools |= geometry_tool::kNormalChaining;
  return c;
}

// The smallest of the candidate headers (value repeats on and off; for lossless, the decimal plan and
// plain float bits): repeats pay on CAD-like meshes (pawn -37% at 14 bits) and cost a few percent where
// coordinates only repeat by chance. Then the best one with normal chaining, if that is smaller
// (`o.try_chaining`): one more encode, not one per header, and only where the best one's ChainCue says it
// may pay (chaining gains on remeshed scans and is neutral elsewhere). With `o.header_sample` the
// choice is made on the first that many vertices (stencils only look back, so a prefix codes on its
// own), scaling the payload to the whole section, and the section is coded once. Last, a section whose
// headers were tried in full tries the winner with the costly tools (cell shapes and logistic mixing)
// and keeps them where smaller (`o.try_costly_tools`), so a level that tries them never writes a
// larger file than one that does not: they nearly double the decoder's work (mh_female_generic_cc2 at
// 14 bits: 2.98 against 1.56 G instructions for the whole decompress, for 1.6% fewer bytes), so
// sampled sections, the large ones, never take them. `chosen` gets the index of the header it chose
// (before the tools).
std::string encode_best(std::span<const float> pos, const Hoods& hoods, const std::vector<Header>& options,
                        const GeometryOptions& o, std::size_t& chosen) {
  const std::uint32_t count = hoods.size();
  const std::optional<bool> coder_thread = o.coder_thread;
  chosen = 0;
  // A section's size with what its mirror prediction costs besides.
  const auto cost = [&o](const std::string& bytes, const Header& h) {
    return bytes.size() + (h.has(geometry_tool::kMirror) ? o.mirror_bytes : 0);
  };
  if (o.header_sample == 0 || count <= o.header_sample) {
    // Every header coded whole, on two threads as the estimates below (a small mesh's four headers were
    // two thirds of its compress), each then without a coder thread of its own.
    std::vector<std::string> coded(options.size());
    std::vector<ChainCue> cues(options.size());
    const bool two = options.size() > 1 && coder_thread != false;
    alternate(options.size(), two, [&](std::size_t i) {
      coded[i] = encode_with(pos, hoods, count, options[i], two ? std::optional<bool>(false) : coder_thread,
                             &cues[i]);
    });
    std::string best;
    ChainCue best_cue;
    for (std::size_t i = 0; i < options.size(); ++i) {
      if (best.empty() || cost(coded[i], options[i]) < cost(best, options[chosen]))
        best = std::move(coded[i]), chosen = i, best_cue = cues[i];
    }
    Header final = options[chosen];
    if (const std::optional<Header> c = o.try_chaining ? chained(final, best_cue) : std::nullopt) {
      std::string bytes = encode_with(pos, hoods, count, *c, coder_thread);
      if (bytes.size() < best.size()) best = std::move(bytes), final = *c;
    }
    if (o.try_costly_tools) {
      Header costly = final;
      costly.tools |= kCostlyTools;
      std::string bytes = encode_with(pos, hoods, count, costly, coder_thread);
      if (bytes.size() < best.size()) {
        best = std::move(bytes);
        // Chaining paid against the cheaper model; against this one it may not (mh_base lossless).
        if (costly.has(geometry_tool::kNormalChaining)) {
          costly.tools &= static_cast<std::uint8_t>(~geometry_tool::kNormalChaining);
          bytes = encode_with(pos, hoods, count, costly, coder_thread);
          if (bytes.size() < best.size()) best = std::move(bytes);
        }
      }
    }
    return best;
  }
  const std::uint32_t sample = o.header_sample;
  const double scale = static_cast<double>(count) / sample;
  const Header* best = nullptr;
  double best_size = 0;
  auto estimate = [&](const Header& h, ChainCue* cue) {
    std::string head;
    write_header(head, h);
    return static_cast<double>(head.size() + (h.has(geometry_tool::kMirror) ? o.mirror_bytes : 0)) +
           scale * static_cast<double>(encode_with(pos, hoods, sample, h, false, cue).size() - head.size());
  };
  ChainCue best_cue;
  if (options.size() == 1 && !o.try_chaining) {
    best = &options[0];  // nothing to choose
  } else {
    // The estimates (the sample codes inline) on two threads.
    std::vector<double> sizes(options.size());
    std::vector<ChainCue> cues(options.size());
    alternate(options.size(), coder_thread != false,
              [&](std::size_t i) { sizes[i] = estimate(options[i], &cues[i]); });
    for (std::size_t i = 0; i < options.size(); ++i) {
      double size = sizes[i];
      if (o.repeats_must_pay && options[i].has(geometry_tool::kValueRepeats))
        size += size / (kRepeatsMustSave - 1);  // saves 1/kRepeatsMustSave of it, or lose
      if (!best || size < best_size) best = &options[i], best_size = size, best_cue = cues[i], chosen = i;
    }
  }
  Header final = *best;
  if (const std::optional<Header> c = o.try_chaining ? chained(*best, best_cue) : std::nullopt;
      c && estimate(*c, nullptr) < best_size)
    final = *c;
  return encode_with(pos, hoods, count, final, coder_thread);
}

}  // namespace

std::string encode_geometry(std::span<const float> positions, std::span<const Stencil> stencil,
                            const GeometryOptions& options, GeometryChoice* chosen) {
  if (positions.size() % 3 != 0) throw Error(ErrorCode::kUsage, "geometry: positions not a multiple of 3");
  if (positions.size() / 3 > kMaxVertices) throw Error(ErrorCode::kLimit, "geometry: too many vertices");
  if (options.quantize_bits > 30) throw Error(ErrorCode::kUsage, "geometry: quantize_bits must be 0..30");
  check_stencils(stencil, positions.size() / 3);
  const Hoods hoods(stencil, options.order);
  Header h;
  h.tools = options.order == CodingOrder::kLayout ? geometry_tool::kLayoutOrder : 0;
  std::vector<Header> headers;
  std::vector<GeometryChoice> choices;  // what each header is, in GeometryChoice's terms
  if (options.quantize_bits) {
    h.bits = options.quantize_bits;
    h.grid = make_grid(positions, h.bits);
    headers = {h};
    choices = {{}};
  } else {
    for (std::size_t a = 0; a < 3; ++a) h.plans[a] = plan_axis(positions, static_cast<int>(a));
    const bool decimal =
        std::any_of(h.plans.begin(), h.plans.end(), [](const AxisPlan& p) { return p.mode != kFloatBits; });
    headers = {h};
    choices = {{false, decimal}};
    // The decimal estimate is a heuristic: never do worse than plain float bits.
    if (decimal) {
      headers.push_back(Header{});
      headers.back().tools = h.tools;
      choices.push_back({false, false});
    }
  }
  for (std::size_t i = 0, n = headers.size(); i < n; ++i) {
    headers.push_back(headers[i]);
    headers.back().tools |= geometry_tool::kValueRepeats;
    choices.push_back({true, choices[i].decimal});
  }
  const bool mirrored =
      options.try_mirror &&
      std::any_of(stencil.begin(), stencil.end(), [](const Stencil& s) { return s.mirror != kInvalid; });
  for (std::size_t i = 0, n = headers.size(); mirrored && i < n; ++i) {
    if (!headers[i].integer_axes()) continue;
    headers.push_back(headers[i]);
    headers.back().tools |= geometry_tool::kMirror;
    choices.push_back({choices[i].repeats, choices[i].decimal, true});
  }
  // Only the headers chosen (all of them if none matches).
  auto keep = [&](auto&& wanted) {
    std::vector<Header> kept;
    std::vector<GeometryChoice> kept_choices;
    for (std::size_t i = 0; i < headers.size(); ++i) {
      if (!wanted(choices[i])) continue;
      kept.push_back(headers[i]);
      kept_choices.push_back(choices[i]);
    }
    if (!kept.empty()) headers = std::move(kept), choices = std::move(kept_choices);
  };
  if (options.choice) {
    keep([&](const GeometryChoice& c) {
      return c.repeats == options.choice->repeats && c.decimal == options.choice->decimal &&
             c.mirror == options.choice->mirror;
    });
  }
  std::size_t best = 0;
  std::string bytes;
  if (options.tools) {  // exactly these tools: the smallest of the value plans that have them
    const bool repeats = (*options.tools & geometry_tool::kValueRepeats) != 0;
    const bool mirror = (*options.tools & geometry_tool::kMirror) != 0;
    keep([&](const GeometryChoice& c) { return c.repeats == repeats && c.mirror == mirror; });
    for (std::size_t i = 0; i < headers.size(); ++i) {
      Header forced = headers[i];
      forced.tools =
          static_cast<std::uint8_t>((*options.tools & geometry_tool::kAll & ~geometry_tool::kLayoutOrder) |
                                    (h.tools & geometry_tool::kLayoutOrder));
      // Mirror prediction reflects integers: a plan of float bits cannot take it.
      if (!forced.integer_axes()) forced.tools &= static_cast<std::uint8_t>(~geometry_tool::kMirror);
      std::string b = encode_with(positions, hoods, hoods.size(), forced, options.coder_thread);
      if (bytes.empty() || b.size() < bytes.size()) bytes = std::move(b), best = i;
    }
  } else {
    bytes = encode_best(positions, hoods, headers, options, best);
  }
  if (chosen) *chosen = choices[best];
  return bytes;
}

}  // namespace qsp
