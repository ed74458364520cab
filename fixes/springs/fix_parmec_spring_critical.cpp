// fix parmec/spring: CRITICAL time-step estimates and the EQM with full inertia tensors (spec §12, §13).
#include "fix_parmec_spring.h"
#include "rank_error.h"
#include "fix_parmec_spring_slot.h"

#include "critical_parmec_order.h"
#include "critical_step.h"
#include "equivalent_mass.h"
#include "math/inertia.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "update.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <unordered_map>

using namespace LAMMPS_NS;
namespace sp = dembridge::springs;

namespace dembridge {

using namespace spring_fix;

// CRITICAL (spec §13, kernel doc §5): per spring from the spring's EQM along its current direction
// (Constant/Planar: d; before the first step the eigen branch); per particle from every spring attached
// to it. Collective: every rank gathers the (few) numbers of all springs, then estimates its own atoms.
double FixParmecSpring::compute_vector(int n)
{
  if (crit_step_ != update->ntimestep) critical();
  crit_step_ = update->ntimestep;
  return crit_[n];
}

double FixParmecSpring::compute_array(int i, int j)
{
  if (crit_step_ != update->ntimestep) critical();
  crit_step_ = update->ntimestep;
  const std::size_t k = 3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(j);
  return k < crit_table_.size() ? crit_table_[k] : 0.0;
}

void FixParmecSpring::critical()
{
  constexpr int kRec = 15;  // tag1 tag2 k_s e dir(3) planar arm1(3) arm2(3) spring index
  const double *rmass = atom->rmass_flag ? atom->rmass : nullptr;
  auto mass_of = [&](int i) { return rmass ? rmass[i] : atom->mass[atom->type[i]]; };
  auto body = [&](int i) {
    sp::BodyMass b;
    b.mass = mass_of(i);
    // as Parmec's critical_perspring (its eqm's J⁻¹); 'critical parmec': inverted with Parmec's rounding
    b.inv_inertia = critical_parmec_ ? sp::parmec_order::inverse(inertia_.tensor(i, b.mass)) : inertia_.inverse(i, b.mass);
    return b;
  };
  sync_records();
  std::vector<double> mine, mine_rows;  // mine_rows: (table row, h, omega, xi)
  double hs = INFINITY;
  for (int i = 0; i < atom->nlocal; i++) {
    for (int s = 0; s < records_.count(i); s++) {
      const double *slot = records_.record(i, s);
      const SpringDef &d = defs_[records_.key(i, s)];
      sp::SpringState st;
      st.unpack(slot + 1);
      const bool fixed_dir = d.mode == sp::DirectionMode::Constant;
      const sp::Vec3 zdir = fixed_dir ? d.d : st.direction;
      const sp::BodyMass b1 = body(i);
      double m_s;
      int k = -1;
      if (d.tag2 >= 0) {
        k = atom->map(d.tag2);
        if (k < 0)
          fail_on_this_rank(lmp, FLERR, fmt::format("{}: CRITICAL: spring {}: part2 atom {} is not available (run at least "
                                                    "'run 0' first, or raise 'comm_modify cutoff')", cmd_, d.id, d.tag2));
        const sp::BodyMass b2 = body(k);
        m_s = sp::equivalent_mass(b1, d.arm1, &b2, d.arm2, zdir, sp::EqmArm::Correct, critical_parmec_, critical_parmec_);
      } else {
        m_s = sp::equivalent_mass(b1, d.arm1, nullptr, {0, 0, 0}, zdir, sp::EqmArm::Correct, critical_parmec_,
                                  critical_parmec_);
      }
      const sp::CriticalEstimate es = sp::spring_critical(d.law, m_s, critical_parmec_);
      hs = std::min(hs, es.step);
      const double row[4] = {double(records_.key(i, s)), es.step, es.omega, es.xi};
      mine_rows.insert(mine_rows.end(), row, row + 4);
      const bool planar = d.mode == sp::DirectionMode::Planar;
      const sp::Vec3 adir = planar ? d.d : zdir;
      const double rec[kRec] = {double(d.tag1), double(d.tag2), d.law.spring->max_abs_slope(),
                                sp::spring_max_damping(d.law, m_s), adir[0], adir[1], adir[2], planar ? 1.0 : 0.0,
                                d.arm1[0], d.arm1[1], d.arm1[2], d.arm2[0], d.arm2[1], d.arm2[2],
                                double(records_.key(i, s))};
      mine.insert(mine.end(), rec, rec + kRec);
    }
  }
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(comm->nprocs), displs(comm->nprocs, 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> all(displs.back() + counts.back());
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), displs.data(), MPI_DOUBLE, world);

