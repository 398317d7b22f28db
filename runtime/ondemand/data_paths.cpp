#include "ondemand/data_paths.hpp"

#include <dlfcn.h>
#include <elf.h>
#include <link.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/fingerprint.hpp"

#ifndef MECHGEN_SOURCE_DIR
#error "MECHGEN_SOURCE_DIR must name the source tree (set by runtime/ondemand/CMakeLists.txt)"
#endif

namespace mechgen::ondemand {

namespace fs = std::filesystem;

namespace {

// <prefix>/share/mechgen when this executable is <prefix>/bin/<name> of an installed mechgen, or
// when this code is in an installed shared object below <prefix> (the Python module in
// <prefix>/lib/python3.X/site-packages, up to five folders deep: Debian's lib/<multiarch>/...),
// whose interpreter is no mechgen.
fs::path installed_data_dir() {
  std::error_code error;
  const auto data = [&error](const fs::path& prefix) {
    const fs::path share = prefix / "share" / "mechgen";
    return fs::exists(share / "templates" / "kernel.hpp.in", error) ? share : fs::path{};
  };
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path share = data(exe.parent_path().parent_path());
    if (!share.empty()) return share;
  }
  Dl_info self{};
  if (::dladdr(reinterpret_cast<void*>(&installed_data_dir), &self) == 0 || !self.dli_fname)
    return {};
  const fs::path object = fs::absolute(self.dli_fname, error);
  if (error || object == exe) return {};
  fs::path folder = object.parent_path();
  for (int up = 0; up < 5 && folder.has_relative_path(); ++up) {
    folder = folder.parent_path();
    const fs::path share = data(folder);
    if (!share.empty()) return share;
  }
  return {};
}

// The main program's NT_GNU_BUILD_ID note, as hex, or "" when it has none.
int find_build_id(dl_phdr_info* info, size_t, void* data) {
  auto& id = *static_cast<std::string*>(data);
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& header = info->dlpi_phdr[i];
    if (header.p_type != PT_NOTE) continue;
    const char* note = reinterpret_cast<const char*>(info->dlpi_addr + header.p_vaddr);
    const char* end = note + header.p_memsz;
    while (note + sizeof(ElfW(Nhdr)) <= end) {
      ElfW(Nhdr) n;
      std::memcpy(&n, note, sizeof n);
      const char* name = note + sizeof n;
      const char* desc = name + ((n.n_namesz + 3) & ~3u);
      if (n.n_type == NT_GNU_BUILD_ID && n.n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0) {
        static const char digits[] = "0123456789abcdef";
        for (unsigned k = 0; k < n.n_descsz; ++k) {
          const auto byte = static_cast<unsigned char>(desc[k]);
          id += digits[byte >> 4];
          id += digits[byte & 15];
        }
        return 1;
      }
      note = desc + ((n.n_descsz + 3) & ~3u);
    }
  }
  return 1;  // only the first object, the main program
}

}  // namespace

std::string templates_dir() {
  const fs::path installed = installed_data_dir();
  return (installed.empty() ? fs::path(MECHGEN_SOURCE_DIR) / "templates" : installed / "templates")
      .string();
}

std::string kernel_include_dir() {
  const fs::path installed = installed_data_dir();
  return (installed.empty() ? fs::path(MECHGEN_SOURCE_DIR) / "runtime" : installed / "include")
      .string();
}

std::string executable_id() {
  std::string id;
  dl_iterate_phdr(&find_build_id, &id);
  if (!id.empty()) return "build-id " + id;
  std::ifstream exe("/proc/self/exe", std::ios::binary);
  std::stringstream bytes;
  bytes << exe.rdbuf();
  Fnv1a64 hash;
  hash.add(bytes.str());
  return "file " + hex64(hash.value());
}

}  // namespace mechgen::ondemand
