// The subdivision's modes and their names: plain vocabulary, which the API
// contract and the command-line client share with the engine (no algorithm).
#pragma once

#include "base/enum_table.hpp"

namespace surfdeform {

enum class SubdivisionMode { kOff, kAdaptive, kUniform };
inline constexpr EnumEntry<SubdivisionMode> kSubdivisionModes[] = {
    {SubdivisionMode::kOff, "off", "no refinement: the input's vertex order and count kept"},
    {SubdivisionMode::kAdaptive, "adaptive",
     "the paper's grid points where the surface bends, refined to the tolerance"},
    {SubdivisionMode::kUniform, "uniform", "every grid point of every large face (the reference)"},
};

}  // namespace surfdeform
