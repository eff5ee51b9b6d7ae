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

#if defined(__linux__)
namespace detail {
// start_beside's hand-over between the creating thread and the new one.
struct Placement {
  cpu_set_t wide;            // the creator's mask, which the new thread gets back once placed
  cpu_set_t others;          // wide without the creator's core
  int here = -1;             // the creator's core, or -1: leave the new thread where Linux puts it
  std::atomic<int> step{0};  // 1: the creator has narrowed the new thread's mask; 2: it has started
};
}  // namespace detail
#endif

// A std::thread running f, started off the calling thread's core where another one is allowed. Linux
// often places a new thread on its creator's core while the other one idles, and moves it only at the
// next balancing tick: traced compressing mh_base on 2 cores, half the threads waited there, up to
// 2.7 ms each, the creator preempted or the new thread queued behind it. So the creator narrows the
// new thread's mask to the other cores, which moves it at once; a thread that runs first, on the
// creator's core (it preempted the creator), moves itself. Whichever of the two comes second widens
// the mask again: after that the thread goes where Linux sends it. Best effort: where the calls fail
// or are missing, the thread runs where Linux puts it. Throws std::system_error as std::thread does
// when no thread is to be had.
template <class F>
std::thread start_beside(F&& f) {
#if defined(__linux__)
  auto p = std::make_shared<detail::Placement>();
  const int here = sched_getcpu();
  if (here >= 0 && sched_getaffinity(0, sizeof p->wide, &p->wide) == 0 && CPU_ISSET(here, &p->wide) &&
      CPU_COUNT(&p->wide) > 1) {
    p->others = p->wide;
    CPU_CLR(here, &p->others);
    p->here = here;
  }
  std::thread t([p, g = std::forward<F>(f)]() mutable {
    if (p->here >= 0) {
      const int before = p->step.exchange(2);
      if (before == 0 && sched_getcpu() == p->here) (void)sched_setaffinity(0, sizeof p->others, &p->others);
      if (before == 1 || sched_getcpu() != p->here) (void)sched_setaffinity(0, sizeof p->wide, &p->wide);
    }
    g();
  });
  if (p->here >= 0 && p->step.load() == 0) {
    (void)pthread_setaffinity_np(t.native_handle(), sizeof p->others, &p->others);
    if (p->step.exchange(1) == 2) (void)pthread_setaffinity_np(t.native_handle(), sizeof p->wide, &p->wide);
  }
  return t;
#else
  return std::thread(std::forward<F>(f));
#endif
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

  std::thread thread_;
  std::unique_ptr<std::packaged_task<R()>> task_;
  std::future<R> result_;
};

// `task` on a second thread when `wanted`, the machine has more than one core and a thread is to be
// had; otherwise deferred, run by get() on the thread that calls it. Either way get() returns its
// result or rethrows what it threw.
template <class Task>
auto beside(bool wanted, Task task) -> Beside<decltype(task())> {
  return Beside<decltype(task())>(wanted && std::thread::hardware_concurrency() != 1, std::move(task));
}

}  // namespace qsp
