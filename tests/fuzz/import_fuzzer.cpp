// libFuzzer target: `mechgen import` without the command line: a URDF (urdfdom) with its Extended
// URDF closures (YAML), or an MJCF file (MuJoCo's compiler, mj_loadXML), read into an import tree,
// its loops closed, described and written as a spatial description, which the model reader must
// then accept. The input: its first byte chooses (bit 0: MJCF, else URDF; bit 1: --floating); a
// URDF input is the URDF text, then optionally a NUL byte and the closures' YAML. The files are
// written to a private temporary folder (the readers take paths).
// A rejection of the source is a located ImportError or ModelError; any other exception, a written
// description the reader rejects (garbage out), a crash, a sanitizer report or a timeout is a
// finding (abort).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "import/import_tree.hpp"
#include "model/model.hpp"
#include "model/spatial_model.hpp"

namespace {

// The folder's name outlives every static (the atexit handler removing it runs after them).
char folder_name[] = "/tmp/mechgen_import_fuzz.XXXXXX";

std::string folder() {
  static const bool made = [] {
    if (!mkdtemp(folder_name)) std::abort();
    std::atexit([] { std::filesystem::remove_all(folder_name); });  // at the run's normal end
    return true;
  }();
  return made ? folder_name : "";
}

std::string write(const std::string& file, const std::string& text) {
  const std::string path = folder() + "/" + file;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) std::abort();
  return path;
}

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "import_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const unsigned mode = data[0];
  const std::string rest(reinterpret_cast<const char*>(data + 1), size - 1);
  namespace im = mechgen::import;
  im::Tree tree;
  try {
    if (mode & 1) {
      tree = im::read_mjcf(write("robot.xml", rest));
    } else {
      const size_t nul = rest.find('\0');
      const std::string urdf = write("robot.urdf", rest.substr(0, nul));
      const std::string closures =
          nul == std::string::npos ? std::string() : write("robot.yaml", rest.substr(nul + 1));
      tree = im::read_urdf(urdf, closures);
    }
    if (tree.name.empty() || tree.name == "robot") tree.name = "fuzzed";
    if (mode & 2) im::float_base(tree);
    im::AssemblyReport report;
    im::TreePose pose = im::assemble(tree, report);
    im::hold_free_joints(tree, pose);
    const im::Description d = im::describe(tree, pose, mode & 2);
    const std::string text = im::write_model(d);
    try {
      (void)mechgen::read_spatial_model_text(text, "imported.yaml");
    } catch (const std::exception& error) {
      finding("the written description is rejected", std::string(error.what()) + "\n" + text);
    }
  } catch (const im::ImportError&) {
    // A located rejection of the source: fine.
  } catch (const mechgen::ModelError&) {
    // Expressions and names go through the model's syntax: located too.
  } catch (const std::exception& error) {
    finding("an unlocated exception", error.what());
  }
  return 0;
}
