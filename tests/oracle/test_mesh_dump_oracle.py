"""dump mesh/stl and dump mesh/vtk against LIGGGHTS 3.8: the deck mesh_dump_rotating (a stress
plate turning under four spheres, a paddle turning above them, 2000 steps, output every 500) runs
in /usr/bin/liggghts and, with only the harness's atom_style/communicate conversion, in LAMMPS +
plugin on 1 and 2 ranks. Its dump lines are unchanged: `mesh/stl` without mesh IDs (all meshes),
with one, and `binary`, `mesh/vtk` with every keyword we support on the plate, and `vel` on all
meshes.

Compared per frame: the triangles (STL: normal and vertices; VTK: the vertices of every cell) to
the digits LIGGGHTS prints (%g, 6 significant: 1e-5 relative), and every VTK cell array that both
files have (both must have the same names) to 1e-8 of the array's largest magnitude (LIGGGHTS
prints about 11 digits; the forces themselves, printed with every digit, are bit-identical:
tests/oracle/test_mesh_stress_oracle.py).

One LIGGGHTS quirk is not reproduced: LIGGGHTS computes normal_stress_average and
shear_stress_average in final_integrate only, so at the first setup (step 0) it writes zeros. We
write the stresses of the setup forces; at step 0 they are checked against LIGGGHTS's own
`stress` (F/A) and STL normals n: |S.n| and |S - (S.n)n|, to the 6 digits of the normals."""
import struct
from pathlib import Path

import numpy as np
import pytest

import oracle_harness as oh

pytestmark = pytest.mark.two_cores  # 2 ranks against a LIGGGHTS run that both cases share

ROOT = Path(__file__).resolve().parent.parent
CASE = ROOT / "data" / "liggghts-walls" / "mesh_dump_rotating"
STEPS = range(0, 2001, 500)
VERTEX_RTOL = 1e-5
CELL_RTOL = 1e-8
SETUP_ZERO = ("normal_stress_average", "shear_stress_average")


def read_stl(path):
    """[(normal, (v1, v2, v3))] of every facet of every solid, in file order"""
    facets, normal, verts = [], None, []
    for line in Path(path).read_text().splitlines():
        t = line.split()
        if t[:2] == ["facet", "normal"]:
            normal, verts = [float(c) for c in t[2:5]], []
        elif t[:1] == ["vertex"]:
            verts.append([float(c) for c in t[1:4]])
        elif t[:1] == ["endfacet"]:
            facets.append((normal, verts))
    return facets


def read_stl_binary(path):
    """(n, 12) float32 rows of a binary STL: normal, then the 3 vertices"""
    data = Path(path).read_bytes()
    (n,) = struct.unpack_from("<I", data, 80)
    assert len(data) == 84 + 50 * n
    return np.array([struct.unpack_from("<12f", data, 84 + 50 * k) for k in range(n)])


def read_vtk(path):
    """ASCII polydata, legacy 2.0 (ours) or 5.1 (LIGGGHTS's VTK library): {'triangles': (n,3,3),
    'cells': {name: (n, ncomp)}}"""
    tok = Path(path).read_text().split()
    i = tok.index("POINTS")
    npts = int(tok[i + 1])
    pts = np.array(tok[i + 3:i + 3 + 3 * npts], float).reshape(npts, 3)
    i = tok.index("POLYGONS")
    ncell = int(tok[i + 1])
    if "CONNECTIVITY" in tok:  # 5.1: OFFSETS ... CONNECTIVITY ...
        ncell -= 1
        j = tok.index("CONNECTIVITY")
        conn = np.array(tok[j + 2:j + 2 + 3 * ncell], int).reshape(ncell, 3)
    else:  # 2.0: one "3 a b c" per cell
        conn = np.array(tok[i + 3:i + 3 + 4 * ncell], int).reshape(ncell, 4)[:, 1:]
    cells = {}
    if "CELL_DATA" in tok:
        j = tok.index("CELL_DATA") + 2
        end = tok.index("POINT_DATA") if "POINT_DATA" in tok else len(tok)
        while j < end:
            w = tok[j]
            if w == "FIELD":
                j += 3
            elif w == "SCALARS":
                cells[tok[j + 1]] = np.array(tok[j + 6:j + 6 + ncell], float).reshape(ncell, 1)
                j += 6 + ncell
            elif w in ("VECTORS", "NORMALS"):
                cells[tok[j + 1]] = np.array(tok[j + 3:j + 3 + 3 * ncell], float).reshape(ncell, 3)
                j += 3 + 3 * ncell
            else:  # FIELD array: name ncomp ntuples type values
                nc = int(tok[j + 1])
                cells[w] = np.array(tok[j + 4:j + 4 + nc * ncell], float).reshape(ncell, nc)
                j += 4 + nc * ncell
    return {"triangles": pts[conn], "cells": cells}


