"""Bad input to fix particletemplate/sphere, particledistribution/discrete, insert/pack, insert/rate/region and
insert/stream: a LAMMPS
ERROR naming the command and the argument (LIGGGHTS 3.8's message where it has one). One fresh LAMMPS
instance per case, in-process."""
from pathlib import Path

import pytest

from dembridge import new_lammps

BASE = [
    "units si", "atom_style sphere", "boundary f f f",
    "region box block -0.05 0.05 -0.05 0.05 0 0.1 units box", "create_box 1 box", "timestep 1e-5",
    "region ins block -0.04 0.04 -0.04 0.04 0.01 0.09 units box",
    "fix g all gravity 9.81 vector 0 0 -1",
]
T1 = "fix pts1 all particletemplate/sphere 15485863 atom_type 1 density constant 2500 radius constant 0.005"
T2 = "fix pts2 all particletemplate/sphere 15485867 atom_type 1 density constant 2500 radius constant 0.008"
D = "fix pdd1 all particledistribution/discrete 32452843 2 pts1 0.3 pts2 0.7"
GEN = "fix ins all insert/pack seed 32452867 distributiontemplate pdd1 insert_every once overlapcheck yes all_in yes " \
      "vel constant 0 0 -0.5"
I = GEN + " region ins volumefraction_region 0.3"
GOOD = BASE + [T1, T2, D, I, "fix nve all nve/sphere", "run 1"]
RATE = "fix ins all insert/rate/region seed 32452867 distributiontemplate pdd1 nparticles 50 particlerate 1000 " \
       "insert_every 100 all_in yes region ins"

FACES = Path(__file__).resolve().parents[1] / "data" / "liggghts-insertion"
FACE = f"fix face all mesh/surface file {FACES / 'stream_face.stl'} type 1"
STREAM = "fix ins all insert/stream seed 32452867 distributiontemplate pdd1 nparticles 20 particlerate 1000 " \
         "vel constant 0 0 -1 insertion_face face extrude_length 0.03"

TPL = "Fix particletemplate/sphere (id pts1)"
PDD = "Fix particledistribution/discrete (id pdd1)"
INS = "Fix insert/pack (id ins)"
RATE_ID = "Fix insert/rate/region (id ins)"
STR = "Fix insert/stream (id ins)"


def swap(old, new, lines=GOOD):
    return [new if line == old else line for line in lines]


STREAM_GOOD = swap(I, FACE + "\n" + STREAM)
STREAM_GOOD = [x for line in STREAM_GOOD for x in line.split("\n")]
# a box that holds the whole extrusion volume (0.08 to 0.11), as LIGGGHTS 3.8 requires (at least 90 %)
STREAM_GOOD = swap("region box block -0.05 0.05 -0.05 0.05 0 0.1 units box",
                   "region box block -0.05 0.05 -0.05 0.05 0 0.12 units box", STREAM_GOOD)


def stream(old, new, lines=None):
    """The insert/stream deck with one change in the insert/stream line (or another line)."""
    lines = STREAM_GOOD if lines is None else lines
    out = swap(STREAM if old is None else old, STREAM.replace(*new) if old is None else new, lines)
    return [x for line in out for x in line.split("\n")]


