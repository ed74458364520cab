"""A test that says it is bit-identical (bitwise, bit for bit, bit-exact) in its name or docstring compares
with tolerance 0: no pytest.approx/allclose/isclose, no rtol/atol/tol argument other than 0, no
``x <= 1e-12``-style bound, no positional tolerance to the oracle harness's check_case/compare; in the C++
tests (name, or the // comment above TEST) no EXPECT_NEAR/ASSERT_NEAR/EXPECT_DOUBLE_EQ (4 ulp). A test
that meets a tolerance says so instead of claiming bit identity."""
import ast
import glob
import os
import re

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CLAIM = re.compile(r"bit[- ]?identical|bitwise|bit[- ]for[- ]bit|bit[- ]exact", re.I)
CLAIM_NAME = re.compile(r"bit_?identical|bitwise|bit_?for_?bit|bit_?exact", re.I)
TOL_KEYWORDS = {"rtol", "atol", "tol", "rel", "abs", "rel_tol", "abs_tol"}
CLOSE_CALLS = {"allclose", "isclose", "approx", "assert_allclose", "assert_array_almost_equal", "assert_almost_equal"}
TOL_POSITION = {"check_case": 1, "compare": 2}  # oracle_harness.check_case(case, rtol), compare(ref, test, rtol)


def source_files(ext):
    return sorted(p for p in glob.glob(os.path.join(ROOT, "tests", "**", f"*.{ext}"), recursive=True)
                  if os.sep + "data" + os.sep not in os.path.relpath(p, ROOT))


def numbers(node, consts):
    """The numbers a tolerance expression can take (module constants and dicts resolved), None if unknown."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return [node.value]
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        v = numbers(node.operand, consts)
        return v and [-x for x in v]
    if isinstance(node, ast.Name) and node.id in consts:
        return numbers(consts[node.id], consts)
    if isinstance(node, ast.Dict):
        vals = [numbers(x, consts) for x in node.values]
        return None if any(v is None for v in vals) else [x for v in vals for x in v]
    if isinstance(node, ast.Subscript):
        return numbers(node.value, consts)
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
        v = (numbers(node.left, consts) or []) + (numbers(node.right, consts) or [])
        return v or None
    return None


def tolerances(fn, consts):
    """(line, what) of every comparison with a tolerance > 0 in a test function."""
    out = []
    for n in ast.walk(fn):
        if isinstance(n, ast.Call):
            f = n.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if name in CLOSE_CALLS:
                out.append((n.lineno, name))
            for kw in n.keywords:
                v = numbers(kw.value, consts) if kw.arg in TOL_KEYWORDS else [0]
                if v is None or any(x != 0 for x in v):
                    out.append((n.lineno, f"{kw.arg}="))
            if name in TOL_POSITION and len(n.args) > TOL_POSITION[name]:
                v = numbers(n.args[TOL_POSITION[name]], consts)
                if v is None or any(x != 0 for x in v):
                    out.append((n.lineno, f"{name}(..., tolerance)"))
        elif isinstance(n, ast.Compare):
            for op, right in zip(n.ops, n.comparators):
                v = numbers(right, consts) if isinstance(op, (ast.Lt, ast.LtE)) else None
                if v and any(0 < abs(x) < 1e-3 for x in v):
                    out.append((n.lineno, "bound below 1e-3"))
    return out


def python_offenders():
    bad = []
    for path in source_files("py"):
        tree = ast.parse(open(path, encoding="utf-8").read())
        consts = {t.id: s.value for s in tree.body if isinstance(s, ast.Assign) for t in s.targets
                  if isinstance(t, ast.Name)}
        for fn in ast.walk(tree):
            if not (isinstance(fn, ast.FunctionDef) and fn.name.startswith("test")):
                continue
            if CLAIM_NAME.search(fn.name) or CLAIM.search(ast.get_docstring(fn) or ""):
                bad += [f"{os.path.relpath(path, ROOT)}:{line} {fn.name}: {what}" for line, what in tolerances(fn, consts)]
    return bad


CPP_TEST = re.compile(r"^\s*(?:TEST|TEST_F|TEST_P)\s*\(\s*\w+\s*,\s*(\w+)\s*\)", re.M)
CPP_NAME = re.compile(r"BitIdentical|Bitwise|BitForBit|BitExact", re.I)
CPP_TOLERANCE = re.compile(r"\b(?:EXPECT|ASSERT)_(?:NEAR|DOUBLE_EQ|FLOAT_EQ)\b")


def cpp_offenders():
    bad = []
    for path in source_files("cpp"):
        src = open(path, encoding="utf-8").read()
        lines = src.splitlines()
        starts = [(src.count("\n", 0, m.start()), m.group(1)) for m in CPP_TEST.finditer(src)]
        for k, (start, name) in enumerate(starts):
            end = starts[k + 1][0] if k + 1 < len(starts) else len(lines)
            doc, i = [], start - 1
            while i >= 0 and lines[i].strip().startswith("//"):
                doc.append(lines[i])
                i -= 1
            if CPP_NAME.search(name) or CLAIM.search("\n".join(doc)):
                bad += [f"{os.path.relpath(path, ROOT)}:{start + j + 1} {name}: {line.strip()}"
                        for j, line in enumerate(lines[start:end]) if CPP_TOLERANCE.search(line)]
    return bad


def test_bitwise_claims_compare_with_tolerance_zero():
    bad = python_offenders() + cpp_offenders()
    assert not bad, ("tests that claim bit identity but compare with a tolerance: assert ==, or say the "
                     "tolerance in the name/docstring instead of the claim\n" + "\n".join(bad))


def test_the_check_sees_a_tolerance(tmp_path):
    """The check itself finds each kind of tolerance (so that an empty list above means something)."""
    src = ('RTOL = {1: 1e-12, 2: 0.0}\n'
           'def test_a_bitwise():\n    assert abs(x - y) <= 1e-12 * s\n'
           'def test_b():\n    """bit-identical"""\n    rep = oh.check_case(c, rtol=RTOL[n])\n'
           'def test_c():\n    """bit for bit"""\n    assert x == pytest.approx(y)\n'
           'def test_d_bit_identical():\n    oh.compare(a, b, 1e-15)\n'
           'def test_e_bitwise():\n    oh.compare(a, b, 0.0); assert oh.check_case(c, rtol=0.0)\n')
    tree = ast.parse(src)
    consts = {t.id: s.value for s in tree.body if isinstance(s, ast.Assign) for t in s.targets}
    found = {fn.name: tolerances(fn, consts) for fn in tree.body if isinstance(fn, ast.FunctionDef)}
    assert [bool(found[k]) for k in sorted(found)] == [True, True, True, True, False]
