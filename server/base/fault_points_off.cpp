// The production build: no fault can be armed (base/fault_points.hpp).
#include "base/fault_points.hpp"

namespace surfdeform::faults {

bool ArmForThisThread(std::string_view) { return false; }
void Disarm() {}
bool Armed(Fault) { return false; }
void MaybeFailAllocation() {}

}  // namespace surfdeform::faults
