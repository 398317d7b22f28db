// Compiled once per generated spatial kernel by tests/CMakeLists.txt with only that kernel's
// folder on the include path: the header needs nothing but <cmath>, <limits> and C++17, in float
// and double.
#include MECHGEN_KERNEL_HEADER

namespace k = mechgen::gen::MECHGEN_KERNEL_NAMESPACE;

template <class T>
int run() {
  k::Params<T> p;
  k::Inputs<T> in;
  k::driver_inputs(p, T(0.1), in);
  k::State<T> s;
  k::Status batch_status;
  k::evaluate_batch(p, &in, 1, &s, &batch_status);
  T row[k::column_count];
  T A[k::ne_rows * k::ne_size];
  T b[k::ne_rows];
  const int status = static_cast<int>(k::evaluate(p, in, s)) +
                     static_cast<int>(k::kinematics(p, in, s)) +
                     static_cast<int>(k::control(p, in, s)) +
                     static_cast<int>(k::ne_system(p, in, A, b)) + static_cast<int>(batch_status);
  k::to_columns(in, s, row);
  return status + static_cast<int>(row[0] + A[0] + b[0]);
}

int main() {
  return run<double>() + run<float>();
}
