// Constant parameters of one spring's force law (spec parmec-springs §4-§6). Tables are owned by the
// caller (defined once, referenced by many springs) and must outlive the law.
#pragma once

#include "spring_table.h"

namespace dembridge::springs {

struct SpringLaw {
  const SpringTable* spring = nullptr;   // elastic force vs stroke (required)
  const SpringTable* dashpot = nullptr;  // dashpot force vs velocity; null = none, unless a ratio is given
  double damping_ratio = -1.0;           // >= 0: critical damping ratio instead of a table (spec §5)
  const SpringTable* unload = nullptr;   // set: GENERAL_NONLINEAR (spec §4.2), else NONLINEAR_ELASTIC
  double ylim_comp = 0.0;                // compression yield limit, <= 0 (default 0: yields at first force)
  double ylim_tens = 0.0;                // tension yield limit, >= 0
  const SpringTable* offset = nullptr;   // stroke offset o(t), linearly extrapolated (Q5), only before yield
  double friction = 0.0;                 // mu >= 0
  double kskn = 0.0;                     // >= 0; 0 = pure sliding friction (spec §6)
  bool fused = false;                    // Parmec's arithmetic: table values by fused multiply-add

  bool general() const { return unload != nullptr; }
  bool ratio_dashpot() const { return damping_ratio >= 0.0; }
  // The equivalent mass (EQM along z) is needed only for a ratio dashpot.
  bool needs_equivalent_mass() const { return ratio_dashpot(); }

  // Throws std::invalid_argument naming the broken rule (spec §2.1 input validation).
  void validate() const;
};

}  // namespace dembridge::springs
