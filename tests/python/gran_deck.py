"""Deck lines shared by the mesh coupling tests: the head of a granular deck (the plugin loaded from the
`plugin` variable, SI units, spheres, a fixed box) and one particle type with the LIGGGHTS Hooke law
(restitution 0.5, friction 0.4, characteristic velocity 1)."""
GRAN_HEAD = """plugin load ${plugin}
units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes"""
HOOKE_ONE_TYPE = """fix m1 all property/global youngsModulus peratomtype 5.e6
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.4
fix m5 all property/global characteristicVelocity scalar 1.0
pair_style gran model hooke tangential history
pair_coeff * *"""
