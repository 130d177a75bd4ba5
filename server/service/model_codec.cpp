#include "service/model_codec.hpp"

#include <bit>
#include <cstdint>
#include <cstring>

#include "proto/api.hpp"

namespace surfdeform {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the model format stores little-endian numbers as they are in memory");

constexpr char kMagic[4] = {'S', 'D', 'F', 'M'};
constexpr size_t kHeaderBytes = sizeof kMagic + sizeof(uint32_t) + sizeof(uint64_t);

Status Refused(const std::string& why) {
  return Status(ErrorCode::kMalformed, "the shared model " + why, "shared_tier");
}

}  // namespace

std::string ModelKey(std::string_view id) {
  return "surfdeform:model:v" + std::to_string(kModelFormatVersion) + ":" + std::string(id);
}

std::string EncodeModel(std::string_view file_bytes) {
  std::string out(kMagic, sizeof kMagic);
  const uint32_t version = kModelFormatVersion;
  const uint64_t size = file_bytes.size();
  out.append(reinterpret_cast<const char*>(&version), sizeof version);
  out.append(reinterpret_cast<const char*>(&size), sizeof size);
  out.append(file_bytes);
  return out;
}

Result<std::string> DecodeModel(std::string_view value, std::string_view id, size_t max_bytes) {
  if (value.size() < kHeaderBytes || std::memcmp(value.data(), kMagic, sizeof kMagic) != 0) {
    return Refused("is not a surfdeform model value");
  }
  uint32_t version = 0;
  uint64_t size = 0;
  std::memcpy(&version, value.data() + sizeof kMagic, sizeof version);
  std::memcpy(&size, value.data() + sizeof kMagic + sizeof version, sizeof size);
  if (version != kModelFormatVersion) {
    return Refused("has format version " + std::to_string(version) + ", not " +
                   std::to_string(kModelFormatVersion));
  }
  if (size > max_bytes || size != value.size() - kHeaderBytes) {
    return Refused("is truncated or longer than its header says");
  }
  std::string bytes(value.substr(kHeaderBytes));
  if (proto::ModelId(bytes) != id) return Refused("does not hash to its id");
  return bytes;
}

}  // namespace surfdeform
