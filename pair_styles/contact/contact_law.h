// A contact law composed of sub-models (normal, damping, tangential, rolling, cohesion, viscous),
// evaluated for one pair or one particle-wall contact. LAMMPS-free; the pair and wall glue loop
// over neighbours.
#pragma once

#include "contact_config.h"
#include "contact_geometry.h"
#include "contact_result.h"
#include "normal_models.h"
#include "pair_coeffs.h"
#include "cohesion_models.h"
#include "lammps_models.h"
#include "rolling_models.h"
#include "tangential_models.h"
#include "wall_geometry.h"

namespace dembridge::gran {

class ContactLaw {
 public:
  explicit ContactLaw(const ContactConfig &cfg = {}) : cfg_(cfg) {}
  const ContactConfig &config() const { return cfg_; }

  // Evaluates the pair (i = a, j = b). Returns false when they do not touch.
  // meff: effective mass after the freeze/rigid rules; history: history_size() doubles or null.
  bool evaluate(const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc, double *history,
                bool history_update, double dt, ContactResult &out) const;
  // Evaluates particle a against a wall point (spec liggghts-walls §2); the caller has checked
  // that they touch. meff: the particle's (or its body's) mass.
  void evaluate_wall(const SphereView &a, const WallTouch &w, double meff, const PairCoeffs &pc, double *history,
                     bool history_update, double dt, ContactResult &out) const;

 private:
  ContactConfig cfg_;

