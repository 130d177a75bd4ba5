// The test build's fault points (base/fault_points.hpp): linked into
// surfdeform-server-faults only, in place of fault_points_off.cpp.
#include <new>

#include "base/fault_points.hpp"

namespace surfdeform::faults {
namespace {

thread_local unsigned t_armed = 0;

unsigned Bit(Fault f) { return 1u << static_cast<unsigned>(f); }

}  // namespace

bool ArmForThisThread(std::string_view spec) {
  t_armed = 0;
  const std::pair<std::string_view, Fault> names[] = {
      {"handler_throws", Fault::kHandlerThrows},
      {"allocation_fails", Fault::kAllocationFails},
      {"draco_encode_fails", Fault::kDracoEncodeFails},
      {"shedding_off", Fault::kSheddingOff}};
  for (const auto& [name, fault] : names) {
    if (spec.find(name) != std::string_view::npos) t_armed |= Bit(fault);
  }
  return true;
}

void Disarm() { t_armed = 0; }

bool Armed(Fault fault) { return (t_armed & Bit(fault)) != 0; }

void MaybeFailAllocation() {
  if (Armed(Fault::kAllocationFails)) throw std::bad_alloc();
}

}  // namespace surfdeform::faults