  // the springs in definition order (Parmec's spring order), whichever rank holds them: the sums per particle
  // do not depend on the decomposition
  std::vector<const double *> order;
  for (std::size_t r = 0; r + kRec <= all.size(); r += kRec) order.push_back(&all[r]);
  std::sort(order.begin(), order.end(), [](const double *a, const double *b) { return a[kRec - 1] < b[kRec - 1]; });
  std::unordered_map<tagint, sp::ParticleCritical> particles;
  std::unordered_map<tagint, int> owned;
  for (int i = 0; i < atom->nlocal; i++) owned[atom->tag[i]] = i;
  for (const double *e : order) {
    const sp::Vec3 dir{e[4], e[5], e[6]};
    for (int side = 0; side < 2; side++) {
      const tagint t = static_cast<tagint>(e[side]);
      if (t < 0 || !owned.count(t)) continue;
      particles.try_emplace(t, critical_parmec_).first->second.add_spring(e[2], e[3], dir, e[7] != 0.0, {e[8 + 3 * side], e[9 + 3 * side], e[10 + 3 * side]});
    }
  }
  double hp = INFINITY;
  for (auto &kv : particles) {
    const int i = owned[kv.first];
    std::array<double, 9> J = inertia_.tensor(i, mass_of(i));
    if (!(J[0] > 0.0)) J = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // no radius, no inertia property
    const sp::CriticalEstimate ep = kv.second.estimate(mass_of(i), J);
    hp = std::min(hp, ep.step);
    const double row[4] = {double(defs_.size()) + double(kv.first - 1), ep.step, ep.omega, ep.xi};
    mine_rows.insert(mine_rows.end(), row, row + 4);
  }
  // every rank gets the whole table (few numbers: one row per spring and per atom)
  const std::size_t nrows = defs_.size() + static_cast<std::size_t>(atom->natoms);
  std::vector<double> table(3 * nrows, 0.0);
  for (std::size_t r = defs_.size(); r < nrows; r++) table[3 * r] = DBL_MAX;
  n = static_cast<int>(mine_rows.size());
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, world);
  for (int p = 1; p < comm->nprocs; p++) displs[p] = displs[p - 1] + counts[p - 1];
  std::vector<double> rows(displs.back() + counts.back());
  MPI_Allgatherv(mine_rows.data(), n, MPI_DOUBLE, rows.data(), counts.data(), displs.data(), MPI_DOUBLE, world);
  for (std::size_t r = 0; r + 4 <= rows.size(); r += 4) {
    const std::size_t at = 3 * static_cast<std::size_t>(rows[r]);
    if (at + 2 < table.size()) std::copy(&rows[r + 1], &rows[r + 4], &table[at]);
  }
  crit_table_.swap(table);
  MPI_Allreduce(&hs, &crit_[0], 1, MPI_DOUBLE, MPI_MIN, world);
  MPI_Allreduce(&hp, &crit_[1], 1, MPI_DOUBLE, MPI_MIN, world);
}

// At every run's set-up: a timestep beyond the critical one (a spring table much stiffer than the step was
// chosen for) makes the explicit integration blow up within a few steps without a word; say so first.
void FixParmecSpring::warn_beyond_critical()
{
  if (defs_.empty()) return;
  // CRITICAL needs every part2 as a local or ghost atom; where one is not (a partner reached otherwise), no check
  int mapped = 1, all_mapped = 1;
  for (int i = 0; i < atom->nlocal; i++)
    for (int s = 0; s < records_.count(i); s++) {
      const SpringDef &d = defs_[records_.key(i, s)];
      if (d.tag2 >= 0 && atom->map(d.tag2) < 0) mapped = 0;
    }
  MPI_Allreduce(&mapped, &all_mapped, 1, MPI_INT, MPI_MIN, world);
  if (!all_mapped) return;
  critical();
  crit_step_ = update->ntimestep;
  const double h = crit_[1] < DBL_MAX ? crit_[1] : crit_[0];  // per particle (CRITICAL()), else per spring
  if (comm->me != 0 || !(std::isfinite(h) && h > 0.0) || !(update->dt > h)) return;
  const bool particle = crit_[1] < DBL_MAX;
  std::size_t row = particle ? defs_.size() : 0, end = particle ? crit_table_.size() / 3 : defs_.size();
  for (std::size_t r = row; r < end; r++)
    if (crit_table_[3 * r] == h) {
      row = r;
      break;
    }
  const std::string who = particle ? fmt::format("per particle, atom {}", row - defs_.size() + 1)
                                   : fmt::format("per spring, spring {}", defs_[row].id);
  error->warning(FLERR, fmt::format("{}: timestep {:.6g} is {:.3g} times the critical step {:.6g} of the springs "
                                    "(CRITICAL, {}): the explicit integration is unstable beyond it; use a timestep "
                                    "below {:.6g} (Parmec scripts take 0.1 to 0.5 of it)",
                                    cmd_, update->dt, update->dt / h, h, who, h));
}

// EQM with the full 3x3 inverse inertia (zero direction: largest point mass; 'eqm parmec': Q8 arm).
// The tensor is referential, as in Parmec's eqm() (its arms and J⁻¹ are the reference ones).
double FixParmecSpring::spring_eqm_general(const EvalContext &c, const SpringDef &d, int i, int k,
                                           const sp::Vec3 &dir) const
{
  auto mass_of = [&](int j) { return c.rmass ? c.rmass[j] : c.mass[c.type[j]]; };
  auto body = [&](int j, const sp::Vec3 &X) {
    if (c.inertia && c.inertia[j][0] > 0.0)  // (an atom without a tensor: the sphere's, as CRITICAL)
      return sp::BodyMass::from_inertia_list(mass_of(j), c.inertia[j], q8_arm_ ? X : sp::Vec3{});
    sp::BodyMass b;
    b.mass = mass_of(j);
    b.inv_inertia = math::inverse_inertia(math::sphere_inertia(b.mass, c.radius ? c.radius[j] : 0.0));
    if (q8_arm_) b.centre = X;
    return b;
  };
  // Correct arm: centre 0, point = body-frame arm (A = -arm). Q8: centre X0, point X0 + arm.
  const sp::BodyMass b1 = body(i, d.X1ref);
  const sp::Vec3 p1 = q8_arm_ ? d.X1ref + d.arm1 : d.arm1;
  const auto arm = q8_arm_ ? sp::EqmArm::ParmecQ8 : sp::EqmArm::Correct;
  if (k >= 0) {
    const sp::BodyMass b2 = body(k, d.X2ref);
    return sp::equivalent_mass(b1, p1, &b2, q8_arm_ ? d.X2ref + d.arm2 : d.arm2, dir, arm, parmec_order_);
  }
  return sp::equivalent_mass(b1, p1, nullptr, {0, 0, 0}, dir, arm, parmec_order_);
}

}  // namespace dembridge
