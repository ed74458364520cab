"""LIGGGHTS 3.8 deck -> LAMMPS deck: the few rewrites inside LAMMPS's own commands.

Everything a plugin can provide (``communicate``, ``fix particletemplate/sphere``, ``dump custom/vtk``,
...) is a style of the plugin and stays as written. What no plugin can change is the syntax of
LAMMPS's built-in commands; those lines are rewritten here, each rule reported once:

* ``atom_style granular`` -> ``atom_style sphere 1`` (radii may change, as with granular; also inside
  ``atom_style hybrid``);
* ``dump_modify ID ... format "..."`` -> ``format line "..."``;
* ``compute_modify ID ... dynamic yes`` -> ``dynamic/dof yes``, ``extra N`` -> ``extra/dof N``;
* ``set ... property/atom NAME V`` -> ``set ... d_NAME V`` (a vector property: ``d2_NAME[k] Vk``);
* ``region``, ``create_atoms``, ``displace_atoms``, ``velocity`` without a ``units`` keyword get
  ``units box``: LIGGGHTS's default, where LAMMPS's is ``units lattice``;
* ``set ... diameter D`` (no ``density`` after it) keeps each atom's density, as LIGGGHTS does (LAMMPS
  keeps the mass): the masses are scaled by (D/d)^3 first (a variable and a set ... mass before the line);
* ``thermo_style custom ... ke ...`` -> the column of the compute ``thermo_kin_eng`` (style ``ke``, defined
  once), headed ``KinEng``: LIGGGHTS's thermo ``ke`` is that compute, the sum of m v^2 / 2, where LAMMPS's is
  the temperature times dof k_B / 2 with the degrees of freedom counted at setup (0 atoms before an insertion).

``include FILE`` and ``jump FILE`` with a literal file name are translated the same way (the line
then names the translated copy); a file name holding a variable runs untranslated, and says so.
Lines keep their numbers and comments, so ``jump ... label`` and error messages still match.
"""
import dataclasses
import os
import re

RULES = {
    # no quotes in these texts: LAMMPS's print parses its text once more
    "atom_style": "atom_style granular -> atom_style sphere 1 (the same atom style in LAMMPS, radii may change)",
    "format": "dump_modify ... format STRING -> format line STRING (LAMMPS takes line, int or float first)",
    "dynamic": "compute_modify ... dynamic -> dynamic/dof (the LAMMPS keyword)",
    "extra": "compute_modify ... extra -> extra/dof (the LAMMPS keyword)",
    "property/atom": "set ... property/atom NAME V -> set ... d_NAME V (a LIGGGHTS per-atom property "
                     "is the LAMMPS custom property d_NAME)",
    "units": "region, create_atoms, displace_atoms and velocity take units box by default in LIGGGHTS and "
             "units lattice in LAMMPS: units box added where the command gives none",
    "diameter": "set ... diameter keeps the density in LIGGGHTS and the mass in LAMMPS: each atom's mass is "
                "scaled by (D/d)^3 before, which keeps its density",
    "ke": "thermo_style ... ke -> c_thermo_kin_eng headed KinEng: LIGGGHTS takes the kinetic energy from the "
          "compute ke, LAMMPS from the temperature and the degrees of freedom counted at setup",
    "include": "included files are translated too: the line names the translated copy",
    "variable_file": "a file name holding a variable is read as it is, without translation",
}

KIN_ENG_ID = "thermo_kin_eng"  # LIGGGHTS's own compute of the thermo ke
KIN_ENG_COLUMN = "c_" + KIN_ENG_ID
_UNITS_BOX = ("region", "create_atoms", "displace_atoms", "velocity")
_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


@dataclasses.dataclass
class Rewrite:
    rule: str      # key of RULES
    file: str
    line: int      # 1-based line of the command's first line


def split_words(text):
    """LAMMPS's word split: whitespace outside quotes; "...", '...' and triple quotes kept whole
    (quotes included). Returns (words, comment) where comment is the text from an unquoted '#'."""
    words, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if c.isspace():
            i += 1
            continue
        if c == "#":
            return words, text[i:]
        start = i
        while i < n and not text[i].isspace():
            if text.startswith('"""', i):
                end = text.find('"""', i + 3)
                i = n if end < 0 else end + 3
            elif text[i] in "\"'":
                end = text.find(text[i], i + 1)
                i = n if end < 0 else end + 1
            else:
                i += 1
        words.append(text[start:i])
    return words, ""


def _is_value(word):
    return bool(_NUMBER.match(word)) or word.startswith("v_") or word.startswith("$")


