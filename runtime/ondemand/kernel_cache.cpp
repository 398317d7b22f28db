#include "ondemand/kernel_cache.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "generate.hpp"
#include "model/fingerprint.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/process.hpp"
#include "spatial_emitter.hpp"

namespace mechgen::ondemand {

namespace fs = std::filesystem;

namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A fresh private folder in the cache for one build.
fs::path make_build_dir(const fs::path& cache, const std::string& name) {
  std::string pattern = (cache / (".build-" + name + "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data()))
    throw std::runtime_error("cannot create a build folder in the kernel cache " + cache.string());
  return pattern;
}

// The build key (kernel_cache.hpp): what besides the fingerprint decides the library's bytes.
std::string build_key(const fs::path& cache, const std::vector<std::string>& command) {
  Fnv1a64 hash;
  hash.add_field(executable_id());
  hash.add_field(std::to_string(kCompiledKernelAbi));
  for (const std::string& word : command) hash.add_field(word);
  // The compiler's version, target and expansion of -march=native, without compiling anything.
  const fs::path dir = make_build_dir(cache, "probe");
  std::vector<std::string> probe = command;
  for (const char* word : {"-###", "-E", "-x", "c++", "/dev/null", "-o", "/dev/null"})
    probe.push_back(word);
  const int status = run_to_file(probe, (dir / "probe.log").string());
  const std::string expansion = read_text(dir / "probe.log");
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  if (status != 0)
    throw std::runtime_error("the compiler '" + command.front() + "' does not run (exit " +
                             std::to_string(status) +
                             "): " + expansion.substr(0, expansion.find('\n')) +
                             " (set MECHGEN_CXX to a C++17 compiler, or use --solver numeric)");
  hash.add_field(expansion);
  return hex64(hash.value());
}

using Entry = const CompiledKernel* (*)(int);

// The kernel in a cached library, or nullptr (with the reason in `problem`) when it does not load
// or is not the expected one.
const CompiledKernel* load(const fs::path& library, const Model& model, std::uint64_t fingerprint,
                           std::string& problem) {
  // Never closed: the kernel's functions are used until the process ends.
  void* handle = ::dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    problem = ::dlerror();
    return nullptr;
  }
  const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "mechgen_kernel_entry"));
  const CompiledKernel* kernel = entry ? entry(kCompiledKernelAbi) : nullptr;
  if (!kernel || model.name != kernel->model || kernel->fingerprint != fingerprint) {
    problem = "not a kernel of this description";
    return nullptr;
  }
  return kernel;
}

// Generates and compiles the kernel into `library` (kernel_cache.hpp).
void build(const Model& model, gen::KernelKind kind, const std::string& support,
           const fs::path& cache, const std::vector<std::string>& command,
           const fs::path& library) {
  const fs::path dir = make_build_dir(cache, model.name);
  std::error_code ignored;
  try {
    const gen::GenerateOptions options{model.file, dir.string(), templates_dir(), false, support};
    if (kind == gen::KernelKind::spatial)
      gen::generate_spatial(options);  // reads model.file again: load() checks the fingerprint
    else
      gen::generate(model, options);
  } catch (const ModelError&) {
    fs::remove_all(dir, ignored);
    throw;
  } catch (const std::exception& error) {
    fs::remove_all(dir, ignored);
    // The generator's own "FILE: error: " prefix is dropped (the command prints its own), and the
    // advice is given once.
    std::string why = error.what();
    const std::string prefix = model.file + ": error: ";
    if (why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    if (why.find("--solver numeric") == std::string::npos) why += " (use --solver numeric)";
    throw std::runtime_error("cannot generate a kernel for '" + model.name + "': " + why);
  }
  std::vector<std::string> argv = command;
  const fs::path built = dir / (model.name + ".so");
  for (const std::string& word :
       {"-I" + dir.string(), "-I" + kernel_include_dir(),
        (dir / (model.name + "_entry.cpp")).string(), std::string("-o"), built.string()})
    argv.push_back(word);
  const fs::path log = dir / "compile.log";
  const int status = run_to_file(argv, log.string());
  if (status != 0) {
    fs::path kept = library;
    kept.replace_extension(".log");
    fs::rename(log, kept, ignored);
    fs::remove_all(dir, ignored);
    throw std::runtime_error("compiling the kernel of '" + model.name + "' failed (" +
                             command.front() + " exit " + std::to_string(status) +
                             "); the compiler's output is in " + kept.string());
  }
  std::error_code error;
  fs::rename(built, library, error);  // atomic: a concurrent build renames an equal file
  fs::remove_all(dir, ignored);
  if (error)
    throw std::runtime_error("cannot move the compiled kernel into the cache as " +
                             library.string() + ": " + error.message());
}

}  // namespace

std::string cache_dir() {
  if (const std::string dir = environment("MECHGEN_CACHE"); !dir.empty()) return dir;
  if (const std::string dir = environment("XDG_CACHE_HOME"); !dir.empty())
    return (fs::path(dir) / "mechgen").string();
  if (const std::string home = environment("HOME"); !home.empty())
    return (fs::path(home) / ".cache" / "mechgen").string();
  throw std::runtime_error(
      "no folder for the kernel cache: set MECHGEN_CACHE, XDG_CACHE_HOME or HOME, or give --cache "
      "DIR");
}

std::vector<std::string> compile_command() {
  const std::string compiler = environment("MECHGEN_CXX");
  return {compiler.empty() ? "c++" : compiler,
          "-std=c++17",
          "-O2",
          "-march=native",
          "-shared",
          "-fPIC",
          "-fvisibility=hidden",
          "-ffp-contract=off",
          "-fno-math-errno",
          "-fno-trapping-math",
          "-DMECHGEN_KERNEL_SHARED"};
}

const CompiledKernel& cached_kernel(const Model& model, std::uint64_t fingerprint,
                                    const std::string& reason, gen::KernelKind kind,
                                    const std::string& support) {
  const fs::path cache = cache_dir();
  std::error_code error;
  fs::create_directories(cache, error);
  if (error)
    throw std::runtime_error("cannot create the kernel cache " + cache.string() + ": " +
                             error.message());
  const std::vector<std::string> command = compile_command();
  const fs::path library =
      cache / (model.name + "-" + hex64(fingerprint) + "-" + build_key(cache, command) + ".so");
  std::string problem;
  if (fs::exists(library, error)) {
    if (const CompiledKernel* kernel = load(library, model, fingerprint, problem)) return *kernel;
    std::cerr << "mechgen: warning: ignoring the cached kernel " << library.string() << " ("
              << problem << ")\n";
    fs::remove(library, error);
  }
  std::cerr << "mechgen: compiling kernel for " << model.name << reason
            << ", first use: " << std::flush;
  const auto start = std::chrono::steady_clock::now();
  try {
    build(model, kind, support, cache, command, library);
  } catch (...) {
    std::cerr << "failed\n";
    throw;
  }
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.1f s",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  std::cerr << seconds << " (cached in " << cache.string() << ")\n";
  if (const CompiledKernel* kernel = load(library, model, fingerprint, problem)) return *kernel;
  throw std::runtime_error("cannot load the kernel just compiled, " + library.string() + ": " +
                           problem);
}

}  // namespace mechgen::ondemand
