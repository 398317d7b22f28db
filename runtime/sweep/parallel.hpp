// Worker threads that cannot take the process down: a limit on how many a request may ask for,
// and a runner that reports a thread that cannot start, or any exception in a worker, as one
// exception on the calling thread after every started thread has joined (an exception escaping a
// std::thread, or a joinable std::thread destroyed during unwinding, calls std::terminate).
#pragma once

#include <cstddef>
#include <functional>

namespace mechgen {

// The most threads a sweep or a grid may ask for: 4 x the hardware threads (at least 4). More
// only add memory and start-up time (each thread has its own stack and buffers).
int thread_limit();

// Runs task(k) for k in [0, threads), each on its own thread (k = 0 on the calling thread). When a
// thread cannot start (std::system_error) the threads already started finish their tasks and
// std::runtime_error "cannot start thread K of N: ..." is thrown; otherwise the exception of the
// lowest k whose task threw, if any, is rethrown.
void run_parallel(size_t threads, const std::function<void(size_t k)>& task);

}  // namespace mechgen