def rewrite_words(words):
    """The rewritten words of one command and the rules applied (empty: unchanged)."""
    if not words:
        return words, []
    cmd, out, rules = words[0], list(words), []
    if cmd in _UNITS_BOX and "units" not in out and not (cmd == "region" and out[-1:] == ["delete"]) \
            and len(out) > 2:
        out.append("units box")
        rules.append("units")
    if cmd == "atom_style" and "granular" in out[1:]:
        # 'sphere 1': radii may change (fix adapt), as they may with LIGGGHTS's granular
        out = [cmd] + [w2 for w in out[1:] for w2 in (["sphere", "1"] if w == "granular" else [w])]
        rules.append("atom_style")
    elif cmd == "dump_modify":
        k = 2
        while k < len(out):
            if out[k] == "format" and k + 1 < len(out) and out[k + 1] not in ("line", "int", "float", "none") \
                    and not out[k + 1].isdigit():
                out.insert(k + 1, "line")
                rules.append("format")
                k += 3
            else:
                k += 1
    elif cmd == "thermo_style" and out[1:2] == ["custom"] and "ke" in out[2:]:
        out = out[:2] + [KIN_ENG_COLUMN if w == "ke" else w for w in out[2:]]
        rules.append("ke")
    elif cmd == "compute_modify":
        for k in range(2, len(out)):
            if out[k] in ("dynamic", "extra") and k + 1 < len(out):
                rules.append(out[k])
                out[k] += "/dof"
    elif cmd == "set" and "property/atom" in out:
        k = out.index("property/atom")
        if k + 2 < len(out):
            name, vals, j = out[k + 1], [], k + 2
            while j < len(out) and _is_value(out[j]):
                vals.append(out[j])
                j += 1
            if vals:
                repl = [f"d_{name}", vals[0]] if len(vals) == 1 else \
                    [w for i, v in enumerate(vals) for w in (f"d2_{name}[{i + 1}]", v)]
                out = out[:k] + repl + out[j:]
                rules.append("property/atom")
    return out, rules


def keep_density(words):
    """The commands before and after ``set ... diameter D`` that keep each atom's density, as LIGGGHTS
    does: the mass is scaled by (D/d)^3 first, while the old diameter d is still there (None when not
    needed: no diameter, or a density after it)."""
    if not words or words[0] != "set" or "diameter" not in words:
        return None
    k = words.index("diameter")
    if k + 1 >= len(words) or "density" in words[k:]:
        return None
    d = words[k + 1]
    target = " ".join(words[1:3])
    return ([f"variable dembridge_mass atom mass*({d}/(2.0*radius))^3", f"set {target} mass v_dembridge_mass"],
            ["variable dembridge_mass delete"])


def kin_eng_column(words):
    """The commands before and after a thermo_style whose ke became the compute ke column: the compute
    (defined unless it is, so a loop may run the line again) and LIGGGHTS's column name."""
    if not words or words[0] != "thermo_style" or KIN_ENG_COLUMN not in words:
        return None
    return ([f'if "$(is_defined(compute,{KIN_ENG_ID})) == 0" then "compute {KIN_ENG_ID} all ke"'],
            [f"thermo_modify colname {KIN_ENG_COLUMN} KinEng"])


def _file_word(words):
    """The file argument of include / jump (None when the command reads no other file)."""
    if not words:
        return None
    if words[0] == "include" and len(words) >= 2:
        return 1
    if words[0] == "jump" and len(words) >= 2 and words[1] != "SELF":
        return 1
    return None


@dataclasses.dataclass
class Translation:
    text: str                 # the translated deck
    rewrites: list            # every Rewrite applied, in order
    children: dict            # absolute path of an included file -> Translation (only those that changed)


def translate_text(text, name, notes=True, resolve=None, seen=None):
    """Translate the deck ``text`` (``name`` is how messages call it). ``notes``: put a ``print`` of
    each rule's first use before the line (for a run); else a comment (for a kept deck).
    ``resolve(path, translation)`` returns the name the rewritten include line uses for a
    translated child file. ``seen``: rules already reported (shared with the included files)."""
    seen = set() if seen is None else seen
    lines = text.split("\n")
    out, rewrites, children = [], [], {}
    k = 0
    while k < len(lines):
        first = k
        logical = lines[k]
        group = [lines[k]]
        while logical.rstrip().endswith("&") and k + 1 < len(lines):
            k += 1
            logical = logical.rstrip()[:-1] + " " + lines[k]
            group.append(lines[k])
        k += 1
        words, comment = split_words(logical)
        new, rules = rewrite_words(words)
        fw = _file_word(new)
        if fw is not None:
            path = new[fw].strip("\"'")
            if "$" in path:
                rules.append("variable_file")
            elif os.path.isfile(path) and resolve is not None:
                child = translate_file(path, notes=notes, resolve=resolve, seen=seen)
                rewrites += child.rewrites
                if child.rewrites or child.children:
                    children[os.path.abspath(path)] = child
                    new = list(new)
                    new[fw] = resolve(path, child)
                    rules.append("include")
        around = keep_density(new)
        if around:
            rules.append("diameter")
        else:
            around = kin_eng_column(new)
        if not rules:
            out += group
            continue
        for r in rules:
            rewrites.append(Rewrite(r, name, first + 1))
        fresh = [r for r in dict.fromkeys(rules) if r not in seen]
        seen.update(fresh)
        for r in fresh:
            msg = f"dembridge-liggghts: {name} line {first + 1}: {RULES[r]}".replace('"', "").replace("'", "")
            out.append(f'print """{msg}"""' if notes else f"# {msg}")
        changed = " ".join(new) if new != words else logical.rstrip()
        if around:
            out += around[0]
        out.append(changed + ((" " + comment) if comment else ""))
        if around:
            out += around[1]
        # keep the line count: a continued command leaves empty lines behind (labels keep their lines)
        out += [""] * (len(group) - 1)
    return Translation("\n".join(out), rewrites, children)


def translate_file(path, notes=True, resolve=None, seen=None):
    with open(path) as fh:
        text = fh.read()
    return translate_text(text, path, notes=notes, resolve=resolve, seen=seen)
