// The heat conduction kernel (fixes/heat) and the time-step estimates (pair_styles/materials) against
// closed forms and values measured on LIGGGHTS 3.8.
#include "heat_conduction.h"
#include "timestep_estimates.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace dembridge;

TEST(HeatConduction, OverlapAreaIsTheIntersectionCircle)
{
  // equal spheres R at distance r: circle radius^2 = R^2 - (r/2)^2
  const double R = 0.004, r = 0.0079;
  const double expect = M_PI * (R * R - r * r / 4);
  EXPECT_NEAR(heat::overlap_contact_area(r, R, R), expect, 1e-12 * expect);
  // unequal spheres: a^2 = ri^2 - d_i^2 with d_i = (r^2 + ri^2 - rj^2) / (2 r)
  const double ri = 0.003, rj = 0.005, d = 0.0075;
  const double di = (d * d + ri * ri - rj * rj) / (2 * d);
  const double expect2 = M_PI * (ri * ri - di * di);
  EXPECT_NEAR(heat::overlap_contact_area(d, ri, rj), expect2, 1e-12 * expect2);
}

TEST(HeatConduction, ConductanceIsTheHarmonicMeanTimesRootArea)
{
  EXPECT_DOUBLE_EQ(heat::contact_conductance(100., 40., 4e-6), 4. * 100. * 40. / 140. * 2e-3);
  EXPECT_EQ(heat::contact_conductance(0., 40., 4e-6), 0.0);  // LIGGGHTS: a conductivity < 1e-5 conducts nothing
}

TEST(HeatConduction, TemperatureStep)
{
  EXPECT_DOUBLE_EQ(heat::updated_temperature(300., 2., 1., 1e-3, 0.5, 10.), 300. + 3e-3 / 5.);
  EXPECT_EQ(heat::updated_temperature(300., 2., 1., 1e-3, 0.5, 0.), 300.);  // zero capacity: unchanged
}

TEST(HeatConduction, InitialTemperatureAsLiggghtsStoresIt)
{
  // measured on LIGGGHTS 3.8 (dump of f_Temp at %.17g after 'initial_temperature T0')
  EXPECT_EQ(heat::liggghts_initial_temperature(300.123456789), 300.1235);
  EXPECT_EQ(heat::liggghts_initial_temperature(12345.6789123), 12345.68);
  EXPECT_EQ(heat::liggghts_initial_temperature(0.000123456), 0.000123);
  EXPECT_EQ(heat::liggghts_initial_temperature(98765432.1), 98765430.);
  EXPECT_EQ(heat::liggghts_initial_temperature(999.99995), 1000.);
  EXPECT_EQ(heat::liggghts_initial_temperature(273.15), 273.15);
}

TEST(TimestepEstimates, RayleighAndHertzClosedForms)
{
  const double r = 0.004, rho = 2500., Y = 5e7, nu = 0.3;
  const double G = Y / 2.6;
  EXPECT_NEAR(gran::rayleigh_time(r, rho, Y, nu), M_PI * r * std::sqrt(rho / G) / (0.1631 * nu + 0.8766), 1e-15);
  const double Yeff = gran::effective_modulus(Y, nu, Y, nu);
  EXPECT_NEAR(Yeff, Y / (2 * (1 - nu * nu)), 1e-9 * Y);
  const double m = 4. / 3. * M_PI * r * r * r * rho, v = 1.5;
  EXPECT_NEAR(gran::hertz_time(r, rho, Yeff, v), 2.87 * std::pow(m * m / (r / 2 * Yeff * Yeff * v), 0.2), 1e-15);
  EXPECT_NEAR(gran::sphere_density(m, r), rho, 1e-12 * rho);
  EXPECT_EQ(gran::relative_speed(1.0, 0.5), 2.0);
  EXPECT_EQ(gran::relative_speed(1.0, 3.0), 4.0);
}