 public:
  // The sub-models on a contact geometry, for a given configuration. The pair kernels pass a copy
  // of config() whose normal/tangential fields are compile-time constants, so the switches fold.
  template <bool Wall>
  static void apply_laws(const ContactConfig &cfg, const ContactGeometry &g, const SphereView &a, const double *roll_wi,
                         const double *roll_wj, double mj, double rj, double meff, const PairCoeffs &pc, double *history,
                         bool history_update, double dt, ContactResult &out);
};

// Normal, cohesion, tangential and rolling sub-models on a contact geometry. roll_wi - roll_wj is
// the relative rotation of the rolling models: ω_i − ω_j for pairs, the wall's cr·ω_i/r − 0 (exact)
// for walls. Walls also use the cap-area cohesion and the wall rolling rules; mj, rj are unused.
// R: double (one contact) or Lanes4 (four pairs, lane_math.h; configurations of
// liggghts_laws_have_lanes).
template <bool Wall, class R>
[[gnu::always_inline]] inline void apply_contact_laws(const ContactConfig &cfg, const ContactGeometryT<R> &g, R radi, R massi,
                                                    const R *roll_wi, const R *roll_wj, R mj, R rj, R meff, const PairCoeffsT<R> &pc,
                                                    R *history, bool history_update, double dt, ContactResultT<R> &out)
{
  const NormalCoefficientsT<R> c = normal_coefficients(cfg, pc, g, meff);

  R Fn = -c.gamman * g.vn + c.kn * g.delta;
  if (cfg.limit_force) Fn = lane_select(Fn < 0.0, lane_splat(0.0, Fn), Fn);
  // Cohesion pulls along n; with tangential_reduce (always in 2.x) it also lowers the Coulomb
  // and rolling limits (spec §6).
  R Fcoh = lane_splat(0.0, Fn);
  if (cfg.cohesion != CohesionModel::Off)
    Fcoh = Wall ? cohesion_force_wall(cfg.cohesion, g, radi, pc.cohesion_energy_density)
                : cohesion_force(cfg.cohesion, g, radi, rj, pc.cohesion_energy_density);
  const R Fn_limit = cfg.tangential_reduce ? Fn + Fcoh : Fn;
  out.Fn = Fn + Fcoh;
  out.delta = g.delta;

  const R Ft_max = pc.mu * lane_fabs(Fn_limit);
  R *Ft = out.Ft;
  R *shear = history;
  switch (cfg.tangential) {
    default:  // None; 'default' tells GCC every path writes Ft (-Wmaybe-uninitialized)
      Ft[0] = Ft[1] = Ft[2] = lane_splat(0.0, Fn);
      break;
    case TangentialModel::NoHistory: tangential_no_history(g, c.gammat, Ft_max, Ft); break;
    case TangentialModel::History:
      tangential_history(g, c.kt, c.gammat, Ft_max, dt, history_update, cfg.legacy_2x_expressions, shear, Ft);
      break;
  }

  R tor[3];
  cross3(g.n, Ft, tor);
  for (int k = 0; k < 3; ++k) {
    out.F[k] = Fn * g.n[k] + Fcoh * g.n[k] + Ft[k];
    out.Ti[k] = -g.cri * tor[k];
    out.Tj[k] = -g.crj * tor[k];
  }
  if (cfg.rolling != RollingModel::Off) {
    R *rolling_history = history + (cfg.tangential == TangentialModel::History ? 3 : 0);
    const RollingInputT<R> in{c.kn, c.kt, Fn_limit, pc.mu_roll, pc.eta_roll, pc.roll_stiffness, massi, mj, radi, rj, Wall, g.cri};
    R M[3];
    rolling_torque(cfg, g, roll_wi, roll_wj, in, dt, history_update, rolling_history, M);
    for (int k = 0; k < 3; ++k) {
      out.Ti[k] -= M[k];
      out.Tj[k] += M[k];
    }
  }
}

// The configurations whose laws have a lane form (all but rolling cdt).
inline bool liggghts_laws_have_lanes(const ContactConfig &cfg) { return !cfg.lammps_formulation && rolling_has_lanes(cfg.rolling); }

// The coefficients the LIGGGHTS laws may read with normal model n (a mask over PairCoeffFields,
// pair_coeffs.h): the normal model's, friction, rolling and cohesion. The AVX2 loop moves only these.
constexpr unsigned liggghts_coeff_fields(NormalModel n)
{
  using P = PairCoeffs;
  const unsigned common = coeff_mask(&P::mu, &P::mu_roll, &P::eta_roll, &P::roll_stiffness, &P::cohesion_energy_density);
  switch (n) {
    case NormalModel::Hooke:
      return common | coeff_mask(&P::Yeff, &P::char_vel, &P::lnE, &P::fluid_viscosity, &P::critical_stokes, &P::ln_max_restitution);
    case NormalModel::Hertz: return common | coeff_mask(&P::Yeff, &P::Geff, &P::beta);
    case NormalModel::HookeStiffness:
    case NormalModel::HertzStiffness: break;
  }
  return common | coeff_mask(&P::kn, &P::kt, &P::gamman, &P::gammat);
}

template <bool Wall>
[[gnu::always_inline]] inline void ContactLaw::apply_laws(const ContactConfig &cfg, const ContactGeometry &g, const SphereView &a,
                                                         const double *roll_wi, const double *roll_wj, double mj, double rj,
                                                         double meff, const PairCoeffs &pc, double *history, bool history_update,
                                                         double dt, ContactResult &out)
{
  apply_contact_laws<Wall>(cfg, g, a.radius, a.mass, roll_wi, roll_wj, mj, rj, meff, pc, history, history_update, dt, out);
}

// always_inline: the neighbour loop is the hot path; without it GCC stopped inlining once the
// rolling/cohesion/viscous branches were added (+27 % instructions, bench/).
[[gnu::always_inline]] inline bool ContactLaw::evaluate(const SphereView &a, const SphereView &b, double meff, const PairCoeffs &pc,
                                 double *history, bool history_update, double dt, ContactResult &out) const
{
  if (cfg_.lammps_formulation) return evaluate_lammps_gran(cfg_, a, b, meff, pc, history, history_update, dt, out);
  ContactGeometry g;
  if (!make_geometry(a, b, true, g)) return false;
  apply_laws<false>(cfg_, g, a, a.omega, b.omega, b.mass, b.radius, meff, pc, history, history_update, dt, out);
  return true;
}

// The wall form (spec liggghts-walls §2): the wall is j with infinite mass and radius.
inline void ContactLaw::evaluate_wall(const SphereView &a, const WallTouch &w, double meff, const PairCoeffs &pc, double *history,
                                      bool history_update, double dt, ContactResult &out) const
{
  ContactGeometry g;
  make_wall_geometry(a, w, g);
  static constexpr double kNoSpin[3] = {0.0, 0.0, 0.0};
  apply_laws<true>(cfg_, g, a, g.wr_wall, kNoSpin, 0.0, 0.0, meff, pc, history, history_update, dt, out);
}

// One touching pair of the LIGGGHTS laws with the neighbour loop's del and rsq reused; the normal
// and tangential models are template arguments (the other switches stay run-time: they cost a
// test each, the models a whole dispatch).
template <NormalModel Normal, TangentialModel Tangential>
[[gnu::always_inline]] inline void liggghts_pair_touching(const ContactConfig &config, const SphereView &a, const SphereView &b,
                                                        const double *del, double rsq, double meff, const PairCoeffs &pc,
                                                        double *history, bool history_update, double dt, ContactResult &out)
{
  ContactConfig cfg = config;
  cfg.normal = Normal;
  cfg.tangential = Tangential;
  ContactGeometry g;
  make_touching_geometry(a, b, del, rsq, true, g);
  ContactLaw::apply_laws<false>(cfg, g, a, a.omega, b.omega, b.mass, b.radius, meff, pc, history, history_update, dt, out);
}

// Four touching pairs (R = Lanes4) or one (double): the geometry and the laws, from the gathered
// atom data. cfg: liggghts_laws_have_lanes.
template <NormalModel Normal, TangentialModel Tangential, class R>
[[gnu::always_inline]] inline void liggghts_pair_law(const ContactConfig &config, const R *del, R rsq, R radi, R radj, const R *vi,
                                                   const R *vj, const R *wi, const R *wj, R mi, R mj, R meff, const PairCoeffsT<R> &pc,
                                                   R *history, bool history_update, double dt, ContactResultT<R> &out)
{
  ContactConfig cfg = config;
  cfg.normal = Normal;
  cfg.tangential = Tangential;
  ContactGeometryT<R> g;
  touching_geometry(del, rsq, radi, radj, vi, vj, wi, wj, true, g);
  apply_contact_laws<false>(cfg, g, radi, mi, wi, wj, mj, radj, meff, pc, history, history_update, dt, out);
}

}  // namespace dembridge::gran
