#include "ondemand/kernel_cache.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "generate.hpp"
#include "model/fingerprint.hpp"
#include "ondemand/cache_folder.hpp"
#include "ondemand/cache_lock.hpp"
#include "ondemand/data_paths.hpp"
#include "ondemand/kernel_budget.hpp"
#include "ondemand/process.hpp"
#include "ondemand/verified_library.hpp"
#include "report/temporary_files.hpp"
#include "spatial_emitter.hpp"

namespace mechgen::ondemand {

namespace fs = std::filesystem;

namespace {

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

// The words of a compiler variable: split at spaces; quotes are refused, not guessed at.
std::vector<std::string> compiler_words(const char* variable, const std::string& value) {
  if (value.find_first_of("\"'\\") != std::string::npos)
    throw std::runtime_error(std::string(variable) + "='" + value +
                             "' holds quotes or backslashes: give the compiler and its arguments "
                             "separated by spaces (a path with spaces: a symbolic link to it)");
  std::vector<std::string> words;
  std::istringstream in(value);
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// What -march=native compiles for, read without a compiler: the first processor's identity and
// feature flags (the fields that differ between two CPUs of one machine, such as its MHz, left
// out).
std::string cpu_identity() {
  struct utsname system {};
  std::string id = ::uname(&system) == 0 ? system.machine : "";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line) && !line.empty();) {
    const std::string key = line.substr(0, line.find_first_of("\t:"));
    for (const char* wanted :
         {"vendor_id", "cpu family", "model", "model name", "stepping", "flags", "Features",
          "CPU implementer", "CPU architecture", "CPU variant", "CPU part", "isa", "uarch"})
      if (key == wanted) id += "\n" + line;
  }
  return id;
}

// The build key (kernel_cache.hpp): what besides the fingerprint decides the library's bytes.
std::string build_key(const std::vector<std::string>& command) {
  Fnv1a64 hash;
  hash.add_field(executable_id());
  hash.add_field(std::to_string(kCompiledKernelAbi));
  for (const std::string& word : command) hash.add_field(word);
  hash.add_field(cpu_identity());
  return hex64(hash.value());
}

using Entry = const CompiledKernel* (*)(int);

// The kernel in a cached library, or nullptr (with the reason in `problem`) when it fails a check
// (verified_library.hpp) or is not the expected one.
const CompiledKernel* load(const fs::path& library, const Model& model, std::uint64_t fingerprint,
                           std::string& problem) {
  // Never closed: the kernel's functions are used until the process ends.
  void* handle = open_verified_library(library.string(), problem);
  if (!handle) return nullptr;
  const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "mechgen_kernel_entry"));
  const CompiledKernel* kernel = entry ? entry(kCompiledKernelAbi) : nullptr;
  if (!kernel || model.name != kernel->model || kernel->fingerprint != fingerprint) {
    problem = "not a kernel of this description";
    return nullptr;
  }
  return kernel;
}

// A private build folder in the cache, locked by its owner (report/temporary_files.hpp) and
// removed with what is in it when it goes out of scope, or by the signal handler.
class BuildFolder {
 public:
  BuildFolder(const fs::path& cache, const std::string& name) {
    std::string pattern = (cache / (".build-" + name + "-XXXXXX")).string();
    int error = 0;
    {
      const report::SignalsHeld held;  // until the folder is registered
      if (::mkdtemp(pattern.data())) {
        path_ = pattern;
        slot_ = report::register_temporary(path_.string(), true);
      } else {
        error = errno;
      }
    }
    if (path_.empty())
      throw std::runtime_error("cannot create a build folder in the kernel cache " +
                               cache.string() + ": " + std::strerror(error));
    lock_ = ::open((path_ / "owner.lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
    if (lock_ >= 0) report::lock_exclusively(lock_);
  }
  ~BuildFolder() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
    report::unregister_temporary(slot_);
    if (lock_ >= 0) ::close(lock_);
  }
  BuildFolder(const BuildFolder&) = delete;
  BuildFolder& operator=(const BuildFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  int slot_ = -1, lock_ = -1;
};

// Removes the build folders of killed runs (kernel_cache.hpp).
void remove_abandoned_builds(const fs::path& cache) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(cache, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(".build-", 0) == 0 && entry.is_directory(error) && !entry.is_symlink(error) &&
        report::is_abandoned((entry.path() / "owner.lock").string(), report::kStaleAge,
                             entry.path().string()))
      fs::remove_all(entry.path(), error);
  }
}

