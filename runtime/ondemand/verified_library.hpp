// A cached kernel library and the content hash recorded beside it (<library>.sha256, in the format
// of `sha256sum`: "<64 hex digits>  <file name>\n"): written by the process that built the library,
// checked before the library is loaded (kernel_cache.hpp).
#pragma once

#include <string>

namespace mechgen::ondemand {

// Writes `built`'s hash, naming it as `final_name`, into the file `record` (a private build
// folder's; renamed into the cache by the builder). Throws std::runtime_error when it cannot.
void record_library_hash(const std::string& built, const std::string& final_name,
                         const std::string& record);

// dlopen's handle for `library` when it is a trusted file (cache_folder.hpp) whose SHA-256 is the
// one recorded beside it; otherwise nullptr with the reason in `problem`. Loaded through the
// descriptor that was hashed, which stays open for the process's lifetime.
void* open_verified_library(const std::string& library, std::string& problem);

}  // namespace mechgen::ondemand
