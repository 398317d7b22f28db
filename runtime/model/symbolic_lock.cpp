// The process-wide lock of symbolic_lock.hpp.
#include "model/symbolic_lock.hpp"

namespace mechgen {

std::recursive_mutex& symbolic_lock() {
  static std::recursive_mutex lock;
  return lock;
}

}  // namespace mechgen