// What a first use says on stderr: "mechgen: compiling kernel for X, first use: " and then, on a
// terminal, the phase (generating, compiling) with the compile's elapsed and expected seconds
// redrawn every kTickSeconds; elsewhere, when the compile is expected to take more than
// kAnnounceSeconds, one line with its expected cost up front; at the end, the time it took.
class FirstUseReport {
 public:
  static constexpr double kAnnounceSeconds = 30, kTickSeconds = 2;
  explicit FirstUseReport(std::string prefix)
      : prefix_(std::move(prefix)), terminal_(::isatty(STDERR_FILENO) == 1) {
    std::cerr << prefix_ << (terminal_ ? "generating" : "") << std::flush;
  }
  // The compiler starts on a kernel of `cost`.
  void compiling(const CompileCost& cost) {
    cost_ = cost;
    if (terminal_) {
      tick(0);
    } else if (cost.seconds > kAnnounceSeconds) {
      std::cerr << describe(cost) << " (expected)\n";
      line_open_ = false;
    }
  }
  void tick(double seconds) {
    if (!terminal_) return;
    std::cerr << "\r\033[K" << prefix_ << printf_number("%.0f s", seconds)
              << printf_number(" of about %.0f s", cost_.seconds)
              << printf_number(" (%.2f MB header, compiling)", cost_.header_mb) << std::flush;
  }
  void finish(const std::string& outcome) {
    std::cerr << (terminal_ ? "\r\033[K" + prefix_ : line_open_ ? "" : prefix_) << outcome << "\n";
  }

 private:
  std::string prefix_;
  bool terminal_;
  bool line_open_ = true;
  CompileCost cost_;
};

// Whether the compiler's log holds one of `signs`.
bool log_says(const fs::path& log, std::initializer_list<const char*> signs) {
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);)
    for (const char* sign : signs)
      if (line.find(sign) != std::string::npos) return true;
  return false;
}

// The reason a compiler's run gives, for the error message.
std::string compile_failure(const std::vector<std::string>& command, const RunResult& run,
                            const CompileCost& cost, const CompileLimits& limits,
                            const fs::path& log) {
  if (run.status == 127)
    return "cannot start the compiler '" + command.front() +
           "' (not on PATH?): set MECHGEN_CXX or CXX to a C++17 compiler, or use --solver numeric";
  const std::string size = printf_number("%.2f MB header", cost.header_mb);
  if (run.timed_out)
    return "stopped at the time limit of " + printf_number("%g s", limits.timeout_seconds) + " (" +
           size +
           printf_number(", about %.0f s expected; --compile-timeout, MECHGEN_COMPILE_TIMEOUT)",
                         cost.seconds);
  const std::string memory =
      " (" + size + printf_number(", about %.0f MB expected; ", cost.peak_mb) +
      (limits.memory_mb > 0 ? printf_number("limit %.0f MB", limits.memory_mb) : "no limit") +
      ", --compile-memory-mb, MECHGEN_COMPILE_MEMORY_MB)";
  // GCC: "virtual memory exhausted", "out of memory allocating"; Clang: std::bad_alloc.
  if (log_says(log, {"memory exhausted", "out of memory", "Cannot allocate memory", "bad_alloc"}))
    return "the compiler ran out of memory" + memory;
  if (run.status == 128 + SIGKILL)
    return "the compiler was killed (SIGKILL: out of memory?)" + memory;
  // A crash under an address-space limit is most often the limit (a stack or heap that cannot
  // grow): "internal compiler error: Segmentation fault signal terminated program cc1plus".
  if (limits.memory_mb > 0 &&
      (run.status > 128 || log_says(log, {"internal compiler error", "terminated program"})))
    return command.front() + " exit " + std::to_string(run.status) + ", a crash: out of memory?" +
           memory;
  return command.front() + " exit " + std::to_string(run.status);
}

// The size of the kernel's header among the generated files.
std::uintmax_t header_bytes(const std::vector<std::string>& written) {
  std::uintmax_t bytes = 0;
  std::error_code error;
  for (const std::string& path : written)
    if (fs::path(path).extension() == ".hpp") bytes += fs::file_size(path, error);
  return bytes;
}

