// SHA-256 (FIPS 180-4), for the content hash the kernel cache records beside each library it
// builds and checks before loading one (kernel_cache.hpp). Written here: no new dependency for
// some 80 lines; checked against coreutils' sha256sum (tests/ondemand_cache_security_test.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace mechgen::ondemand {

class Sha256 {
 public:
  Sha256();
  void add(const void* data, std::size_t size);
  // The digest as 64 lowercase hex digits; the object is spent afterwards.
  std::string hex();

 private:
  void block(const unsigned char* bytes);

  std::uint32_t state_[8];
  unsigned char buffer_[64];
  std::size_t buffered_ = 0;
  std::uint64_t length_ = 0;  // bytes added
};

// The SHA-256 of everything readable from `fd` from its start (pread: the offset is not moved);
// "" when a read fails.
std::string sha256_of_fd(int fd);

}  // namespace mechgen::ondemand
