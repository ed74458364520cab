// The Rayleigh and Hertz time estimates of LIGGGHTS 3.8's fix check/timestep/gran, LAMMPS-free so that
// the fix and the pair styles' own time-step check compute them alike (same operations, same order).
#pragma once

namespace dembridge::gran {

// Rayleigh-wave time of a sphere of radius r, density rho, Young's modulus Y, Poisson ratio nu:
// pi r sqrt(rho / G) / (0.1631 nu + 0.8766), G = Y / (2 (nu + 1)).
double rayleigh_time(double r, double rho, double Y, double nu);

// Effective modulus of a type pair, LIGGGHTS's Yeff: 1 / ((1 - nu_i^2)/Y_i + (1 - nu_j^2)/Y_j).
double effective_modulus(double Yi, double nui, double Yj, double nuj);

// Hertz contact time of a sphere hitting its twin at relative speed v_rel (LIGGGHTS's estimate):
// 2.87 (m^2 / (r/2 Yeff^2 v_rel))^0.2 with m = 4/3 pi r^3 rho.
double hertz_time(double r, double rho, double Yeff, double v_rel);

// The relative speed the estimates use: max(2 v_particle, v_particle + v_mesh).
double relative_speed(double vmax_particle, double vmax_mesh);

// Sphere density from its mass (LAMMPS keeps mass, LIGGGHTS density): m / (4/3 pi r^3).
double sphere_density(double mass, double r);

}  // namespace dembridge::gran
