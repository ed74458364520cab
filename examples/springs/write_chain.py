"""Writes the definitions file of a hanging chain for fix parmec/spring (doc/fix_parmec_spring.md):
n atoms along x (spacing 1), neighbour springs with a dashpot, next-neighbour springs with an
unload curve and yield limits (hysteresis), the first atom hung from a point in space.
Usage: python write_chain.py [n] [file]   (defaults: 40 chain.springs)"""
import sys


def write_chain(path, n=40):
    with open(path, "w") as f:
        f.write("# tables: spring force vs stroke, dashpot force vs velocity, unload curve\n")
        f.write("table K -1 -1e5 1 1e5\n")
        f.write("table K2 -1 -2e4 0 0 0.5 1e4 1 3e4\n")
        f.write("table U -1 -2e5 1 2e5\n")
        f.write("table D -1 -50 1 50\n")
        f.write("spring 1 1 centre -1 -1 0 0 K dashpot D    # anchor in space\n")
        sid = 2
        for i in range(1, n):
            f.write(f"spring {sid} {i} centre {i + 1} centre K dashpot D\n")
            sid += 1
            if i + 2 <= n:
                f.write(f"spring {sid} {i} centre {i + 2} centre K2 unload U ylim -100 100\n")
                sid += 1
    return sid - 1


if __name__ == "__main__":
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    path = sys.argv[2] if len(sys.argv) > 2 else "chain.springs"
    print(f"{write_chain(path, n)} springs written to {path}")
