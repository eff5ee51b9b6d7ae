// Where the geometry encoder's coding loop puts its decisions: coded at once, or (large sections) on a
// second thread that runs the range coder while the loop predicts the next vertices.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "beside.h"
#include "entropy.h"
#include "geometry_model.h"

namespace qsp {

// One decision group of the geometry stream, as the encoder's coding loop produces it.
struct Symbol {
  enum Op : std::uint8_t { kResidual, kZeros, kRepeat };
  std::uint64_t value;  // residual u (kResidual), trailing zeros t (kZeros), rank (kRepeat)
  Op op;
  std::uint8_t ctx;   // context kind (kResidual, kRepeat)
  std::uint8_t arg;   // magnitude class (kResidual), digit count (kZeros), previous axis (kRepeat)
  std::uint8_t arg2;  // the axis's maximum length (kResidual), taken or not (kRepeat)
  std::uint8_t axis = 0, neighbour_cls = 0, previous = 0;  // kResidual, logistic mixing: its other contexts
};

// Codes `s` through `m` into `rc`.
void code_symbol(const Symbol& s, ResidualModel& m, RangeEncoder& rc);
// Codes `block` through `m` into `rc`: the coder thread's loop, with the model's kind chosen once and
// every residual's coding inlined (a call per symbol and its context on the stack were an eighth of it).
void code_symbols(std::span<const Symbol> block, ResidualModel& m, RangeEncoder& rc);

// Where the encoder's coding loop puts its symbols: coded at once, or (large sections) handed in blocks
// to a second thread that codes them while the loop predicts the next vertices. The model's state never
// feeds back into prediction, so both give the same bytes. The second thread takes the range coder off
// the critical path: bench_geometry on mh_female_generic_cc2 (2 cores), 14 bits 167 -> 145 ms,
// lossless 395 -> 357 ms.
class SymbolSink {
 public:
  // Codes into `payload` with a residual model with or without logistic mixing; on a second thread if
  // `threaded` (and there is more than one core and a thread to be had).
  SymbolSink(bool logistic, std::string& payload, bool threaded);
  SymbolSink(const SymbolSink&) = delete;
  SymbolSink& operator=(const SymbolSink&) = delete;
  ~SymbolSink();  // on an exception in the coding loop: stops the coder unheard

  void put(const Symbol& s) {
    if (!thread_.joinable()) return code_symbol(s, coder_->model, coder_->rc);
    block_.push_back(s);
    if (block_.size() == kBlock) hand_over();
  }

  // Codes what is left and ends the stream into the payload; rethrows what failed the coder thread.
  void finish();

 private:
  // The coder thread starts when the first block is full and codes the last after the loop ends, so a
  // block is what does not overlap, twice: at 16384 symbols it was half of mh_base's 57k, 4096 a seventh.
  static constexpr std::size_t kBlock = 4096;    // symbols (64 KiB)
  static constexpr std::size_t kMaxQueued = 32;  // blocks the loop may run ahead: bounds the memory

  void hand_over();
  void run();

  // The coder's state, on its own cache lines: on the coding loop's stack its every symbol missed the
  // coder thread's cache, and coding took twice as long as on one thread.
  struct alignas(64) Coder {
    explicit Coder(bool logistic) : model(logistic), rc(bytes) {}
    ResidualModel model;
    std::string bytes;
    RangeEncoder rc;  // into bytes
  };

  std::string& payload_;
  std::unique_ptr<Coder> coder_;
  std::vector<Symbol> block_;  // being filled by the coding loop
  Helper thread_;
  std::mutex mutex_;  // guards the members below
  std::condition_variable ready_, taken_;
  std::deque<std::vector<Symbol>> full_;  // blocks waiting to be coded, in order
  std::vector<std::vector<Symbol>> empty_;
  // Atomic (still written under the mutex) so the coder thread can spin on it and on queued_, a mirror
  // of full_.size(), before it blocks (spin_until).
  std::atomic<bool> done_{false};
  std::atomic<std::size_t> queued_{0};
  std::exception_ptr error_;
};

}  // namespace qsp