CASES = {
    # fix particletemplate/sphere
    "template_radius_gaussian": (swap(T1, T1.replace("radius constant 0.005", "radius gaussian 0.005 0.001")),
                                 [TPL, "invalid radius random style 'gaussian'"]),
    "template_radius_uniform": (swap(T1, T1.replace("radius constant 0.005", "radius uniform 0.004 0.006")),
                                [TPL, "invalid radius random style"]),
    "template_density_gaussian": (swap(T1, T1.replace("density constant 2500", "density gaussian 2500 10")),
                                  [TPL, "invalid density random style"]),
    "template_seed_small_prime": (swap(T1, T1.replace("15485863", "7919")), [TPL, "seed 7919", "prime"]),
    "template_seed_1009": (swap(T1, T1.replace("15485863", "1009")), [TPL, "> 10000 and a prime"]),
    "template_seed_not_prime": (swap(T1, T1.replace("15485863", "15485864")), [TPL, "15485864"]),
    "template_seed_above_int_max": (swap(T1, T1.replace("15485863", "2147483659")), [TPL, "INT_MAX"]),
    "template_no_density": (swap(T1, T1.replace(" density constant 2500", "")), [TPL, "have to define 'density'"]),
    "template_no_radius": (swap(T1, T1.replace(" radius constant 0.005", "")), [TPL, "have to define 'radius'"]),
    "template_radius_zero": (swap(T1, T1.replace("constant 0.005", "constant 0")), [TPL, "radius must be > 0"]),
    "template_radius_text": (swap(T1, T1.replace("constant 0.005", "constant big")), [TPL, "'radius' expects a number"]),
    "template_unknown_keyword": (swap(T1, T1 + " volume_limit 1e-9"), [TPL, "unrecognized keyword 'volume_limit'"]),
    "template_atom_type_zero": (swap(T1, T1.replace("atom_type 1", "atom_type 0")), [TPL, "invalid atom type"]),
    "template_atom_type_too_large": (swap(T1, T1.replace("atom_type 1", "atom_type 3")), ["atom_type 3", "atom types"]),
    # fix particledistribution/discrete
    "distribution_unknown_template": (swap(D, D.replace("pts2 0.7", "pts9 0.7")),
                                      [PDD, "invalid ID for fix particletemplate provided: 'pts9'"]),
    "distribution_not_a_template": (swap(D, D.replace("pts2 0.7", "g 0.7")), [PDD, "fix g is not of type particletemplate"]),
    "distribution_count_mismatch": (swap(D, D.replace(" pts2 0.7", "")), [PDD, "does not match # of arguments"]),
    "distribution_negative_weight": (swap(D, D.replace("0.7", "-0.7")), [PDD, "invalid weight -0.7 of pts2"]),
    "distribution_weights_zero": (swap(D, D.replace("0.3", "0").replace("0.7", "0")), [PDD, "the weights sum to 0"]),
    "distribution_template_twice": (swap(D, D.replace("pts2 0.7", "pts1 0.7")), [PDD, "same template twice ('pts1')"]),
    "distribution_bad_seed": (swap(D, D.replace("32452843", "10007x")), [PDD, "not an integer"]),
    "distribution_no_templates": (swap(D, "fix pdd1 all particledistribution/discrete 32452843 0 pts1 1 pts2 1"),
                                  [PDD, "illegal number of templates 0"]),
    "distribution_numberbased_bad_weight": (swap(D, D.replace("discrete", "discrete/numberbased").replace("0.3", "x")),
                                            ["Fix particledistribution/discrete/numberbased (id pdd1)", "weight of pts1"]),
    # fix insert/pack
    "insert_no_distribution": (swap(I, I.replace(" distributiontemplate pdd1", "")),
                               [INS, "have to define a 'distributiontemplate'"]),
    "insert_unknown_distribution": (swap(I, I.replace("distributiontemplate pdd1", "distributiontemplate pts1")),
                                    [INS, "particledistribution/discrete: 'pts1' is not one"]),
    "insert_unknown_region": (swap(I, I.replace("region ins", "region nowhere")), [INS, "region ID 'nowhere' does not exist"]),
    "insert_no_region": (swap(I, I.replace(" region ins", "")), [INS, "must define an insertion region"]),
    "insert_two_targets": (swap(I, I + " particles_in_region 10"), [INS, "exactly one keyword out of 'volumefraction_region'"]),
    "insert_no_target": (swap(I, I.replace(" volumefraction_region 0.3", "")), [INS, "exactly one keyword"]),
    "insert_volumefraction_above_1": (swap(I, I.replace("0.3", "1.5")), [INS, "Invalid volumefraction 1.5"]),
    "insert_particles_zero": (swap(I, I.replace("volumefraction_region 0.3", "particles_in_region 0")),
                              [INS, "'particles_in_region' > 0 required"]),
    "insert_mass_negative": (swap(I, I.replace("volumefraction_region 0.3", "mass_in_region -1")),
                             [INS, "'mass_in_region' > 0 required"]),
    "insert_ntry_mc_small": (swap(I, I + " ntry_mc 500"), [INS, "ntry_mc must be > 1000, got 500"]),
    "insert_keyword_order": (swap(I, GEN.replace(" all_in yes", "") + " region ins volumefraction_region 0.3 all_in yes"),
                             [INS, "unknown keyword 'all_in' at this place", "before region"]),
    "insert_unknown_keyword": (swap(I, I + " foo 1"), [INS, "unknown keyword 'foo'"]),
    "insert_seed_equals_distribution": (swap(I, I.replace("seed 32452867", "seed 32452843")), [INS, "are different"]),
    "insert_seed_equals_template": (swap(I, I.replace("seed 32452867", "seed 15485863")), [INS, "are different"]),
    "insert_seed_not_prime": (swap(I, I.replace("seed 32452867", "seed 32452868")), [INS, "seed 32452868", "prime"]),
    "insert_no_seed_keyword": (swap(I, I.replace("seed 32452867 ", "")), [INS, "expecting keyword 'seed'"]),
    "insert_vel_style": (swap(I, I.replace("vel constant", "vel random")), [INS, "after keyword 'vel', got 'random'"]),
    "insert_vel_too_few": (swap(I, GEN.replace("vel constant 0 0 -0.5", "vel uniform 0 0 -0.5 0.1") +
                                " region ins volumefraction_region 0.3"), [INS, "'vel uniform' expects a number, got 'region'"]),
    "insert_omega_not_constant": (swap(I, GEN + " omega uniform 1 2 3 region ins volumefraction_region 0.3"),
                                  [INS, "expecting keyword 'constant' after keyword 'omega'"]),
    "insert_overlapcheck_value": (swap(I, I.replace("overlapcheck yes", "overlapcheck maybe")),
                                  [INS, "'overlapcheck' expects 'yes' or 'no', got 'maybe'"]),
    "insert_no_insert_every": (swap(I, I.replace(" insert_every once", "")), [INS, "must define 'insert_every'"]),
    "insert_nparticles_not_allowed": (swap(I, GEN + " nparticles 10 region ins volumefraction_region 0.3"),
                                      [INS, "specifying 'nparticles' or 'mass' not allowed"]),
    "insert_rate_with_once": (swap(I, GEN + " particlerate 10 region ins volumefraction_region 0.3"),
                              [INS, "must not define 'particlerate' or 'massrate'"]),
    "insert_region_smaller_than_particle": (
        swap(I, I.replace("region ins", "region tiny"), GOOD[:7] + ["region tiny block 0 0.01 0 0.01 0.02 0.03 units box"] +
             GOOD[7:]), [INS, "region 'tiny' - region too small", "0.008"]),
    "insert_maxattempt_zero": (swap(I, I.replace("insert_every once", "maxattempt 0 insert_every once")),
                               [INS, "'maxattempt' must be >= 1"]),
    "insert_start_in_the_past": (swap(I, I.replace("insert_every once", "start 0 insert_every once")),
                                 [INS, "'start' step can not be before current step"]),
    "insert_orientation_refused": (swap(I, GEN + " orientation random region ins volumefraction_region 0.3"),
                                   [INS, "keyword 'orientation' is not supported", "remove it"]),
    "insert_set_property_unknown": (swap(I, GEN + " set_property tracer 2 region ins volumefraction_region 0.3"),
                                    [INS, "set_property", "'tracer' is not a scalar fix property/atom"]),
    "insert_set_property_value": (swap(I, GEN + " set_property tracer hot region ins volumefraction_region 0.3"),
                                  [INS, "set_property", "'hot'"]),
    "insert_set_property_short": (swap(I, GEN + " set_property tracer"),
                                  [INS, "'set_property' expects a fix property/atom name and a value"]),
    "insert_dynamic_region": (swap(I, I.replace("region ins", "region mov"), GOOD[:7] + [
        "variable vz equal 0.1*time", "region mov block -0.04 0.04 -0.04 0.04 0.01 0.05 move NULL NULL v_vz units box"] +
        GOOD[7:]), [INS, "dynamic regions are not allowed ('mov')"]),
    "insert_region_outside_box": (swap(I, I.replace("region ins", "region out"), GOOD[:7] + [
        "region out block 1 2 1 2 1 2 units box"] + GOOD[7:]), [INS, "Unable to calculate the volume of region 'out'"]),
    "rate_once_not_allowed": (swap(I, RATE.replace("insert_every 100", "insert_every once")),
                              [RATE_ID, "must not define 'particlerate' or 'massrate' for 'insert_every' = once"]),
    "rate_no_total": (swap(I, RATE.replace("nparticles 50 ", "")), [RATE_ID, "must define either 'nparticles' or 'mass'"]),
    "rate_no_rate": (swap(I, RATE.replace("particlerate 1000 ", "")), [RATE_ID, "must define either 'massrate' or 'particlerate'"]),
    "rate_with_pack_target": (swap(I, RATE + " volumefraction_region 0.3"), [RATE_ID, "belong to insert/pack"]),
    "rate_nparticles_and_mass": (swap(I, RATE.replace("nparticles 50", "nparticles 50 mass 0.1")),
                                 [RATE_ID, "must not define both 'nparticles' and 'mass'"]),
    "insert_atom_style_atomic": (swap("atom_style sphere", "atom_style atomic")[:5] + ["mass 1 1.0"] +
                                 swap("fix nve all nve/sphere", "fix nve all nve")[5:],
                                 [INS, "requires atom attributes radius, rmass, omega"]),
    # fix insert/stream
    "stream_every_and_extrude": (stream(None, ("vel constant", "insert_every 100 vel constant")),
                                 [STR, "must not provide both 'insert_every' and 'extrude_length'"]),
    "stream_neither_every_nor_extrude": (stream(None, (" extrude_length 0.03", "")),
                                         [STR, "must define either 'insert_every' or 'extrude_length'"]),
    "stream_nparticles_and_mass": (stream(None, ("nparticles 20", "nparticles 20 mass 0.1")),
                                   [STR, "must not define both 'nparticles' and 'mass'"]),
    "stream_nparticles_inf": (stream(None, ("nparticles 20", "nparticles INF")), [STR, "does not accept INF"]),
    "stream_no_rate": (stream(None, ("particlerate 1000 ", "")), [STR, "must define either 'massrate' or 'particlerate'"]),
    "stream_all_in_needs_planar": (stream(None, ("vel constant", "all_in yes vel constant")),
                                   [STR, "all_in yes requires you to use a fix mesh/surface/planar", "fix face"]),
    "stream_velocity_in_face_plane": (stream(None, ("vel constant 0 0 -1", "vel constant 1 0 0")),
                                      [STR, "insertion velocity projected on face normal is < 1e-3"]),
    "stream_extrude_too_small": (stream(None, ("extrude_length 0.03", "extrude_length 0.01")),
                                 [STR, "'extrude_length' is too small", "0.008"]),
    "stream_every_too_short": (stream(None, ("vel constant 0 0 -1 insertion_face face extrude_length 0.03",
                                             "insert_every 10 vel constant 0 0 -1 insertion_face face")),
                               [STR, "'insert_every' or 'vel' is too small"]),
    "stream_keyword_order": (stream(None, ("vel constant 0 0 -1 insertion_face face",
                                           "insertion_face face vel constant 0 0 -1")),
                             [STR, "wrong keyword order", "'vel'"]),
    "stream_no_face": (stream(None, ("insertion_face face ", "")), [STR, "must define an insertion face"]),
    "stream_face_not_a_mesh": (stream(None, ("insertion_face face", "insertion_face g")),
                               [STR, "insertion_face", "fix 'g' is a fix gravity, not a mesh"]),
    "stream_face_unknown": (stream(None, ("insertion_face face", "insertion_face nope")),
                            [STR, "mesh ID 'nope' does not exist"]),
    "stream_face_not_planar": (stream(FACE, FACE.replace("stream_face.stl", "bent_face.stl")),
                               [STR, "requires a planar face for insertion", "triangle 2"]),
    "stream_insert_every_once": (stream(None, ("vel constant", "insert_every once vel constant")),
                                 [STR, "must not define 'particlerate' or 'massrate' for 'insert_every' = once"]),
    "stream_parallel_word": (stream(None, ("extrude_length 0.03", "extrude_length 0.03 parallel maybe")),
                             [STR, "'parallel'", "'maybe'"]),
    "stream_extrusion_outside_box": (stream("region box block -0.05 0.05 -0.05 0.05 0 0.12 units box",
                                            "region box block -0.05 0.05 -0.05 0.05 0 0.1 units box"),
                                     [STR, "insertion volume could not be distributed properly",
                                      "of the extrusion volume is inside the box, needs 0.9 to 1.1"]),
    "stream_duration_with_extrude": (stream(None, ("extrude_length 0.03", "extrude_length 0.03 duration 10")),
                                     [STR, "must not provide both 'extrude_length' and 'duration'"]),
    "stream_moving_face": (stream("fix nve all nve/sphere", "fix mv all move/mesh mesh face linear 0 0 0.1\n"
                                  "fix nve all nve/sphere"),
                           [STR, "cannot translate, rotate, scale mesh which is used for particle insertion"]),
    "stream_seed_shared": (stream(None, ("seed 32452867", "seed 32452843")), [STR, "seeds", "are different"]),
}


def run_lines(lines):
    lmp = new_lammps()
    try:
        for line in lines:
            lmp.command(line)
        return None
    except Exception as e:  # the lammps module raises Exception with the ERROR text
        return str(e)
    finally:
        lmp.close()


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_insertion_input_gives_error(name):
    lines, expected = CASES[name]
    assert lines != GOOD, "the case does not change the deck"
    msg = run_lines(lines)
    assert msg is not None, f"{name}: no ERROR"
    for e in expected:
        assert e in msg, f"{name}: {e!r} not in {msg!r}"


def test_good_insertion_deck_runs():
    assert run_lines(GOOD) is None
    assert run_lines(swap(I, RATE)) is None
    assert run_lines(STREAM_GOOD) is None
