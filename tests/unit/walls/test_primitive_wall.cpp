#include "primitive_wall.h"

#include <cmath>
#include <gtest/gtest.h>

using dembridge::walls::PrimitiveWall;

TEST(PrimitiveWall, PlaneIsTwoSided)
{
  PrimitiveWall w;
  w.axis = 2;
  w.pos = 0.01;
  double d, delta[3];
  const double above[3] = {1, 2, 0.013};
  ASSERT_TRUE(w.distance(above, 0.004, d, delta));
  EXPECT_NEAR(d, -0.001, 1e-15);
  EXPECT_EQ(delta[0], 0.0);
  EXPECT_NEAR(delta[2], -0.003, 1e-15);
  const double below[3] = {0, 0, 0.008};
  ASSERT_TRUE(w.distance(below, 0.004, d, delta));
  EXPECT_NEAR(d, -0.002, 1e-15);
  EXPECT_NEAR(delta[2], 0.002, 1e-15);
}

TEST(PrimitiveWall, CylinderInsideOutsideAndAxes)
{
  PrimitiveWall w;
  w.shape = PrimitiveWall::Shape::Cylinder;
  w.axis = 0;  // x axis through (y, z) = (1, 2)
  w.radius = 1.0;
  w.c1 = 1.0;
  w.c2 = 2.0;
  double d, delta[3];
  const double inside[3] = {5, 1.0, 2.9};  // 0.9 from the axis
  ASSERT_TRUE(w.distance(inside, 0.2, d, delta));
  EXPECT_NEAR(d, 1.0 - 0.9 - 0.2, 1e-14);
  EXPECT_NEAR(delta[2], 0.1, 1e-14);  // the wall is further out along +z
  EXPECT_EQ(delta[0], 0.0);
  const double outside[3] = {5, 1.0 + 3.0, 2.0};
  ASSERT_TRUE(w.distance(outside, 0.5, d, delta));
  EXPECT_NEAR(d, 3.0 - 1.0 - 0.5, 1e-14);
  EXPECT_NEAR(delta[1], -2.0, 1e-14);
  const double on_axis[3] = {0, 1.0, 2.0};
  EXPECT_FALSE(w.distance(on_axis, 0.5, d, delta));
}

TEST(PrimitiveWall, ShearVelocity)
{
  PrimitiveWall plane;
  double v[3];
  const double x[3] = {0.3, 0.4, 0.0};
  plane.shear_velocity(x, 0, 2.0, v);
  EXPECT_EQ(v[0], 2.0);
  EXPECT_EQ(v[1], 0.0);
  PrimitiveWall cyl;
  cyl.shape = PrimitiveWall::Shape::Cylinder;
  cyl.axis = 2;
  cyl.radius = 1.0;
  cyl.shear_velocity(x, 0, 2.0, v);  // spinning about z at 2 rad/s: ω × r
  EXPECT_NEAR(v[0], -0.8, 1e-15);
  EXPECT_NEAR(v[1], 0.6, 1e-15);
  EXPECT_EQ(v[2], 0.0);
}

TEST(PrimitiveWall, CentreOnTheWallHasNoNormal)
{
  PrimitiveWall w;
  w.pos = 0.004;
  double d, delta[3];
  const double on[3] = {0.001, 0.002, 0.004};
  ASSERT_TRUE(w.distance(on, 0.005, d, delta));
  EXPECT_TRUE(dembridge::walls::normal_undefined(delta, 0.005));  // Δ = 0: LIGGGHTS divides 0 by 0
  const double near[3] = {0.001, 0.002, 0.004 + 1e-13};          // 2e-11 of the radius away: defined
  ASSERT_TRUE(w.distance(near, 0.005, d, delta));
  EXPECT_FALSE(dembridge::walls::normal_undefined(delta, 0.005));
  const double nan_delta[3] = {std::nan(""), 0.0, 0.0};
  EXPECT_TRUE(dembridge::walls::normal_undefined(nan_delta, 0.005));
  EXPECT_EQ(w.describe(), "zplane at 0.0040000000000000001");
  w.shape = PrimitiveWall::Shape::Cylinder;
  w.axis = 0;
  w.radius = 0.04;
  EXPECT_EQ(w.describe(), "xcylinder of radius 0.040000000000000001 about (0, 0)");
}
