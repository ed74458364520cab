"""Deck lines shared by the mesh coupling tests: one particle type with the LIGGGHTS Hooke law
(restitution 0.5, friction 0.4, characteristic velocity 1)."""
HOOKE_ONE_TYPE = """fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
fix m5 all property/global characteristicVelocity scalar 1.0
pair_style gran model hooke tangential history
pair_coeff * *"""
