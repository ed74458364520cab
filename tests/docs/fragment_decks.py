"""Decks around the documented deck fragments (doc_blocks.fragments): a prologue that sets up what a
fragment's lines refer to, small and fast, and the commands of a fragment for its `lines` mode."""
import os
import re

def granular(ntypes):
    """Three spheres of `ntypes` types at rest on each other's surface, the materials of every pair style
    and wall model (property/global), gran/hooke/history, nve/sphere."""
    per_type = " ".join(["5.e7"] * ntypes), " ".join(["0.3"] * ntypes)
    pairs = lambda v: f"{ntypes} " + " ".join([v] * ntypes * ntypes)
    return f"""units si
atom_style sphere
atom_modify map array
boundary f f f
newton off
comm_modify vel yes
region box block -0.05 0.05 -0.05 0.05 -0.05 0.05 units box
create_box {ntypes} box
create_atoms 1 single -0.0025 0 0.002 units box
create_atoms {ntypes} single 0.0025 0 0.002 units box
create_atoms 1 single 0 0.01 0.002 units box
set group all diameter 0.005
set group all density 2500
velocity all set 0.1 0 -0.2 units box
region halfbed block -0.05 0 INF INF INF INF units box
fix m1 all property/global youngsModulus peratomtype {per_type[0]}
fix m2 all property/global poissonsRatio peratomtype {per_type[1]}
fix m3 all property/global coefficientRestitution peratomtypepair {pairs("0.7")}
fix m4 all property/global coefficientFriction peratomtypepair {pairs("0.3")}
fix m5 all property/global characteristicVelocity scalar 1.0
fix m6 all property/global coefficientRollingFriction peratomtypepair {pairs("0.1")}
fix m8 all property/global coefficientRollingViscousDamping peratomtypepair {pairs("0.1")}
fix m7 all property/global cohesionEnergyDensity peratomtypepair {pairs("1e4")}
fix k1 all property/global kn peratomtypepair {pairs("2e5")}
fix k2 all property/global kt peratomtypepair {pairs("1e5")}
fix k3 all property/global gamman_abs peratomtypepair {pairs("1.0")}
fix k4 all property/global gammat_abs peratomtypepair {pairs("0.5")}
pair_style gran/hooke/history
pair_coeff * *
neighbor 0.001 bin
fix integrate all nve/sphere
timestep 1e-6
"""


# a mesh named cad and a wall fix on it, for lines that refer to them
MESH = """fix cad all mesh/surface file cad.stl type 1
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes cad
"""

PROLOGUES = {"granular": granular(1), "granular-2types": granular(2), "granular-2types-mesh": granular(2) + MESH}
EPILOGUE = "run 5\n"

_SQUARE = """solid square
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 -0.02 0
vertex 0.02 0.02 0
endloop
endfacet
facet normal 0 0 1
outer loop
vertex -0.02 -0.02 0
vertex 0.02 0.02 0
vertex -0.02 0.02 0
endloop
endfacet
endsolid square
"""


def commands(body):
    """The commands of a fragment: continuation lines (&) joined, blank and comment-only lines left out."""
    out, cur = [], ""
    for line in body.splitlines():
        cur = cur + " " + line.strip() if cur else line.rstrip()
        if cur.rstrip().endswith("&"):
            cur = cur.rstrip()[:-1].rstrip()
            continue
        if cur.strip() and not cur.strip().startswith("#"):
            out.append(cur.strip())
        cur = ""
    return out


def prepare(workdir, text):
    """Files the deck reads (every `file NAME.stl`, a 4 cm square at z = 0) and folders it writes to."""
    for name in set(re.findall(r"\bfile\s+(\S+\.stl)\b", text)) | {"cad.stl"}:
        with open(os.path.join(workdir, name), "w") as fh:
            fh.write(_SQUARE)
    for path in re.findall(r"\s(\S+)/\S*\*", text):  # dump ... post/mesh_*.vtk
        os.makedirs(os.path.join(workdir, path), exist_ok=True)


def decks(how, prologue, body):
    """(label, deck text) of the runs of one fragment ('deck' or 'lines:N', N runs in the deck): the block after the prologue, or (lines) each command
    after its own prologue, one LAMMPS process for them all (`clear` in between; the plugin stays loaded)."""
    head = PROLOGUES[prologue]
    if how == "deck":
        return [("deck", head + body + "\n" + EPILOGUE)]
    # a pair_style line on its own gets the pair_coeff every granular style takes
    runs = [head + cmd + "\n" + ("pair_coeff * *\n" if cmd.startswith("pair_style") else "") + EPILOGUE
            for cmd in commands(body)]
    return [(f"lines:{len(runs)}", "clear\n".join(runs))]
