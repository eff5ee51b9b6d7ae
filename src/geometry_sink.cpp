// The geometry encoder's symbol sink and coder thread: see geometry_sink.h.
#include "geometry_sink.h"

#include <system_error>

namespace qsp {

namespace {

template <bool kLogistic>
[[gnu::always_inline]] inline void code_one(const Symbol& s, ResidualModel& m, RangeEncoder& rc) {
  switch (s.op) {
    case Symbol::kResidual:
      m.encode<kLogistic>(rc, s.value, {s.ctx, s.arg, s.arg2, s.axis, s.neighbour_cls, s.previous});
      break;
    case Symbol::kZeros:
      m.encode_zeros(rc, static_cast<int>(s.value), s.arg);
      break;
    case Symbol::kRepeat:
      rc.encode_bit(m.repeat(s.ctx, s.arg), s.arg2);
      if (s.arg2) m.rank.encode(rc, static_cast<std::uint32_t>(s.value));
      break;
  }
}

template <bool kLogistic>
void code_all(std::span<const Symbol> block, ResidualModel& m, RangeEncoder& rc) {
  for (const Symbol& s : block) code_one<kLogistic>(s, m, rc);
}

}  // namespace

void code_symbol(const Symbol& s, ResidualModel& m, RangeEncoder& rc) { code_symbols({&s, 1}, m, rc); }

void code_symbols(std::span<const Symbol> block, ResidualModel& m, RangeEncoder& rc) {
  m.logistic() ? code_all<true>(block, m, rc) : code_all<false>(block, m, rc);
}

SymbolSink::SymbolSink(bool logistic, std::string& payload, bool threaded)
    : payload_(payload), coder_(std::make_unique<Coder>(logistic)) {
  if (!threaded || !threads_allowed()) return;  // one core (or one asked for): a thread only costs
  block_.reserve(kBlock);                       // before the thread: once it runs, nothing here may throw
  try {
    thread_ = start_beside([this] { run(); });
  } catch (const std::system_error&) {
    // no thread to be had: code on this one
  }
}

SymbolSink::~SymbolSink() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    done_ = true;
    full_.clear();
  }
  ready_.notify_all();
  thread_.join();
}

void SymbolSink::finish() {
  if (thread_.joinable()) {
    hand_over();
    {
      std::lock_guard lock(mutex_);
      done_ = true;
    }
    ready_.notify_all();
    thread_.join();
    if (error_) std::rethrow_exception(error_);
  }
  coder_->rc.finish();
  payload_ = std::move(coder_->bytes);
}

void SymbolSink::hand_over() {
  std::vector<Symbol> next;
  {
    std::unique_lock lock(mutex_);
    taken_.wait(lock, [this] { return full_.size() < kMaxQueued || error_; });
    if (error_) return block_.clear();  // finish() rethrows it
    full_.push_back(std::move(block_));
    queued_ = full_.size();
    if (!empty_.empty()) next = std::move(empty_.back()), empty_.pop_back();
  }
  ready_.notify_one();
  block_ = std::move(next);
  block_.clear();
  block_.reserve(kBlock);
}

void SymbolSink::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    if (full_.empty() && !done_) {  // spin for the next block before blocking (spin_until)
      lock.unlock();
      spin_until([this] { return queued_.load() > 0 || done_.load(); });
      lock.lock();
    }
    ready_.wait(lock, [this] { return !full_.empty() || done_; });
    if (full_.empty()) return;
    std::vector<Symbol> block = std::move(full_.front());
    full_.pop_front();
    queued_ = full_.size();
    lock.unlock();
    taken_.notify_one();
    try {
      code_symbols(block, coder_->model, coder_->rc);
    } catch (...) {
      lock.lock();
      error_ = std::current_exception();
      full_.clear();
      taken_.notify_all();
      return;
    }
    block.clear();
    lock.lock();
    empty_.push_back(std::move(block));
  }
}

}  // namespace qsp
