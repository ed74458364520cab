// What differs between the LAMMPS versions dembridge supports (4 Feb 2025 and later), in one place.
// Kept free of LAMMPS headers: templates on the LAMMPS class, checked by tests/unit/test_lammps_compat.cpp.
#pragma once

#include <string>

namespace dembridge {

namespace compat_detail {
// Domain::minimum_image takes the caller's file and line (FLERR) since mid-2025 (after 4 Feb 2025,
// in 22 Jul 2025); before, only the displacement. The int/long argument prefers the newer form.
template <class D>
auto minimum_image(const D *d, const std::string &file, int line, double *v, int)
    -> decltype(d->minimum_image(file, line, v), void())
{
  d->minimum_image(file, line, v);
}
template <class D> void minimum_image(const D *d, const std::string &, int, double *v, long) { d->minimum_image(v); }
template <class D>
auto minimum_image(const D *d, const std::string &file, int line, double &x, double &y, double &z, int)
    -> decltype(d->minimum_image(file, line, x, y, z), void())
{
  d->minimum_image(file, line, x, y, z);
}
template <class D> void minimum_image(const D *d, const std::string &, int, double &x, double &y, double &z, long)
{
  d->minimum_image(x, y, z);
}
}  // namespace compat_detail

// domain->minimum_image(FLERR, d) of every supported LAMMPS: dembridge::minimum_image(domain, FLERR, d)
template <class D> void minimum_image(const D *d, const std::string &file, int line, double *v)
{
  compat_detail::minimum_image(d, file, line, v, 0);
}
template <class D> void minimum_image(const D *d, const std::string &file, int line, double &dx, double &dy, double &dz)
{
  compat_detail::minimum_image(d, file, line, dx, dy, dz, 0);
}

}  // namespace dembridge
