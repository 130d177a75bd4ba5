// What a request says about a flattening ("flatten" of POST /v1/surfaces):
// the method and its parameters. Plain vocabulary, which the API's request
// types (proto/) share with the engine; how a flattening runs (threads, time
// budget, limits) is the engine's FlattenOptions (flatten.hpp), which the
// service fills.
#pragma once

#include "base/enum_table.hpp"
#include "base/status.hpp"

namespace surfdeform {

enum class FlattenMethod { kMajorization, kPaper };
inline constexpr EnumEntry<FlattenMethod> kFlattenMethods[] = {
    {FlattenMethod::kMajorization, "majorization",
     "stress majorization (Guttman transform), the default"},
    {FlattenMethod::kPaper, "paper", "the paper's gradient descent (the baseline)"},
};

const char* FlattenMethodName(FlattenMethod method);

struct FlattenSettings {
  FlattenMethod method = FlattenMethod::kMajorization;
  int range = 3;                  // r: grid range of the neighbourhood Omega_i, 1..8
  double tolerance = 1e-7;        // stop when an iteration lowers C by less than this fraction
  int max_iterations = 0;         // 0 = the method's default (majorization 3000, paper 200000)
  double step = 0.0;              // the paper's rho; 0 = automatic, 1 / (8 max |Omega_i|)
  bool exact_developable = true;  // unroll analytic cylinder and cone patches in closed form
  int lattice_factor = 0;         // distance integration lattice per cell side; 0 = automatic
  int relax_steps = 2;            // geodesic relaxation steps per pair; 0 = straight segments
};

// kInvalidArgument naming the field without a prefix ("range").
Status ValidateFlattenSettings(const FlattenSettings& settings);

}  // namespace surfdeform
