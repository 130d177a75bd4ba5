// A DeformMemo that recalls what a test gives it and asks for the footprint
// when told to: the engine's reuse without the service's memo.
#pragma once

#include <memory>
#include <optional>

#include "engine/deform/deform.hpp"

namespace surfdeform::testing {

struct GivenMemo final : DeformMemo {
  std::optional<Placement> placement;
  std::shared_ptr<const SheetFootprint> footprint;
  std::optional<SubdivisionStats> unrefined;
  bool record_footprint = false;

  std::optional<Placement> RecallPlacement() const override { return placement; }
  std::shared_ptr<const SheetFootprint> RecallFootprint() const override { return footprint; }
  std::optional<SubdivisionStats> RecallUnrefined() const override { return unrefined; }
  bool WantsFootprint() const override { return record_footprint; }
};

}  // namespace surfdeform::testing
