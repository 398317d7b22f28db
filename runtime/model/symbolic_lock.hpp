// One process-wide lock for the numeric solvers run from several threads at once.
#pragma once

#include <mutex>

namespace mechgen {

// GiNaC counts the references of its expressions without atomics: threads that copy, substitute
// or evaluate the expressions of one shared model (the numeric solvers do all three) race and
// corrupt them. Code that may run a numeric solver beside another thread's holds this lock
// around it: the seeding of a spatial kernel sweep (the numeric assembly at t0), the Python
// module's sweeps. Generated kernels need no lock. Recursive: a holder may call code that takes it.
std::recursive_mutex& symbolic_lock();

}  // namespace mechgen