def close(got, ref, rtol, atol):
    got, ref = np.asarray(got, float), np.asarray(ref, float)
    assert got.shape == ref.shape, (got.shape, ref.shape)
    bad = np.abs(got - ref) > rtol * np.abs(ref) + atol
    assert not bad.any(), f"{bad.sum()} values differ, worst |d| {np.abs(got - ref).max():.3e}"


@pytest.fixture(scope="module")
def liggghts_out(tmp_path_factory):
    wd = tmp_path_factory.mktemp("liggghts")
    oh.run_liggghts(CASE, wd)
    return wd


@pytest.mark.liggghts
@pytest.mark.parametrize("nprocs", [1, 2])
def test_mesh_dump_lines_write_liggghts_triangles_and_cell_data(plugin, liggghts_out, tmp_path, nprocs):
    deck = oh.liggghts_to_lammps_deck((CASE / "in.liggghts").read_text(), plugin_path=plugin, syntax="3x")
    oh.run_lammps(deck, tmp_path, nprocs=nprocs,
                  files=[CASE / "data.txt", CASE / "plate.stl", CASE / "paddle.stl"])
    ref_dir, got_dir = liggghts_out, tmp_path
    for step in STEPS:
        for name, ntri in (("all", 4), ("pad", 2)):
            ref, got = read_stl(ref_dir / f"{name}{step}.stl"), read_stl(got_dir / f"{name}{step}.stl")
            assert len(ref) == ntri and len(got) == ntri, (name, step, len(ref), len(got))
            close([f[1] for f in got], [f[1] for f in ref], VERTEX_RTOL, 1e-15)
            close([f[0] for f in got], [f[0] for f in ref], VERTEX_RTOL, 1e-6)
        ref, got = read_stl_binary(ref_dir / f"bin{step}.stl"), read_stl_binary(got_dir / f"bin{step}.stl")
        assert ref.shape == (4, 12)
        close(got, ref, 1e-6, 1e-12)  # float32 of the same doubles, up to their round-off
        for name, ntri in (("plate", 2), ("both", 4)):
            ref, got = read_vtk(ref_dir / f"{name}{step}.vtk"), read_vtk(got_dir / f"{name}{step}.vtk")
            assert ref["triangles"].shape == (ntri, 3, 3)
            close(got["triangles"], ref["triangles"], VERTEX_RTOL, 1e-15)
            assert sorted(got["cells"]) == sorted(ref["cells"]), (name, step)
            for key, r in ref["cells"].items():
                if step == 0 and key in SETUP_ZERO:
                    assert not r.any()  # the quirk: nothing computed yet
                    continue
                close(got["cells"][key], r, 0.0, CELL_RTOL * max(np.abs(r).max(), 1e-300))
        # step 0: the stresses from LIGGGHTS's F/A and normals of the plate (first two facets)
        if step == 0:
            s = read_vtk(ref_dir / "plate0.vtk")["cells"]["stress"]
            n = np.array([f[0] for f in read_stl(ref_dir / "all0.stl")[:2]])
            sn = np.einsum("ij,ij->i", s, n)
            cells = read_vtk(got_dir / "plate0.vtk")["cells"]
            scale = np.abs(s).max()
            close(cells["normal_stress_average"][:, 0], np.abs(sn), 0.0, 1e-5 * scale)
            close(cells["shear_stress_average"][:, 0], np.linalg.norm(s - sn[:, None] * n, axis=1), 0.0, 1e-5 * scale)
            assert np.abs(sn).max() > 1.0
    # the run is not trivial: both meshes moved, the plate carries the spheres
    first, last = read_stl(ref_dir / "all0.stl"), read_stl(ref_dir / "all2000.stl")
    for k in (0, 2):
        assert np.abs(np.array(last[k][1]) - np.array(first[k][1])).max() > 1e-3
    plate = read_vtk(ref_dir / "plate2000.vtk")["cells"]
    assert plate["normal_stress_average"].max() > 1.0 and np.abs(plate["v"]).max() > 0.1
    assert sorted(plate) == ["active_corners", "active_edges", "area", "index", "meshid",
                             "normal_stress_average", "shear_stress_average", "stress", "v"]
