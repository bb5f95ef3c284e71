#pragma once
// The movers' shapes, each built in its own frame as a small Scene (mesh plus the objects whose
// colour and variant drive the procedural textures).

#include <cstdint>

#include "artemis/sim/traffic.hpp"
#include "noise.hpp"

namespace artemis::sim::detail {

// A car of variant 0..2 (sedan, hatchback, van) with a paint drawn from `rng`; sets the mover's
// shape and half extents.
void buildCarShape(Mover& mover, const SceneParams& params, Rng& rng);
// A bicycle with its rider (class bicyclist).
void buildCyclistShape(Mover& mover, const SceneParams& params, Rng& rng);
// A person walking along its x axis.
void buildWalkerShape(Mover& mover, const SceneParams& params, Rng& rng);

}  // namespace artemis::sim::detail
