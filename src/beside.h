// Work run beside the calling thread, for the pipelines' independent steps (the decoder's check of the
// rebuilt quads, the encoder's topology section, the OBJ writer's face lines).
#pragma once

#include <future>
#include <system_error>
#include <thread>
#include <utility>

namespace qsp {

// `task` on a second thread when `wanted`, the machine has more than one core and a thread is to be
// had; otherwise deferred, run by get() on the thread that calls it. Either way get() returns its
// result or rethrows what it threw, and the future's destructor waits for a running task, so a caller
// that throws first never leaves it reading freed memory.
template <class Task>
auto beside(bool wanted, Task task) -> std::future<decltype(task())> {
  if (wanted && std::thread::hardware_concurrency() != 1) {
    try {
      return std::async(std::launch::async, std::move(task));
    } catch (const std::system_error&) {
      // no thread to be had
    }
  }
  return std::async(std::launch::deferred, std::move(task));
}

}  // namespace qsp
