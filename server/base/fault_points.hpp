// Test-only fault injection (docs/RELIABILITY.md, "Faults"): a handler that
// throws, an allocation that fails, a Draco encode that fails, each where
// the real one would happen, so that a test can prove the server answers
// 500 problem+json without the exception's text and goes on; and load
// shedding turned off (a request past the queue is neither refused before
// its body is read nor held before its 503 goes out), so that a test can
// prove that the load test's check catches shedding that costs the cores.
//
// The production server links fault_points_off.cpp: nothing can be armed
// and Armed() is always false. Only the test build's surfdeform-server-faults
// links fault_points_on.cpp, where the HTTP layer arms, for one request, the
// faults its X-Surfdeform-Fault header names.
#pragma once

#include <string_view>

namespace surfdeform::faults {

enum class Fault { kHandlerThrows, kAllocationFails, kDracoEncodeFails, kSheddingOff };

// Arms the faults named in `spec` ("handler_throws, allocation_fails,
// draco_encode_fails, shedding_off") on the calling thread until Disarm(). False (and
// nothing armed) in a build without fault points.
bool ArmForThisThread(std::string_view spec);
void Disarm();
bool Armed(Fault fault);

// Throws std::bad_alloc where kAllocationFails is armed.
void MaybeFailAllocation();

}  // namespace surfdeform::faults
