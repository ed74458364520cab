// Per-slot "in contact" flag of the list-order contact history. An enum, not unsigned char: a
// store through a char type may alias anything, which made the compiler reload every array
// pointer of the neighbour loop after each flag store (issue 12, callgrind).
#pragma once

namespace dembridge::gran {

enum class TouchFlag : unsigned char { Separated = 0, Touching = 1 };

// Flags the history keeps after its last slot, so that four flags can be read from any slot on.
constexpr int kTouchPadding = 3;

}  // namespace dembridge::gran
