"""python -m dembridge.parmec [--parmec-quirks[=fixedQ1Q3]] [--workdir DIR] model.py [script arguments]

Runs a Parmec input script on LAMMPS + dembridge (doc/parmec_front_end.md).

options:
  --parmec-quirks            upstream Parmec's behaviour, every quirk (default: corrected)
  --parmec-quirks=fixedQ1Q3  every quirk but Q1 and Q3 (the oracle's second Parmec build)
  --workdir DIR              keep the generated LAMMPS inputs and dumps in DIR (default: a temporary folder)
  -h, --help                 print this help and exit"""
import sys

from . import ParmecError, run_script


def main(argv):
    quirks, workdir = False, None
    while argv and argv[0].startswith("-"):
        opt = argv.pop(0)
        if opt in ("-h", "--help"):
            print(__doc__)
            return 0
        if opt == "--parmec-quirks":
            quirks = True
        elif opt == "--parmec-quirks=fixedQ1Q3":
            quirks = "fixedQ1Q3"
        elif opt == "--workdir" and argv:
            workdir = argv.pop(0)
        else:
            print(f"dembridge.parmec: unknown option {opt!r} (expected --parmec-quirks, --parmec-quirks=fixedQ1Q3, "
                  "--workdir DIR or --help)", file=sys.stderr)
            return 2
    if not argv:
        print("usage: python -m dembridge.parmec [--parmec-quirks] [--workdir DIR] model.py [args] (--help: more)",
              file=sys.stderr)
        return 2
    try:
        run_script(argv[0], argv[1:], quirks=quirks, workdir=workdir)
    except ParmecError as e:
        print(f"Parmec input error: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
