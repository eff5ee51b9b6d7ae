// Work run beside the calling thread, for the pipelines' independent steps (the decoder's check of the
// rebuilt quads, the encoder's topology section, the OBJ writer's face lines), and the threads that
// start it.
#pragma once

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <system_error>
#include <thread>
#include <utility>

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace qsp {

// How long a thread that waits for another keeps its core (yielding it to any other runnable thread)
// before it blocks. A blocked thread lets its core idle, and a virtual machine's idle core halts: on
// the benchmark VM (KVM, guest halt polling off) waking it again cost qsp 3-5 ms of mh_base's 16 ms
// compress, measured by turning the guest's halt polling on (200 us) and off. Waits here are short
// (a step's other half, the coder thread's next block: 50-200 us), and a spin of 300 us measured as
// fast as one of 2 ms. The price is CPU time: compressing mh_base took 17 ms of it against 15 before,
// for 0.88x the wall time. Where other threads want the core, yielding gives it to them.
constexpr std::chrono::microseconds kSpinWait{500};

// Returns true as soon as ready() does, yielding the core between tries, or false after `limit`.
template <class Ready>
bool spin_until(Ready&& ready, std::chrono::microseconds limit = kSpinWait) {
  if (ready()) return true;
  const auto end = std::chrono::steady_clock::now() + limit;
  for (;;) {
    std::this_thread::yield();
    if (ready()) return true;
    if (std::chrono::steady_clock::now() >= end) return false;
  }
}

namespace detail {
inline std::atomic<unsigned> thread_limit{0};  // set_thread_limit's n
inline thread_local bool one_thread = false;   // OneThread's scope, on this thread
}  // namespace detail

// Whether a step may start a second thread: not on one core, not after set_thread_limit(1), not in a
// OneThread scope.
inline bool threads_allowed() {
  return !detail::one_thread && detail::thread_limit.load(std::memory_order_relaxed) != 1 &&
         std::thread::hardware_concurrency() != 1;
}

// While it lives, the steps this thread runs start no thread (an encode or decode asked for one thread).
class OneThread {
 public:
  explicit OneThread(bool on) : saved_(detail::one_thread) { detail::one_thread = saved_ || on; }
  OneThread(const OneThread&) = delete;
  OneThread& operator=(const OneThread&) = delete;
  ~OneThread() { detail::one_thread = saved_; }

 private:
  bool saved_;
};

namespace detail {
// start_beside's hand-over between the creating thread and the new one.
struct Placement {
#if defined(__linux__)
  cpu_set_t wide;            // the creator's mask, which the new thread gets back once placed
  cpu_set_t others;          // wide without the creator's core
  int here = -1;             // the creator's core, or -1: leave the new thread where Linux puts it
  std::atomic<int> step{0};  // 1: the creator has narrowed the new thread's mask; 2: it has started
#endif
  std::atomic<bool> done{false};  // the thread's function has returned
};
}  // namespace detail

// A thread started by start_beside; join() waits by spin_until before it blocks.
class Helper {
 public:
  Helper() = default;
  Helper(std::thread t, std::shared_ptr<detail::Placement> state)
      : thread_(std::move(t)), state_(std::move(state)) {}
  bool joinable() const { return thread_.joinable(); }
  void join() {
    spin_until([this] { return state_->done.load(std::memory_order_acquire); });
    thread_.join();
  }

 private:
  std::thread thread_;
  std::shared_ptr<detail::Placement> state_;
};

// A thread running f (a Helper: a std::thread whose join spins first), started off the calling
// thread's core where another one is allowed. Linux often places a new thread on its creator's core
// while the other one idles, and moves it only at the next balancing tick: traced compressing mh_base
// on 2 cores, half the threads waited there, up to 2.7 ms each, the creator preempted or the new
// thread queued behind it. So the creator narrows the new thread's mask to the other cores, which
// moves it at once; a thread that runs first, on the creator's core (it preempted the creator), moves
// itself. Whichever of the two comes second widens the mask again: after that the thread goes where
// Linux sends it. Best effort: where the calls fail or are missing, the thread runs where Linux puts
// it. Throws std::system_error as std::thread does when no thread is to be had, and where
// threads_allowed() says no.
template <class F>
Helper start_beside(F&& f) {
  if (!threads_allowed())  // as when no thread is to be had: every caller then runs on one thread
    throw std::system_error(std::make_error_code(std::errc::resource_unavailable_try_again));
  auto p = std::make_shared<detail::Placement>();
#if defined(__linux__)
  const int here = sched_getcpu();
  if (here >= 0 && sched_getaffinity(0, sizeof p->wide, &p->wide) == 0 && CPU_ISSET(here, &p->wide) &&
      CPU_COUNT(&p->wide) > 1) {
    p->others = p->wide;
    CPU_CLR(here, &p->others);
    p->here = here;
  }
#endif
  std::thread t([p, g = std::forward<F>(f)]() mutable {
#if defined(__linux__)
    if (p->here >= 0) {
      const int before = p->step.exchange(2);
      bool narrowed = before == 1;  // by the creator, which left the widening to this thread
      if (before == 0 && sched_getcpu() == p->here)
        narrowed = sched_setaffinity(0, sizeof p->others, &p->others) == 0;
      if (narrowed) (void)sched_setaffinity(0, sizeof p->wide, &p->wide);
    }
#endif
    g();
    p->done.store(true, std::memory_order_release);
  });
#if defined(__linux__)
  if (p->here >= 0 && p->step.load() == 0) {
    (void)pthread_setaffinity_np(t.native_handle(), sizeof p->others, &p->others);
    if (p->step.exchange(1) == 2) (void)pthread_setaffinity_np(t.native_handle(), sizeof p->wide, &p->wide);
  }
#endif
  return Helper(std::move(t), std::move(p));
}

// A task's result, computed on a second thread or, deferred, by get(). Like a future of std::async,
// its destructor waits for a running task, so a caller that throws first never leaves it reading
// freed memory.
template <class R>
class [[nodiscard]] Beside {
 public:
  Beside() = default;
  template <class Task>
  Beside(bool threaded, Task&& task)
      : task_(std::make_unique<std::packaged_task<R()>>(std::forward<Task>(task))),
        result_(task_->get_future()) {
    if (!threaded) return;
    try {
      thread_ = start_beside([t = task_.get()] { (*t)(); });  // the task stays put when this moves
    } catch (const std::system_error&) {
      // no thread to be had: get() runs it
    }
  }
  Beside(Beside&& o) noexcept = default;
  Beside& operator=(Beside&& o) noexcept {
    wait();
    thread_ = std::move(o.thread_);
    task_ = std::move(o.task_);
    result_ = std::move(o.result_);
    return *this;
  }
  ~Beside() { wait(); }

  bool valid() const { return result_.valid(); }
  // The task's result, or what it threw; runs a deferred task here. Once only.
  R get() {
    if (thread_.joinable()) {
      thread_.join();
    } else if (task_ && result_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      (*task_)();
    }
    return result_.get();
  }

 private:
  void wait() noexcept {
    if (thread_.joinable()) thread_.join();
  }

  Helper thread_;
  std::unique_ptr<std::packaged_task<R()>> task_;
  std::future<R> result_;
};

// `task` on a second thread when `wanted`, threads_allowed() and a thread is to be had; otherwise deferred,
// run by get() on the thread that calls it. Either way get() returns its result or rethrows what it threw.
template <class Task>
auto beside(bool wanted, Task task) -> Beside<decltype(task())> {
  return Beside<decltype(task())>(wanted && threads_allowed(), std::move(task));
}

}  // namespace qsp
