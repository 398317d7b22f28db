// mechgen_generate MODEL.yaml OUTPUT_DIR TEMPLATES_DIR: the build's own generator, without the
// kernels linked in (the full mechgen binary links them, so it cannot be what makes them).
#include <iostream>

#include "generate.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: mechgen_generate MODEL.yaml OUTPUT_DIR TEMPLATES_DIR\n";
    return 1;
  }
  try {
    mechgen::gen::generate({argv[1], argv[2], argv[3], false});
  } catch (const std::exception& error) {
    std::cerr << error.what() << "\n";
    return 1;
  }
  return 0;
}
