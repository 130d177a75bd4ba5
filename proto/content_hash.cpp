#include "proto/content_hash.hpp"

#include <openssl/evp.h>

#include <algorithm>

namespace surfdeform::proto {

std::string Sha256Hex(std::string_view bytes, size_t hex_digits) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int k = 0; k < length && hex.size() < hex_digits; ++k) {
    hex.push_back(kHex[digest[k] >> 4]);
    hex.push_back(kHex[digest[k] & 15]);
  }
  hex.resize(std::min(hex.size(), hex_digits));
  return hex;
}

}  // namespace surfdeform::proto
