// libFuzzer target: any text through the model reader and its checks (structure, solve plan).
// A rejection is a located ModelError (or another std::exception the command line reports as one
// line); a crash, a sanitizer report, a stack overflow or a timeout is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>

#include "model/mechanism_graph.hpp"
#include "model/model.hpp"
#include "model/solve_plan.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const mechgen::Model model = mechgen::read_model_text(text, "fuzz.yaml");
    (void)mechgen::make_solve_plan(model);
  } catch (const std::exception&) {
    // A rejection: fine.
  }
  return 0;
}
