// mechgen_generate MODEL.yaml OUTPUT_DIR TEMPLATES_DIR [SUPPORT]: the build's own generator,
// without the kernels linked in (the full mechgen binary links them, so it cannot be what makes
// them). SUPPORT: a spatial model's single-support kernel on that body (model/support_model.hpp).
#include <iostream>

#include "generate.hpp"

int main(int argc, char** argv) {
  if (argc != 4 && argc != 5) {
    std::cerr << "usage: mechgen_generate MODEL.yaml OUTPUT_DIR TEMPLATES_DIR [SUPPORT]\n";
    return 1;
  }
  try {
    mechgen::gen::generate({argv[1], argv[2], argv[3], false, argc == 5 ? argv[4] : ""});
  } catch (const std::exception& error) {
    std::cerr << error.what() << "\n";
    return 1;
  }
  return 0;
}