// Generates and compiles the kernel into `library` with its hash record (kernel_cache.hpp): the
// header's size checked against the limit before the compiler starts, the compiler run under the
// time and memory limits (kernel_budget.hpp).
void build(const Model& model, gen::KernelKind kind, const std::string& support,
           const fs::path& cache, const std::vector<std::string>& command, const fs::path& library,
           FirstUseReport& report) {
  const BuildFolder folder(cache, model.name);
  const fs::path& dir = folder.path();
  gen::GenerateResult generated;
  try {
    const gen::GenerateOptions options{model.file, dir.string(), templates_dir(), false, support};
    if (kind == gen::KernelKind::spatial)
      generated = gen::generate_spatial(options);  // reads model.file again: load() checks it
    else
      generated = gen::generate(model, options);
  } catch (const ModelError&) {
    throw;
  } catch (const std::exception& error) {
    // The generator's own "FILE: error: " prefix is dropped (the command prints its own), and the
    // advice is given once.
    std::string why = error.what();
    const std::string prefix = model.file + ": error: ";
    if (why.rfind(prefix, 0) == 0) why.erase(0, prefix.size());
    if (why.find("--solver numeric") == std::string::npos) why += " (use --solver numeric)";
    throw std::runtime_error("cannot generate a kernel for '" + model.name + "': " + why);
  }
  const CompileCost cost = expected_compile_cost(header_bytes(generated.written));
  const CompileLimits limits = compile_limits(cost);
  check_kernel_size(model.name, cost, limits);
  std::vector<std::string> argv = command;
  const fs::path built = dir / (model.name + ".so");
  for (const std::string& word :
       {"-I" + dir.string(), "-I" + kernel_include_dir(),
        (dir / (model.name + "_entry.cpp")).string(), std::string("-o"), built.string()})
    argv.push_back(word);
  const fs::path log = dir / "compile.log";
  RunLimits run_limits;
  run_limits.timeout_seconds = limits.timeout_seconds;
  run_limits.memory_bytes = static_cast<std::uint64_t>(limits.memory_mb * 1e6);
  run_limits.tick = [&report](double seconds) { report.tick(seconds); };
  run_limits.tick_seconds = FirstUseReport::kTickSeconds;
  report.compiling(cost);
  const RunResult run = run_to_file(argv, log.string(), run_limits);
  std::error_code error;
  if (run.status != 0) {
    fs::path kept = library;
    kept.replace_extension(".log");
    fs::rename(log, kept, error);
    throw std::runtime_error("compiling the kernel of '" + model.name + "' failed (" +
                             compile_failure(command, run, cost, limits, kept) +
                             "); the compiler's output is in " + kept.string());
  }
  // Readable by all (a shared read-only cache), writable by none but its owner whatever the umask.
  fs::permissions(built, fs::perms(0644), error);
  const fs::path record = dir / "library.sha256";
  record_library_hash(built.string(), library.filename().string(), record.string());
  fs::permissions(record, fs::perms(0644), error);
  // The record first: a library is never in place without its hash (a reader that sees the new
  // record beside an older library finds them unequal and waits for this build's lock).
  fs::rename(record, library.string() + ".sha256", error);
  if (!error) fs::rename(built, library, error);
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
  std::vector<std::string> command;
  for (const char* variable : {"MECHGEN_CXX", "CXX"})
    if (const std::string value = environment(variable); !value.empty()) {
      command = compiler_words(variable, value);
      if (!command.empty()) break;
    }
  if (command.empty()) command = {"c++"};
  for (const char* word :
       {"-std=c++17", "-O2", "-march=native", "-shared", "-fPIC", "-fvisibility=hidden",
        "-ffp-contract=off", "-fno-math-errno", "-fno-trapping-math", "-DMECHGEN_KERNEL_SHARED"})
    command.push_back(word);
  return command;
}

const CompiledKernel& cached_kernel(const Model& model, std::uint64_t fingerprint,
                                    const std::string& reason, gen::KernelKind kind,
                                    const std::string& support) {
  const CacheFolder cache = open_cache_folder(cache_dir());
  const std::vector<std::string> command = compile_command();
  const std::string stem = model.name + "-" + hex64(fingerprint) + "-" + build_key(command);
  const fs::path library = fs::path(cache.path) / (stem + ".so");
  std::error_code error;
  std::string problem;
  const bool present = fs::exists(fs::symlink_status(library, error));
  if (present) {
    if (const CompiledKernel* kernel = load(library, model, fingerprint, problem)) return *kernel;
    std::cerr << "mechgen: warning: ignoring the cached kernel " << library.string() << " ("
              << problem << ")\n";
  }
  if (!cache.writable)
    throw std::runtime_error(
        (present ? "the cached kernel " + library.string() + " cannot be used (" + problem + ")"
                 : "no kernel of '" + model.name + "' for this machine and mechgen in the cache (" +
                       library.filename().string() + ")") +
        " and the kernel cache " + cache.path +
        " is read-only: build it once into a writable cache (--cache DIR), or use --solver "
        "numeric");
  const CacheLock lock((fs::path(cache.path) / (stem + ".lock")).string(),
                       "the kernel of " + model.name, cache_lock_timeout());
  remove_abandoned_builds(cache.path);
  // Another process may have built it while this one waited.
  if (fs::exists(fs::symlink_status(library, error)))
    if (const CompiledKernel* kernel = load(library, model, fingerprint, problem)) return *kernel;
  FirstUseReport report("mechgen: compiling kernel for " + model.name + reason + ", first use: ");
  const auto start = std::chrono::steady_clock::now();
  try {
    build(model, kind, support, cache.path, command, library, report);
  } catch (...) {
    report.finish("failed");
    throw;
  }
  report.finish(
      printf_number(
          "%.1f s",
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) +
      " (cached in " + cache.path + ")");
  if (const CompiledKernel* kernel = load(library, model, fingerprint, problem)) return *kernel;
  throw std::runtime_error("cannot load the kernel just compiled, " + library.string() + ": " +
                           problem);
}

}  // namespace mechgen::ondemand
