#include "sweep/parallel.hpp"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace mechgen {

int thread_limit() {
  return 4 * std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

void run_parallel(size_t threads, const std::function<void(size_t k)>& task) {
  std::vector<std::exception_ptr> errors(std::max<size_t>(threads, 1));
  auto guarded = [&](size_t k) {
    try {
      task(k);
    } catch (...) {
      errors[k] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  std::string start_error;
  for (size_t k = 1; k < threads; ++k) {
    try {
      pool.emplace_back(guarded, k);
    } catch (const std::exception& error) {  // std::system_error, std::bad_alloc
      start_error = "cannot start thread " + std::to_string(k + 1) + " of " +
                    std::to_string(threads) + ": " + error.what() + " (ask for fewer threads)";
      break;
    }
  }
  if (start_error.empty()) guarded(0);
  for (std::thread& thread : pool) thread.join();
  if (!start_error.empty()) throw std::runtime_error(start_error);
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
}

}  // namespace mechgen
